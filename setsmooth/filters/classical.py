"""The classical linear set-membership filter (stability paper Algorithm 1), as set algebra.

    prior_k     = A_{k-1} posterior_{k-1} ⊕ E_{k-1} W ⊕ {B_{k-1} u_{k-1}}   stability (3)
    posterior_k = { x ∈ prior_k : C_k x ∈ y_k ⊕ F_k(−V) }                   stability (4)

Under unrelated noises this is the optimal SMF (rethinking paper Corollary 1; smoothing paper Lemma 3).
With constrained-zonotope inputs the set algebra produces exactly the CZs of stability (20)–(21); with
other representations the sets stay exact, as lazy sets. The two steps are `setsmooth.filters.steps`;
`first_inconsistency` runs the filter to find where the data contradict the model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import measured
from ..results import SetEstimates
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet
from ..sets.reduction import apply_methods, as_methods
from ..trajectories.generic_program import filtered_ranges
from ..trajectories.nominal import RecursionDeviations, about_nominal
from ..trajectories.posterior_views import posterior_views
from ..trajectories.recursion_certificates import certified_against_data
from ._polygon_form import polygon_posteriors
from .consistency import ON_INCONSISTENT, Inconsistency, filter_inconsistency, report_inconsistency
from .hulls_along_time import filtered_hulls
from .steps import _check_state_set, _predict, _update

__all__ = ["classical_filter", "first_inconsistency", "FORMS"]

#: The forms of the exact filter's CZ posteriors (``form=``). 'views': the last projections of one
#: sparse trajectory CZ (`setsmooth.trajectories.posterior_views`), O(T) memory for a data set, and the
#: accurate form: the recursion's CZs of an unstable system carry generators grown like ‖A‖^k around a set
#: of unit width, and their hull endpoints can be 1e-4 of the width off an exact oracle, while the views,
#: whose states are deviations from the nominal trajectory, agree to 1e-6 (docs/numerical_core.md).
#: 'recursion': Algorithm 1's CZs, built step by step (the recursion smoother's input), now also about
#: the nominal trajectory (`setsmooth.trajectories.nominal`). Cost, example (31) with certified hulls,
#: CPU per data set: T = 50, views 0.33 s, recursion 0.22 s; T = 100, 0.88 s and 1.37 s (the
#: recursion grows as O(T³), the views as O(T²); ``benchmarks/bench_long_horizon.py --cases crossover``).
#: 'polygon': planar polytope systems only, Algorithm 1 in closed form with `Polygon`s (no solver;
#: `setsmooth.filters._polygon_form`), each containing the exact posterior up to rounding.
FORMS = ("auto", "views", "recursion", "polygon")


def classical_filter(system, X0: ConvexSet, ys: Any, *, reduce: Any = None,
                     detect_empty: bool = True, form: str = "auto",
                     on_inconsistent: str = "warn") -> SetEstimates:
    """Posterior ranges ⟦x_k | y_{0:k}⟧ for k = 0..T (stability paper Algorithm 1).

    With ``reduce`` it is a bounded filter: the reduction is applied to every posterior before the next
    prediction (CORA's reduced constrained-zonotope observer is Algorithm 1 plus this one line, e.g.
    ``reduce=ss.CORA_GIRARD``). The estimates are then **outer bounds** of the exact posteriors,
    ⟦x_k | y_{0:k}⟧ ⊆ posteriors[k], not the posteriors themselves; their complexity stays bounded.

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
        Initial prior range ⟦x_0⟧.
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T.
    reduce : ReductionMethod or sequence of ReductionMethod, optional
        Order reduction applied to every posterior (see `setsmooth.reduce`), e.g. ``ss.CORA_GIRARD``
        or ``(ss.Rescale('iter'), ss.EliminateConstraints(1), ss.Girard(1))``. None (default): the
        exact filter.
    detect_empty : bool
        Return `EmptySet` from the first empty posterior on. Emptiness of the exact posteriors is
        monotone in k, so this is one feasibility program on the last posterior when the data are
        consistent (a bisection otherwise), not one per step (with ``reduce``: one per step). With
        False the sets are returned as computed; an empty one is still empty (``is_empty()``), only
        not simplified.
    form : {'auto', 'views', 'recursion', 'polygon'}
        How exact posteriors of constrained-zonotope data are represented (the same sets either way):
        'auto' and 'views' give `PosteriorView`s of one shared trajectory CZ (accurate and O(T)
        memory; see `FORMS`), 'recursion' the CZs of Algorithm 1's recursion (what the recursion
        smoother reads). Sets without a CZ form always take the trajectory program. 'polygon'
        (n = 2 with X0, W, V polytopes: Box, Zonotope, VPolytope, Polygon; V also an HPolytope)
        gives `Polygon`s computed in closed form, each containing the exact posterior and larger
        only by rounding (certified hulls without a solver, ~10× faster on example (31)); a
        posterior certainly empty is an `EmptySet` from there on whatever ``detect_empty`` (a
        `Polygon` is never empty). ``optimal_smoother(method='recursion', posteriors=...)`` smooths
        them in closed form too. Not with ``reduce`` (a ValueError: the reduced filter has its own
        recursion).
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when the exact filter's posteriors become empty (with ``detect_empty``): the
        data contradict the model from that step on (model invalidation,
        `setsmooth.filters.consistency`). 'warn' issues a `ModelInvalidationWarning` naming the
        first step, its measurement and its ∞-norm distance from the predicted output set; 'raise'
        raises `ModelInvalidatedError` with the same message. (Reduced filters are outer bounds,
        whose emptiness proves inconsistency too; they report it the same way.)

    Returns
    -------
    SetEstimates
        A list of sets, ``posteriors[k]`` = ⟦x_k | y_{0:k}⟧, or a superset of it with ``reduce``
        (``outer=True``), with interval-hull tubes (``lo``, ``hi``, ``diameters()``, ``plot_tubes``)
        and the data it was computed from. An empty posterior
        means the measurements are inconsistent with the model (ill-posedness is data, not an
        exception). Without ``reduce``, when X0, W or V has no CZ form and X0 and W are bounded, the
        posteriors are `FilteredState`s: the same sets as projections of one compiled trajectory
        program (`setsmooth.trajectories.generic_program`). When they all flatten to CZs they are
        `PosteriorView`s (unless ``form='recursion'``): the same CZs as projections of one shared
        sparse trajectory CZ (`setsmooth.trajectories.posterior_views`), O(T) memory for all of them.

    Raises
    ------
    TypeError
        When ``system`` is not a setsmooth system: a `control.StateSpace` is led to
        `LinearSystem.from_statespace`, which adds the noise ranges.
    """
    given = system   # the inconsistency is reported in the user's terms (y_k with D u_k)
    system, ys = measured(system, ys)
    _check_state_set(X0, "X0", system.n)
    if on_inconsistent not in ON_INCONSISTENT:
        raise ValueError(f"on_inconsistent must be one of {ON_INCONSISTENT}, got {on_inconsistent!r}")
    result = _filtered(system, X0, ys, reduce, detect_empty, form)
    if detect_empty and on_inconsistent != "ignore" and len(result) \
            and isinstance(result[-1], EmptySet):  # (empty from the first empty one on)
        report_inconsistency(filter_inconsistency(system, X0, ys, result, given), on_inconsistent)
    return result


def first_inconsistency(system, X0: ConvexSet, ys: Any,
                        estimates: SetEstimates | None = None) -> Inconsistency | None:
    """The first step at which the measurements ``ys`` contradict the model, or None: the first
    empty posterior of Algorithm 1 (stability paper (3)–(4)) and y_k's distance from the output set
    predicted from the data before it (`setsmooth.filters.consistency`).

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
    ys : array_like, shape (T+1, m)
    estimates : SetEstimates, optional
        The exact filter's sets on these data, when already computed (`classical_filter`); an
        outer-bound filter's (`oit_cz_filter`, a reduced filter) give its first empty step, which may
        come later. Not a smoother's: its sets are all empty or none is (ValueError).

    Returns
    -------
    Inconsistency or None
        None when the data are consistent with the model (every posterior non-empty).
    """
    given = system
    system, ys = measured(system, ys)
    if estimates is None:
        estimates = classical_filter(system, X0, ys, on_inconsistent="ignore")
    return filter_inconsistency(system, X0, ys, estimates, given)


def _filtered(system, X0: ConvexSet, ys: np.ndarray, reduce: Any, detect_empty: bool,
              form: str) -> SetEstimates:
    """`classical_filter` after its checks."""
    if form not in FORMS:
        raise ValueError(f"form must be one of {FORMS}, got {form!r}")
    if reduce is not None and form != "auto":
        raise ValueError(f"form={form!r} chooses how the exact filter computes its sets; with reduce= "
                         "the filter is the reduced recursion (pass one of form= and reduce=)")
    if reduce is not None:
        return SetEstimates(_reduced_filter(system, X0, ys, as_methods(reduce, "reduce"), detect_empty),
                            system=system, X0=X0, ys=ys, kind="filtered", outer=True)
    if form == "polygon":
        return SetEstimates(polygon_posteriors(system, X0, ys), system=system, X0=X0, ys=ys,
                            kind="filtered")
    posteriors: list[ConvexSet] | None = None
    cz_form = all(S._flat_cz is not None for S in (X0, system.W, system.V))
    if not cz_form:
        # Without a CZ form the recursion's sets nest O(k) deep, one CVXPY compilation per query:
        # the same posteriors as projections of one compiled trajectory program (bounded states).
        posteriors = filtered_ranges(system, X0, ys)
    elif form != "recursion":
        # The recursion's CZs grow O(k²) dense rows each (O(T³) time and memory over a data set);
        # as views of one sparse trajectory CZ they are the same sets at O(k) per query, O(T) kept.
        posteriors = posterior_views(system, X0, ys)
    deviations = None
    if posteriors is None:
        # Algorithm 1's recursion, run on the deviations from the nominal trajectory (the same sets,
        # without rounding at the states' magnitude: `setsmooth.trajectories.nominal`).
        form_about = about_nominal(system, X0, ys)
        if form_about is None:  # an unbounded X0 (no centre): the original coordinates
            posteriors = _recursion(system, X0, ys)
        else:
            deviations = _recursion(form_about.system, form_about.X0, form_about.ys)
            posteriors = form_about.to_states(deviations)
        # The recursion's CZs are certified against the data
        # (`setsmooth.trajectories.recursion_certificates`).
        posteriors = certified_against_data(posteriors, system, X0, ys, "filtered")
    if detect_empty:
        first = _first_empty(posteriors)
        posteriors[first:] = [EmptySet(system.n) for _ in range(first, len(posteriors))]
        if deviations is not None:
            deviations[first:] = posteriors[first:]
    result = SetEstimates(posteriors, system=system, X0=X0, ys=ys, kind="filtered")
    if cz_form:
        result._along_time = _AlongTime(system, X0, ys, result)
    if deviations is not None:
        result._recursion_deviations = RecursionDeviations(form_about, deviations, result)
    return result


class _AlongTime:
    """The exact posteriors' hulls along time (`hulls_along_time.filtered_hulls`), valid for a
    result that holds ``sets``, the estimator's own, in order."""

    def __init__(self, system, X0: ConvexSet, ys: np.ndarray, result: list):
        self.system, self.X0, self.ys = system, X0, ys
        self.sets = tuple(result)

    def __call__(self, *, certified: bool, progress: bool) -> list[ConvexSet]:
        return filtered_hulls(self.system, self.X0, self.ys, certified=certified, progress=progress)


