"""Model invalidation: do the measurements contradict the model, and from which step?

A set-membership filter's posterior ⟦x_k | y_{0:k}⟧ is empty exactly when no trajectory of the model,
with every noise in its set, explains y_0, …, y_k; emptiness is monotone in k. The first such k is
where the data invalidate the model (a sensor fault, a wrong noise bound, a wrong matrix): the
measurement y_k lies outside the output set predicted from the data before it,

    O_k = C_k P_k + F_k V,    P_k = A_{k−1} ⟦x_{k−1} | y_{0:k−1}⟧ + E_{k−1} W (+ B_{k−1} u_{k−1}),  P_0 = X0,

(P_k the prediction (3) of the stability paper's Algorithm 1; the update (4) intersects it with the
states whose output can be y_k, empty exactly when y_k ∉ O_k),

and `first_inconsistency` reports k, y_k and its ∞-norm distance from O_k (it lives beside the filter
it runs, in `setsmooth.filters.classical`; `filter_inconsistency` here reads the filter's sets). That
distance is the closest-point program's value (`ConvexSet.center(method='closest')`), a measure of how
far the data miss, not a certified bound; the verdict itself is the filter's certified emptiness
decision.

The other estimators report the same way (`ModelInvalidationWarning`, ``on_inconsistent``):
`optimal_smoother` (its sets are all empty exactly when a posterior is, and it names the filter's first
empty step), and the outer-bound filters `oit_cz_filter`, `oit_inspired_filter`, `lsu_cz_filter`,
`lsuo_filter` and `lsup_filter` through `outer_inconsistency`. Their estimates contain the exact
posteriors, so an empty estimate proves the data inconsistent with the model; a non-empty one does not
prove them consistent (an outer bound of an empty set need not be empty), and the exact filter may find
the inconsistency at an earlier step. Their distance is measured from the output set predicted from
their own estimate at k − 1, a superset of the exact one: it is at most the exact filter's distance at
that step.

The scalar interval filters `interval_filter` (exact for its model) and `classical_interval_filter` (an
outer bound of the rethinking paper's optimal range) report an `IntervalInconsistency`: they know y_k
only through the states it allows, so their distance is the gap, in the state, between those states and
the predicted range.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..results import SetEstimates
from ..sets.algebra import linear_map, minkowski_sum
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet
from .steps import _predict

__all__ = ["Inconsistency", "IntervalInconsistency", "ModelInvalidationWarning", "ModelInvalidatedError",
           "filter_inconsistency", "outer_inconsistency", "report_inconsistency", "check_on_inconsistent",
           "ON_INCONSISTENT"]

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
    estimator : str
        '' for the exact filter; else the outer-bound estimator whose estimate is first empty at
        ``step`` (`outer_inconsistency`), whose distance is measured from its own prediction.
    """

    step: int
    measurement: np.ndarray
    distance: float
    estimator: str = ""

    def __str__(self) -> str:
        y = f"y_{self.step} = {np.array2string(self.measurement, precision=4)}"
        if self.estimator:
            before = "X0" if self.step == 0 else f"its estimate at k = {self.step - 1}"
            return (f"the measurements contradict the model by k = {self.step}: the {self.estimator} "
                    f"estimate, an outer bound of the exact posterior, is empty there; {y} lies "
                    f"{self.distance:.3g} (∞-norm) outside the output set predicted from {before}")
        before = "the initial set X0" if self.step == 0 else f"y_0..y_{self.step - 1}"
        return (f"the measurements contradict the model from k = {self.step}: {y} lies "
                f"{self.distance:.3g} (∞-norm) outside the output set predicted from {before}")


@dataclass(frozen=True)
class IntervalInconsistency(Inconsistency):
    """The first inconsistent step of a scalar interval filter (`interval_filter`,
    `classical_interval_filter`): the states consistent with y_k miss the range predicted for x_k.

    These filters know the measurement only through the states it allows (smoothing paper (7)), not
    through an output map, so ``distance`` is measured in the state: the gap between the two
    intervals below. The verdict is exact arithmetic on the endpoints (lo > hi).

    Attributes
    ----------
    predicted : tuple of float
        The prior range of x_k: the prediction (6) from y_0..y_{k−1}, ``x0_interval`` at k = 0.
    consistent : tuple of float
        The states consistent with y_k, ``measurement_interval(k, y_k)``.
    """

    predicted: tuple[float, float] = (np.nan, np.nan)
    consistent: tuple[float, float] = (np.nan, np.nan)

    def __str__(self) -> str:
        y = f"y_{self.step} = {np.array2string(self.measurement, precision=4)}"
        before = "the initial range x0_interval" if self.step == 0 else \
            f"the range predicted from y_0..y_{self.step - 1}"
        (c_lo, c_hi), (p_lo, p_hi) = self.consistent, self.predicted
        return (f"the measurements contradict the model from k = {self.step}: the states consistent "
                f"with {y}, [{c_lo:.4g}, {c_hi:.4g}], lie {self.distance:.3g} outside {before}, "
                f"[{p_lo:.4g}, {p_hi:.4g}]")


