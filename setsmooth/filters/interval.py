"""The optimal set-membership filter for scalar systems with monotone dynamics (smoothing paper (27)–(28)).

    x_{k+1} = η(x_k) + w_k,   w_k ∈ [w_lo, w_hi],        y_k = g(x_k, v_k),

with η: ℝ → ℝ continuous and strictly increasing. Every range is then an interval and Lemma 3 reduces
to interval endpoint arithmetic:

    prediction (6):  [a, b] ↦ [η(a) + w_lo, η(b) + w_hi],
    update (7):      prior ∩ {x : y_k = g(x, v) for some v ∈ ⟦v_k⟧},

where the measurement-consistent interval is supplied by the caller (for y = 2x + v, v ∈ [1, 3]:
x ∈ [(y − 3)/2, (y − 1)/2], smoothing paper (34)).

An empty range is stored as ``lo = hi = nan``: NaN can never pass as a real bound in a comparison,
and ``IntervalEstimates.empty`` exposes the flag.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import real_array, real_number


@dataclass(frozen=True)
class IntervalEstimates:
    """Interval ranges [lo[k], hi[k]] for k = 0..T; both NaN where the range is empty.

    Attributes
    ----------
    lo, hi : ndarray, shape (T+1,)
        Lower and upper endpoints (read-only copies; ±inf allowed for unbounded ranges).

    Raises
    ------
    ValueError
        When shapes differ, NaN appears in only one endpoint, or lo > hi somewhere.
    """

    lo: np.ndarray
    hi: np.ndarray

    def __post_init__(self) -> None:
        lo = real_array(self.lo, "lo").reshape(-1).copy() if np.ndim(self.lo) <= 1 else None
        hi = real_array(self.hi, "hi").reshape(-1).copy() if np.ndim(self.hi) <= 1 else None
        if lo is None or hi is None or lo.shape != hi.shape:
            raise ValueError(f"lo and hi must be 1-D arrays of one length (T+1,), got shapes "
                             f"{np.shape(self.lo)} and {np.shape(self.hi)}")
        if not np.array_equal(np.isnan(lo), np.isnan(hi)):
            raise ValueError("lo and hi must be NaN at the same steps (NaN marks an empty range)")
        with np.errstate(invalid="ignore"):
            if np.any(lo > hi):
                raise ValueError(f"lo must not exceed hi; first violation at k = {int(np.argmax(lo > hi))}")
        lo.setflags(write=False)
        hi.setflags(write=False)
        # Frozen dataclass: assign the validated copies through object.__setattr__.
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)

    @property
    def empty(self) -> np.ndarray:
        """Boolean array, True where the range is empty."""
        return np.isnan(self.lo)

    @property
    def diameters(self) -> np.ndarray:
        """hi − lo for every k (NaN for an empty range, inf for an unbounded one)."""
        return self.hi - self.lo

    def __len__(self) -> int:
        return self.lo.shape[0]


def interval_filter(eta: Callable[[float], float], w_interval: Any, x0_interval: Any, ys: Any,
                    measurement_interval: Callable[[int, Any], tuple[float, float]]) -> IntervalEstimates:
    """Posterior ranges ⟦x_k | y_{0:k}⟧ = [a_k, b_k] for k = 0..T (smoothing paper Lemma 3, (6)–(7)).

    Parameters
    ----------
    eta : callable float -> float
        The transition η of (27); must be continuous and strictly increasing on ℝ.
    w_interval : array_like, shape (2,) or (T, 2)
        Process-noise range [w_lo, w_hi], constant or one row per step k = 0..T-1.
    x0_interval : array_like, shape (2,)
        Initial prior range ⟦x_0⟧ = [lo, hi]; infinite endpoints are allowed.
    ys : array_like, shape (T+1,) or (T+1, m)
        Measurements; ``ys[k]`` is passed unchanged to ``measurement_interval``.
    measurement_interval : callable (k, y_k) -> (lo, hi)
        The interval ⋃_{v ∈ ⟦v_k⟧} g_{k,v}⁻¹({y_k}) of states consistent with y_k (7).

    Returns
    -------
    IntervalEstimates
        The posteriors. Once a range is empty (measurements inconsistent with the model) every
        later range is empty too.

    Raises
    ------
    ValueError
        For malformed intervals, a measurement interval with lo > hi or NaN, or when η is seen not to
        be increasing (η(a) > η(b) for a < b) or returns NaN.
    TypeError
        When ``eta`` or ``measurement_interval`` is not callable.

    References
    ----------
    Smoothing paper Lemma 3 (6)–(7) and §IV-B; the example (33)–(34) uses η(x) = ∛x + x.
    """
    if not callable(eta):
        raise TypeError(f"eta must be a callable float -> float, got {type(eta).__name__}")
    if not callable(measurement_interval):
        raise TypeError("measurement_interval must be a callable (k, y_k) -> (lo, hi), got "
                        f"{type(measurement_interval).__name__}")
    ys = real_array(ys, "ys", "an array of measurements")
    if ys.ndim < 1 or ys.shape[0] < 1:
        raise ValueError(f"ys must have shape (T+1,) or (T+1, m) with T >= 0, got {ys.shape}")
    if not np.isfinite(ys).all():
        raise ValueError("ys contains NaN or inf")
    steps = ys.shape[0]
    w = _noise_intervals(w_interval, steps - 1)
    lo0, hi0 = _interval(x0_interval, "x0_interval", allow_inf=True)

    lo = np.full(steps, np.nan)
    hi = np.full(steps, np.nan)
    prior = (lo0, hi0)
    for k in range(steps):
        if k > 0:
            eta_lo, eta_hi = _eval_eta(eta, lo[k - 1]), _eval_eta(eta, hi[k - 1])
            if eta_lo > eta_hi:
                raise ValueError(f"eta must be increasing: eta({lo[k - 1]}) > eta({hi[k - 1]})")
            prior = (eta_lo + w[k - 1, 0], eta_hi + w[k - 1, 1])
        m_lo, m_hi = _interval(measurement_interval(k, ys[k]), f"measurement_interval({k}, ys[{k}])",
                               allow_inf=True)
        a, b = max(prior[0], m_lo), min(prior[1], m_hi)
        if a > b:
            break  # inconsistent data: this and all later ranges stay NaN (empty)
        lo[k], hi[k] = a, b
    return IntervalEstimates(lo, hi)


def _noise_intervals(w_interval: Any, T: int) -> np.ndarray:
    """Return the process-noise ranges as a (T, 2) array of finite [w_lo, w_hi] rows."""
    arr = real_array(w_interval, "w_interval", "an array of intervals [w_lo, w_hi]")
    if arr.shape == (2,):
        arr = np.broadcast_to(arr, (T, 2))
    if arr.shape != (T, 2):
        raise ValueError(f"w_interval must have shape (2,) or (T, 2) = ({T}, 2), got {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError("w_interval must have finite endpoints")
    if np.any(arr[:, 0] > arr[:, 1]):
        raise ValueError("w_interval must satisfy w_lo <= w_hi")
    return arr


def _eval_eta(eta: Callable[[float], float], x: float) -> float:
    """η(x) as a float, raising ValueError when η returns NaN."""
    value = real_number(eta(float(x)), f"eta({float(x)!r})")
    if np.isnan(value):
        raise ValueError(f"eta({float(x)!r}) returned NaN; eta must be defined on all of R")
    return value


def _interval(value: Any, name: str, allow_inf: bool) -> tuple[float, float]:
    arr = real_array(value, name, "a pair of numbers (lo, hi)").reshape(-1)
    if arr.shape != (2,):
        raise ValueError(f"{name} must be a pair (lo, hi) of shape (2,), got shape {np.shape(value)}")
    if np.isnan(arr).any() or (not allow_inf and np.isinf(arr).any()):
        raise ValueError(f"{name} must have {'non-NaN' if allow_inf else 'finite'} endpoints, got {arr}")
    if arr[0] > arr[1]:
        raise ValueError(f"{name} must satisfy lo <= hi, got {arr}")
    return float(arr[0]), float(arr[1])
