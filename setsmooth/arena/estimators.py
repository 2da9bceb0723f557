"""The estimator registry: any callable ``(system, X0, ys) -> estimates``, by name.

An estimate is whatever an estimator returns, read through its interval hulls (`hull_tubes`): an object
with ``lo``/``hi`` tubes (`SetEstimates`, `IntervalEstimates`), an `OITResult` (its certified hulls),
or a list of sets with ``interval_hull()``. So a new set representation or a new filter enters the
arena with one call::

    register("my_filter", my_filter)             # my_filter(system, X0, ys) -> list of sets

Each estimator states what it estimates (``kind``): ``'filtered'`` sets ⟦x_k | y_{0:k}⟧ are compared
with the exact filter, ``'smoothed'`` sets ⟦x_k | y_{0:T}⟧ with the exact (trajectory) smoother. And
it states the systems it applies to (``applies_to``, among `STRUCTURES`): ``'linear'`` (a
`LinearSystem`, the default) or ``'scalar_monotone'`` (x_{k+1} = η(x_k) + w_k with η increasing,
smoothing paper (27): the interval filter and smoother). A problem declares the structures its system
has, and the arena runs an estimator only on the problems it applies to; every other pair is "n/a".
Heavy estimators (the recursion smoother, O(T²); LSUP, combinatorial in n) run only when named.

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
from ..filters.interval import interval_filter
from ..filters.lsu import LSUModel, lsu_cz_filter, lsuo_filter, lsup_filter
from ..filters.oit import oit_inspired_filter
from ..filters.oit_cz import oit_cz_filter
from ..sets.reduction import CORA_COMBASTEL, CORA_GIRARD
from ..smoothers.linear import optimal_smoother
from ..smoothers.nonlinear import interval_smoother
from .scalar import monotone_scalar_form

__all__ = ["Estimator", "register", "unregister", "ESTIMATORS", "REFERENCES", "KINDS", "STRUCTURES",
           "check_estimators", "hull_tubes", "estimated_sets", "lsu_model"]

KINDS = ("filtered", "smoothed")
#: What a problem's system can be, and what an estimator can take: a `LinearSystem`; a scalar system
#: x_{k+1} = η(x_k) + w_k with η increasing (`setsmooth.arena.scalar`; a scalar linear one with A > 0
#: is both).
STRUCTURES = ("linear", "scalar_monotone")


@dataclass(frozen=True)
class Estimator:
    """A registered estimator: its name, the callable, what it estimates, the structures of system it
    applies to, a one-line summary, and whether it is heavy (left out of the default selection)."""

    name: str
    fn: Callable[..., Any]
    kind: str = "filtered"
    summary: str = ""
    heavy: bool = False
    applies_to: frozenset[str] = frozenset({"linear"})

    def __call__(self, system, X0, ys):
        return self.fn(system, X0, ys)

    def applies(self, structure: frozenset[str]) -> bool:
        """Whether it runs on a problem whose system has ``structure`` (one shared structure suffices)."""
        return bool(self.applies_to & structure)


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


def recursion_smoother(system, X0, ys):
    """The exact smoother by its recursion (smoothing paper Algorithm 1, (24)): O(T²) constraints."""
    return optimal_smoother(system, X0, ys, method="recursion")


def reduced_combastel(system, X0, ys):
    """CORA's reduced CZ filter with Combastel's reduction (order 1) instead of Girard's: outer bounds."""
    return classical_filter(system, X0, ys, reduce=CORA_COMBASTEL)


def oit_inspired(system, X0, ys):
    """The OIT-inspired filter (stability paper Algorithm 2), exact sets reset when empty."""
    return oit_inspired_filter(system, X0, ys)


_TINY = 1e-12