def _recursion(system, X0: ConvexSet, ys: np.ndarray) -> list[ConvexSet]:
    """Algorithm 1's posteriors, step by step (stability (3)–(4))."""
    posteriors: list[ConvexSet] = []
    prior = X0
    for k, y in enumerate(ys):
        if k > 0:
            prior = _predict(system, k - 1, posteriors[-1])
        posteriors.append(_update(system, k, prior, y))
    return posteriors


def _reduced_filter(system, X0: ConvexSet, ys: np.ndarray, methods, detect_empty: bool
                    ) -> list[ConvexSet]:
    """The filter with a reduction after every update. An outer bound of an empty set need not be
    empty, so emptiness is not monotone along a reduced filter: each reduced posterior is checked
    before the next prediction uses it."""
    posteriors: list[ConvexSet] = []
    prior = X0
    for k, y in enumerate(ys):
        if k > 0:
            prior = _predict(system, k - 1, posteriors[-1])
        posterior = apply_methods(_update(system, k, prior, y), methods)
        if detect_empty and not isinstance(posterior, EmptySet) and posterior.is_empty():
            posterior = EmptySet(system.n)
        posteriors.append(posterior)
    return posteriors


def _first_empty(posteriors: list[ConvexSet]) -> int:
    """Index of the first empty posterior (len(posteriors) when none is empty), by bisection.

    Emptiness is monotone in k: ⟦x_k | y_{0:k}⟧ = ∅ makes every later posterior empty (more data, fewer
    consistent trajectories; in the recursion the prediction of an empty set is empty). So one
    feasibility program on the last posterior settles a consistent data set, and ⌈log₂(T + 1)⌉ more
    find the first empty one otherwise, instead of one program per step.
    """
    last = len(posteriors) - 1
    if not posteriors[last].is_empty():
        return last + 1
    lo, hi = 0, last  # the first empty posterior lies in [lo, hi]
    while lo < hi:
        mid = (lo + hi) // 2
        if posteriors[mid].is_empty():
            hi = mid
        else:
            lo = mid + 1
    return lo