def _predicted_outputs(system, k: int, prior: ConvexSet) -> ConvexSet:
    """C_k P + F_k V: the outputs the model allows at step k for states in ``prior`` (y − D_k u_k)."""
    return minkowski_sum(linear_map(system.C_at(k), prior),
                         linear_map(-np.eye(system.m), system.measurement_noise_image(k)))


def _first_empty(estimates: SetEstimates) -> int | None:
    """The first empty set's index: where the filter marked it (an `EmptySet` from there on, as
    ``detect_empty`` does), else by the interval hulls (``first_empty``, one program per set)."""
    if getattr(estimates, "kind", "") == "smoothed":
        raise ValueError("estimates must be a filter's sets: smoothed sets are all empty or none is, so "
                         "they do not locate the first inconsistent step (pass the filter's, or none)")
    marked = [k for k, S in enumerate(estimates) if isinstance(S, EmptySet)]
    return marked[0] if marked else estimates.first_empty


def filter_inconsistency(system, X0: ConvexSet, ys: np.ndarray, estimates: SetEstimates,
                         given: Any = None) -> Inconsistency | None:
    """The first step at which a filter's sets ``estimates`` on ``ys`` are empty, as an
    `Inconsistency` (y_k's distance from O_k), or None: `first_inconsistency` once the filter has run.

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
    ys : ndarray, shape (T+1, m)
        The measurements, already checked (feedthrough taken off).
    estimates : SetEstimates
        The exact filter's sets on these data (an outer-bound filter's give its first empty step,
        which may come later); not a smoother's (ValueError).
    given : LinearSystem, optional
        The system as the user gave it, as in `outer_inconsistency`.
    """
    if len(estimates) != len(ys):
        raise ValueError(f"estimates has {len(estimates)} sets but ys has {len(ys)} measurements: "
                         "they must be the filter's sets on these data")
    k = _first_empty(estimates)
    return None if k is None else _inconsistency_at(system, X0, ys, estimates, k, "", given)


def _inconsistency_at(system, X0: ConvexSet, ys: np.ndarray, estimates: list, k: int, estimator: str,
                      given: Any) -> Inconsistency:
    """y_k's ∞-norm distance from the output set predicted (stability (3)) from ``estimates[k − 1]``
    (from X0 at k = 0), as an `Inconsistency`."""
    prior = X0 if k == 0 else _predict(system, k - 1, estimates[k - 1])
    y = ys[k]
    closest = _predicted_outputs(system, k, prior).center(method="closest", reference=y, norm=np.inf)
    distance = float(np.abs(closest - y).max()) if np.all(np.isfinite(closest)) else np.inf
    return Inconsistency(k, _as_given(y, k, system, given), distance, estimator)


def _as_given(y: np.ndarray, k: int, system, given) -> np.ndarray:
    """y_k as the user gave it: the feedthrough D_k u_k that the estimators' door took off, added back."""
    return y if given is None or given is system else y + given.feedthrough_term(k)


def report_inconsistency(found: Inconsistency | None, on_inconsistent: str) -> None:
    """Warn (`ModelInvalidationWarning`), raise (`ModelInvalidatedError`) or stay silent."""
    if found is None or on_inconsistent == "ignore":
        return
    if on_inconsistent == "raise":
        raise ModelInvalidatedError(str(found))
    warning = ModelInvalidationWarning(str(found))
    warning.inconsistency = found
    warnings.warn(warning, stacklevel=3)


def check_on_inconsistent(on_inconsistent: Any) -> None:
    """Raise ValueError unless ``on_inconsistent`` is one of `ON_INCONSISTENT`."""
    if on_inconsistent not in ON_INCONSISTENT:
        raise ValueError(f"on_inconsistent must be one of {ON_INCONSISTENT}, got {on_inconsistent!r}")


def outer_inconsistency(system, X0: ConvexSet, ys: np.ndarray, estimates: list, estimator: str,
                        given: Any = None) -> Inconsistency | None:
    """The first empty estimate of an outer-bound estimator, as an `Inconsistency`, or None.

    The estimator marks an empty estimate as an `EmptySet` (``estimates[k]``, k indexing ``ys``). Each
    estimate contains the exact posterior ⟦x_k | y_{0:k}⟧, so an empty one proves the data
    inconsistent with the model by step k (non-emptiness proves nothing). The distance is that of y_k
    from the output set predicted (stability (3)) from the estimate at k − 1 (from X0 at k = 0):
    positive when the estimate is the update (4) of P_k or is contained in it, and never more than the
    exact filter's distance at the same step.

    Parameters
    ----------
    system : LinearSystem
        The model the estimator ran on (for LSU models, their support system).
    X0 : ConvexSet
    ys : ndarray, shape (T+1, m)
        The measurements, already checked.
    estimates : list of ConvexSet
    estimator : str
        Its name, for the message.
    given : LinearSystem, optional
        The system as the user gave it, when the door took its feedthrough off ``ys``: the reported
        measurement is then y_k as given, D_k u_k included (as `first_inconsistency` reports it).
    """
    k = next((k for k, S in enumerate(estimates) if isinstance(S, EmptySet)), None)
    return None if k is None else _inconsistency_at(system, X0, ys, estimates, k, estimator, given)