def lsu_model(system, X0, ys) -> tuple[LSUModel, np.ndarray, np.ndarray]:
    """The LSU model (LSU paper (4)–(6)) whose boxes hold this system's noise terms, with its data.

    The LSU filters take x_{t+1} = A x_t + B u_t + w, y_t = C x_t + v with w, v in centred boxes and a
    box prior. E·W and F·V are replaced by their interval hulls (centres moved into the known input and
    the measurements; a zero half-width widened to 1e-12 at the coordinate's scale) and ⟦x_0⟧ by its
    hull, so every set the LSU filters return bounds the system's exact posterior too. Constant matrices only (reading ``system.A`` raises otherwise).

    Returns
    -------
    model : LSUModel
    ys : ndarray, shape (T+1, m)
        The measurements less the centre of F·V.
    us : ndarray, shape (T+1, n)
        The known term B_k u_k plus the centre of E·W (the LSU model's B is the identity).
    """
    A, C, E, F = system.A, system.C, system.E, system.F
    W, V, prior = system.W.interval_hull(), system.V.interval_hull(), X0.interval_hull()
    w_mid, w_half = E @ ((W.lo + W.hi) / 2), np.abs(E) @ ((W.hi - W.lo) / 2)
    v_mid, v_half = F @ ((V.lo + V.hi) / 2), np.abs(F) @ ((V.hi - V.lo) / 2)
    # the LSU model needs positive half-widths: a coordinate no noise reaches gets a rounding's width
    w_half = np.maximum(w_half, _TINY * np.maximum(1.0, np.abs(w_mid)))
    v_half = np.maximum(v_half, _TINY * np.maximum(1.0, np.abs(v_mid)))
    ys = np.asarray(ys, dtype=float)
    T = len(ys) - 1      # u_T drives no state of the horizon (and a system may not be given it)
    us = np.array([(system.input_term(k) if k < T else 0.0) + w_mid for k in range(T + 1)])
    model = LSUModel(A, np.eye(system.n), C, w_half, v_half, prior.lo, prior.hi)
    return model, ys - v_mid, us


def lsu_cz(system, X0, ys):
    """LSU-CZ (LSU paper Algorithm 1, n_g = max(9, 3n), n_c = 2) on the system's LSU model: outer bounds."""
    model, ys, us = lsu_model(system, X0, ys)
    # the paper's n_g = 9 (at its n = 3), grown with n beyond that (n_g ≥ n + n_c is required)
    return lsu_cz_filter(model, ys, us, max_generators=max(9, 3 * system.n), max_constraints=2,
                         estimates=(), std=False)


def lsuo(system, X0, ys):
    """LSUO, the orthotopic LSU filter, on the system's LSU model: outer bounds (boxes)."""
    model, ys, us = lsu_model(system, X0, ys)
    return lsuo_filter(model, ys, us, std=False)


def lsup(system, X0, ys):
    """LSUP, the parallelotopic LSU filter (minimal volume), on the system's LSU model: outer bounds."""
    model, ys, us = lsu_model(system, X0, ys)
    return lsup_filter(model, ys, us, std=False)


def interval_filter_estimator(system, X0, ys):
    """The interval filter, smoothing paper Lemma 3 (6)–(7): exact for a scalar system with η increasing."""
    form = monotone_scalar_form(system, X0, ys)
    return interval_filter(form.eta, form.w_intervals, form.x0_interval, ys, form.measurement_interval)


def interval_smoother_estimator(system, X0, ys):
    """The interval smoother, smoothing paper Proposition 2 (Algorithm 2): exact for a scalar η increasing."""
    form = monotone_scalar_form(system, X0, ys)
    filtered = interval_filter(form.eta, form.w_intervals, form.x0_interval, ys, form.measurement_interval)
    return interval_smoother(form.eta, form.w_intervals, filtered, form.eta_inverse)


#: The registry, by name; built-ins first. `register` adds to it.
ESTIMATORS: dict[str, Estimator] = {}

#: The exact estimator of each kind, whose hulls every estimator of that kind must contain.
REFERENCES = {"filtered": "exact_filter", "smoothed": "trajectory_smoother"}


