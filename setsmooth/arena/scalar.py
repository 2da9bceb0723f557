"""Scalar systems with increasing dynamics, the class the interval filter and smoother are exact for.

Smoothing paper (27): x_{k+1} = η(x_k) + w_k with η continuous and strictly increasing, and the states
consistent with a measurement y_k an interval. Two kinds of problem in the zoo have that form:

* `MonotoneScalarSystem`, a `NonlinearSystem` that also states η, η⁻¹ and the measurement interval
  (the smoothing paper's nonlinear example (33)–(34));
* a scalar `LinearSystem` with constant A > 0: η(x) = A x, the known input B_k u_k folded into the
  process-noise interval E·⟦w_k⟧, and y_k = C x_k + D_k u_k + F v_k read row by row.

`monotone_scalar_form` gives both as the arguments of `interval_filter` and `interval_smoother`, and
refuses any other system with a message that says why.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..models.linear_system import LinearSystem
from ..models.nonlinear_system import NonlinearSystem
from ..sets.base import ConvexSet

__all__ = ["MonotoneScalarSystem", "MonotoneScalarForm", "monotone_scalar_form"]


class MonotoneScalarSystem(NonlinearSystem):
    """x_{k+1} = η(x_k) + w_k, y_k = g(k, x_k, v_k), with η increasing (smoothing paper (27)).

    A `NonlinearSystem` (so `simulate` runs it) that also states what the interval filter needs.

    Parameters
    ----------
    eta : callable float -> float
        η, continuous, strictly increasing, onto ℝ (vectorised: `simulate` passes arrays).
    g : callable (k, x, v) -> y
        The measurement function.
    measurement_interval : callable (k, y_k) -> (lo, hi)
        The states consistent with y_k for some v ∈ V, ⋃_v g_{k,v}⁻¹({y_k}) (smoothing paper (7), (34)).
    W, V : Box
        ⟦w_k⟧ (one-dimensional) and ⟦v_k⟧.
    eta_inverse : callable float -> float, optional
        η⁻¹ in closed form, for the smoother (inverted numerically without it).
    """

    def __init__(self, eta: Callable, g: Callable, measurement_interval: Callable, W: ConvexSet,
                 V: ConvexSet, eta_inverse: Callable | None = None):
        if not callable(eta) or not callable(measurement_interval):
            raise TypeError("eta and measurement_interval must be callables")
        super().__init__(self._step, g, W, V, n=1)
        if W.dim != 1:
            raise ValueError(f"W must be one-dimensional (x_{{k+1}} = η(x_k) + w_k), got dimension {W.dim}")
        self.eta, self.eta_inverse, self.measurement_interval = eta, eta_inverse, measurement_interval

    def _step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        return self.eta(x) + w


@dataclass(frozen=True)
class MonotoneScalarForm:
    """The arguments of `interval_filter` (and `interval_smoother`) for one system and data set."""

    eta: Callable[[float], float]
    eta_inverse: Callable[[float], float] | None
    w_intervals: np.ndarray        # (T, 2): ⟦w_k⟧ plus the known input, k = 0..T-1
    x0_interval: tuple[float, float]
    measurement_interval: Callable[[int, Any], tuple[float, float]]


def monotone_scalar_form(system: Any, X0: ConvexSet, ys: Any) -> MonotoneScalarForm:
    """``system`` as x_{k+1} = η(x_k) + w_k with its measurement intervals, over the data ``ys``.

    Raises
    ------
    ValueError
        When the system is not scalar with increasing dynamics: n ≠ 1, a time-varying A or C, A ≤ 0,
        C = 0, or a nonlinear system that does not state η (`MonotoneScalarSystem`).
    """
    T = len(ys) - 1
    hull = X0.interval_hull()
    x0 = (float(hull.lo[0]), float(hull.hi[0]))
    if isinstance(system, MonotoneScalarSystem):
        W = system.W.interval_hull()
        w = np.tile([W.lo[0], W.hi[0]], (T, 1))
        return MonotoneScalarForm(system.eta, system.eta_inverse, w, x0, system.measurement_interval)
    if not isinstance(system, LinearSystem):
        raise ValueError("the interval filter needs x_{k+1} = η(x_k) + w_k with η increasing: a scalar "
                         "LinearSystem with A > 0 or a MonotoneScalarSystem, got "
                         f"{type(system).__name__}")
    varying = {"A", "C"} & set(system.time_varying)
    if system.n != 1 or varying:
        raise ValueError("the interval filter needs a scalar system (n = 1) with constant A and C, got "
                         + (f"n = {system.n}" if system.n != 1 else f"time-varying {sorted(varying)}"))
    a, c = float(system.A_at(0)[0, 0]), system.C_at(0)[:, 0]
    if not a > 0:
        raise ValueError(f"the interval filter needs increasing dynamics η(x) = A x: A = {a:g} is not > 0")
    if not np.any(c != 0):
        raise ValueError("the interval filter needs C ≠ 0 (a measurement that sees the state)")
    w = np.array([_hull(system.process_noise_image(k)) + system.input_term(k)[0] for k in range(T)])
    w = w.reshape(T, 2)
    steps = T + 1 if "F" in system.time_varying else 1
    noise = [_rows(system.measurement_noise_image(k)) for k in range(steps)]

    def measurement_interval(k: int, y: Any) -> tuple[float, float]:
        # C x ∈ y − D u + F(−V), row by row: each row with c_i ≠ 0 bounds x; the intersection
        # is the consistent interval when F V is a box (one row: always), an outer bound otherwise.
        lo_r, hi_r = noise[min(k, len(noise) - 1)]
        r = np.asarray(y, dtype=float).reshape(-1) - system.feedthrough_term(k)
        lo_r, hi_r = r + lo_r, r + hi_r
        seen = c != 0
        ends = np.stack([lo_r[seen] / c[seen], hi_r[seen] / c[seen]])
        return float(np.max(ends.min(axis=0))), float(np.min(ends.max(axis=0)))

    return MonotoneScalarForm(lambda x: a * x, lambda z: z / a, w, x0, measurement_interval)


def _hull(S: ConvexSet) -> np.ndarray:
    B = S.interval_hull()
    return np.array([B.lo[0], B.hi[0]])


def _rows(S: ConvexSet) -> tuple[np.ndarray, np.ndarray]:
    B = S.interval_hull()
    return B.lo, B.hi
