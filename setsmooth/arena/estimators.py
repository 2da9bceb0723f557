"""The estimator registry: any callable ``(system, X0, ys) -> estimates``, by name.

An estimate is whatever an estimator returns, read through its interval hulls (`hull_tubes`): an object
with ``lo``/``hi`` tubes (`SetEstimates`, `IntervalEstimates`), an `OITResult` (its certified hulls),
or a list of sets with ``interval_hull()``. So a new set representation or a new filter enters the
arena with one call::

    register("my_filter", my_filter)             # my_filter(system, X0, ys) -> list of sets

Each estimator states what it estimates (``kind``): ``'filtered'`` sets ⟦x_k | y_{0:k}⟧ are compared
with the exact filter, ``'smoothed'`` sets ⟦x_k | y_{0:T}⟧ with the exact (trajectory) smoother.

For a process pool (and Dask) the estimator's function travels to the workers by pickling: a
module-level function, or a `functools.partial` of one. A lambda or a local function runs with
``executor='serial'``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..filters.classical import classical_filter
from ..filters.oit import oit_cz_filter
from ..sets.reduction import CORA_GIRARD
from ..smoothers.linear import optimal_smoother

__all__ = ["Estimator", "register", "unregister", "ESTIMATORS", "REFERENCES", "KINDS", "check_estimators",
           "hull_tubes"]

KINDS = ("filtered", "smoothed")


@dataclass(frozen=True)
class Estimator:
    """A registered estimator: its name, the callable, what it estimates, and a one-line summary."""

    name: str
    fn: Callable[..., Any]
    kind: str = "filtered"
    summary: str = ""

    def __call__(self, system, X0, ys):
        return self.fn(system, X0, ys)


def exact_filter(system, X0, ys):
    """The exact (optimal) filter, stability paper Algorithm 1: the reference for filtered sets."""
    return classical_filter(system, X0, ys)


def trajectory_smoother(system, X0, ys):
    """The exact smoother via the trajectory set (smoothing paper Corollary 1): the smoothed reference."""
    return optimal_smoother(system, X0, ys, method="trajectory")


def reduced_girard(system, X0, ys):
    """CORA's reduced CZ filter (rescale, eliminate to one constraint, Girard order 1): outer bounds."""
    return classical_filter(system, X0, ys, reduce=CORA_GIRARD)


def oit_cz(system, X0, ys):
    """The OIT-CZ SMF (stability paper Algorithm 3) with its certified hulls: outer bounds."""
    return oit_cz_filter(system, X0, ys, hulls=True)


#: The registry, by name; built-ins first. `register` adds to it.
ESTIMATORS: dict[str, Estimator] = {}

#: The exact estimator of each kind, whose hulls every estimator of that kind must contain.
REFERENCES = {"filtered": "exact_filter", "smoothed": "trajectory_smoother"}


def register(name: str, fn: Callable[..., Any], *, kind: str = "filtered", summary: str = "",
             replace: bool = False) -> Estimator:
    """Add an estimator to the arena under ``name``.

    Parameters
    ----------
    name : str
        The name used on the command line and in the table.
    fn : callable (system, X0, ys) -> estimates
        Returns an object with ``lo``/``hi`` tubes of shape (T+1, n), an `OITResult`, or a list of
        T+1 sets with ``interval_hull()`` (see `hull_tubes`).
    kind : {'filtered', 'smoothed'}
        What the sets bound: filtered ranges are held to the exact filter, smoothed ones to the exact
        smoother.
    summary : str
        One line for listings; the function's docstring's first line by default.
    replace : bool
        Allow replacing an estimator already registered under ``name``.

    Returns
    -------
    Estimator

    Raises
    ------
    ValueError
        For an empty name, an unknown ``kind``, or a name already taken (without ``replace``).
    TypeError
        When ``fn`` is not callable.
    """
    if not isinstance(name, str) or not name or "," in name:
        raise ValueError(f"name must be a non-empty string without commas, got {name!r}")
    if not callable(fn):
        raise TypeError(f"fn must be a callable (system, X0, ys) -> estimates, got {type(fn).__name__}")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    if name in ESTIMATORS and not replace:
        raise ValueError(f"an estimator named {name!r} is already registered; pass replace=True to "
                         "replace it, or choose another name")
    if not summary:
        summary = ((getattr(fn, "__doc__", None) or "").strip().splitlines() or [""])[0]
    estimator = Estimator(name, fn, kind, summary)
    ESTIMATORS[name] = estimator
    return estimator


def chosen_names(names: Any, choices: dict, default: list[str], argument: str, kind: str
                 ) -> list[str]:
    """``names`` (a name or a sequence of names; None: ``default``) without repeats, each a key of
    ``choices``; a ValueError naming ``argument`` and the valid choices otherwise."""
    if names is None:
        return default
    names = list(dict.fromkeys([names] if isinstance(names, str) else names))
    unknown = [name for name in names if name not in choices]
    if unknown or not names:
        what = f"unknown {kind} {', '.join(map(repr, unknown))}" if unknown else f"no {kind} given"
        raise ValueError(f"{argument}: {what}; choose from {', '.join(choices)}")
    return names


def unregister(name: str) -> None:
    """Remove a registered estimator (a built-in one too)."""
    check_estimators([name], "name")
    del ESTIMATORS[name]


def check_estimators(names: Any, argument: str = "estimators") -> list[str]:
    """Validate estimator names; None gives every registered estimator.

    Raises
    ------
    ValueError
        For an unknown name, naming ``argument`` and the valid choices.
    """
    return chosen_names(names, ESTIMATORS, list(ESTIMATORS), argument, "estimator")


def hull_tubes(estimates: Any) -> tuple[np.ndarray, np.ndarray]:
    """Interval-hull tubes (lo, hi), shape (T+1, n), of an estimator's output; NaN rows where empty.

    Raises
    ------
    TypeError
        When the output has neither ``lo``/``hi``, OIT hulls, nor sets with ``interval_hull()``.
    """
    hulls = getattr(estimates, "hulls", None)
    if isinstance(hulls, tuple) and len(hulls) == 2:      # OITResult(hulls=True)
        return _tubes(*hulls)
    if hasattr(estimates, "lo") and hasattr(estimates, "hi"):
        return _tubes(estimates.lo, estimates.hi)
    sets = getattr(estimates, "estimates", estimates)     # an OITResult without hulls: its sets
    try:
        boxes = [S.interval_hull() for S in sets]
    except (AttributeError, TypeError) as exc:
        raise TypeError("an estimator must return an object with lo/hi tubes or a list of sets with "
                        f"interval_hull(), got {type(estimates).__name__}") from exc
    lo = np.array([np.full(S.dim, np.nan) if B.is_empty() else B.lo for S, B in zip(sets, boxes)])
    hi = np.array([np.full(S.dim, np.nan) if B.is_empty() else B.hi for S, B in zip(sets, boxes)])
    return lo, hi


def _tubes(lo: Any, hi: Any) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    if lo.ndim == 1:       # a scalar state (IntervalEstimates)
        lo, hi = lo[:, None], hi[:, None]
    return lo, hi


for _name, _fn, _kind in (("exact_filter", exact_filter, "filtered"),
                          ("trajectory_smoother", trajectory_smoother, "smoothed"),
                          ("reduced_girard", reduced_girard, "filtered"),
                          ("oit_cz", oit_cz, "filtered")):
    register(_name, _fn, kind=_kind)