def register(name: str, fn: Callable[..., Any], *, kind: str = "filtered", summary: str = "",
             heavy: bool = False, applies_to: Any = ("linear",), replace: bool = False) -> Estimator:
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
    heavy : bool
        Leave it out when no estimators are named (it runs when named).
    applies_to : str or sequence of str
        The structures of system it takes, among `STRUCTURES`: ``'linear'`` (a `LinearSystem`),
        ``'scalar_monotone'`` (`setsmooth.arena.scalar`). The arena runs it on a problem only when the
        problem's system has one of them, and reports the other pairs as not applicable.
    replace : bool
        Allow replacing an estimator already registered under ``name``.

    Returns
    -------
    Estimator

    Raises
    ------
    ValueError
        For an empty name, an unknown ``kind`` or structure, or a name already taken (without
        ``replace``).
    TypeError
        When ``fn`` is not callable.
    """
    if not isinstance(name, str) or not name or "," in name:
        raise ValueError(f"name must be a non-empty string without commas, got {name!r}")
    if not callable(fn):
        raise TypeError(f"fn must be a callable (system, X0, ys) -> estimates, got {type(fn).__name__}")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    applies_to = frozenset([applies_to] if isinstance(applies_to, str) else applies_to)
    if not applies_to or not applies_to <= set(STRUCTURES):
        raise ValueError(f"applies_to must name structures among {STRUCTURES}, got {sorted(applies_to)}")
    if name in ESTIMATORS and not replace:
        raise ValueError(f"an estimator named {name!r} is already registered; pass replace=True to "
                         "replace it, or choose another name")
    if not summary:
        summary = ((getattr(fn, "__doc__", None) or "").strip().splitlines() or [""])[0]
    estimator = Estimator(name, fn, kind, summary, bool(heavy), applies_to)
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
    """Validate estimator names; None gives every registered estimator that is not heavy.

    Raises
    ------
    ValueError
        For an unknown name, naming ``argument`` and the valid choices.
    """
    default = [name for name, e in ESTIMATORS.items() if not e.heavy]
    return chosen_names(names, ESTIMATORS, default, argument, "estimator")


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
    sets = estimated_sets(estimates)
    try:
        boxes = [S.interval_hull() for S in sets]
    except (AttributeError, TypeError) as exc:
        raise TypeError("an estimator must return an object with lo/hi tubes or a list of sets with "
                        f"interval_hull(), got {type(estimates).__name__}") from exc
    lo = np.array([np.full(S.dim, np.nan) if B.is_empty() else B.lo for S, B in zip(sets, boxes)])
    hi = np.array([np.full(S.dim, np.nan) if B.is_empty() else B.hi for S, B in zip(sets, boxes)])
    return lo, hi


def estimated_sets(estimates: Any) -> Any:
    """The sets of an estimator's output: an LSU result's supports, an OIT result's estimates, or
    the output itself (a list of sets, `SetEstimates`); tubes only (``lo``/``hi``) give themselves."""
    for attribute in ("supports", "estimates"):
        sets = getattr(estimates, attribute, None)
        if isinstance(sets, (list, tuple)):
            return sets
    return estimates


def _tubes(lo: Any, hi: Any) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    if lo.ndim == 1:       # a scalar state (IntervalEstimates)
        lo, hi = lo[:, None], hi[:, None]
    return lo, hi


for _name, _fn, _kind, _heavy in (("exact_filter", exact_filter, "filtered", False),
                                  ("trajectory_smoother", trajectory_smoother, "smoothed", False),
                                  ("recursion_smoother", recursion_smoother, "smoothed", True),
                                  ("reduced_girard", reduced_girard, "filtered", False),
                                  ("reduced_combastel", reduced_combastel, "filtered", False),
                                  ("oit_cz", oit_cz, "filtered", False),
                                  ("oit_inspired", oit_inspired, "filtered", False),
                                  ("lsu_cz", lsu_cz, "filtered", False),
                                  ("lsuo", lsuo, "filtered", False),
                                  ("lsup", lsup, "filtered", True)):
    register(_name, _fn, kind=_kind, heavy=_heavy)
register("interval_filter", interval_filter_estimator, kind="filtered", applies_to="scalar_monotone")
register("interval_smoother", interval_smoother_estimator, kind="smoothed", applies_to="scalar_monotone")
