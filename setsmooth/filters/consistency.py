"""Model invalidation: do the measurements contradict the model, and from which step?

A set-membership filter's posterior ⟦x_k | y_{0:k}⟧ is empty exactly when no trajectory of the model,
with every noise in its set, explains y_0, …, y_k; emptiness is monotone in k. The first such k is
where the data invalidate the model (a sensor fault, a wrong noise bound, a wrong matrix): the
measurement y_k lies outside the output set predicted from the data before it,

    O_k = C_k P_k + D_k V,    P_k = A_{k−1} ⟦x_{k−1} | y_{0:k−1}⟧ + B_{k−1} W (+ u_{k−1}),  P_0 = X0,

(P_k the prediction (3) of the stability paper's Algorithm 1; the update (4) intersects it with the
states whose output can be y_k, empty exactly when y_k ∉ O_k),

and `first_inconsistency` reports k, y_k and its ∞-norm distance from O_k. That distance is the
closest-point program's value (`ConvexSet.center(method='closest')`), a measure of how far the data
miss, not a certified bound; the verdict itself is the filter's certified emptiness decision.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_measurements, check_system
from ..results import SetEstimates
from ..sets.algebra import linear_map, minkowski_sum
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet

__all__ = ["Inconsistency", "ModelInvalidationWarning", "ModelInvalidatedError",
           "first_inconsistency", "report_inconsistency", "ON_INCONSISTENT"]

#: What an estimator does when the data contradict the model: warn (the default), raise, or ignore.
ON_INCONSISTENT = ("warn", "raise", "ignore")


class ModelInvalidationWarning(UserWarning):
    """The measurements contradict the model from some step on (the `Inconsistency` is its
    ``inconsistency`` attribute)."""


class ModelInvalidatedError(ValueError):
    """Raised instead of `ModelInvalidationWarning` with ``on_inconsistent='raise'``."""


@dataclass(frozen=True)
class Inconsistency:
    """The first step at which the measurements contradict the model.

    Attributes
    ----------
    step : int
        The first k with an empty posterior.
    measurement : ndarray, shape (m,)
        y_k.
    distance : float
        ∞-norm distance of y_k from the output set predicted from y_0, …, y_{k−1} (solver value).
    """

    step: int
    measurement: np.ndarray
    distance: float

    def __str__(self) -> str:
        before = "the initial set X0" if self.step == 0 else f"y_0..y_{self.step - 1}"
        return (f"the measurements contradict the model from k = {self.step}: y_{self.step} = "
                f"{np.array2string(self.measurement, precision=4)} lies {self.distance:.3g} "
                f"(∞-norm) outside the output set predicted from {before}")


def _predicted_outputs(system, k: int, prior: ConvexSet) -> ConvexSet:
    """C_k P + D_k V: the outputs the model allows at step k for states in ``prior``."""
    return minkowski_sum(linear_map(system.C(k), prior),
                         linear_map(-np.eye(system.m), system.measurement_noise_image(k)))


def _first_empty(estimates: SetEstimates) -> int | None:
    """The first empty set's index: where the filter marked it (an `EmptySet` from there on, as
    ``detect_empty`` does), else by the interval hulls (``first_empty``, one program per set)."""
    marked = [k for k, S in enumerate(estimates) if isinstance(S, EmptySet)]
    return marked[0] if marked else estimates.first_empty


def first_inconsistency(system, X0: ConvexSet, ys: Any,
                        estimates: SetEstimates | None = None) -> Inconsistency | None:
    """The first step at which the measurements ``ys`` contradict the model, or None: the first
    empty posterior of Algorithm 1 (stability paper (3)–(4)) and y_k's distance from O_k.

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
    ys : array_like, shape (T+1, m)
    estimates : SetEstimates, optional
        The exact filter's sets on these data, when already computed (`classical_filter`).

    Returns
    -------
    Inconsistency or None
        None when the data are consistent with the model (every posterior non-empty).
    """
    from .classical import _predict, classical_filter

    ys = as_measurements(ys, check_system(system).m)
    if estimates is None:
        estimates = classical_filter(system, X0, ys, on_inconsistent="ignore")
    elif len(estimates) != len(ys):
        raise ValueError(f"estimates has {len(estimates)} sets but ys has {len(ys)} measurements: "
                         "they must be the filter's sets on these data")
    k = _first_empty(estimates)
    if k is None:
        return None
    y = ys[k]
    prior = X0 if k == 0 else _predict(system, k - 1, estimates[k - 1])
    closest = _predicted_outputs(system, k, prior).center(method="closest", reference=y,
                                                           norm=np.inf)
    distance = float(np.abs(closest - y).max()) if np.all(np.isfinite(closest)) else np.inf
    return Inconsistency(k, y, distance)


def report_inconsistency(found: Inconsistency | None, on_inconsistent: str) -> None:
    """Warn (`ModelInvalidationWarning`), raise (`ModelInvalidatedError`) or stay silent."""
    if found is None or on_inconsistent == "ignore":
        return
    if on_inconsistent == "raise":
        raise ModelInvalidatedError(str(found))
    warning = ModelInvalidationWarning(str(found))
    warning.inconsistency = found
    warnings.warn(warning, stacklevel=3)
