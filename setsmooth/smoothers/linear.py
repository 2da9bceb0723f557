"""The optimal set-membership smoother for linear systems (smoothing paper Corollary 1, Algorithm 1).

    ⟦x_k | y_{0:T}⟧ = ⟦x_k | y_{0:k}⟧ ∩ ( ker(Φ_k) ⊕ Φ_k⁺(⟦x_{k+1} | y_{0:T}⟧ ⊕ Γ_k⟦−w_k⟧ ⊖ u_k) )
                    = { x ∈ ⟦x_k | y_{0:k}⟧ : Φ_k x ∈ ⟦x_{k+1} | y_{0:T}⟧ ⊕ Γ_k⟦−w_k⟧ − u_k }   (15), (25)

The second form is one generalized intersection, exact for any Φ_k (singular included: the preimage
keeps the kernel directions that (16) adds explicitly). With constrained zonotopes it is exactly
Proposition 1, eq. (24).

Two ways to compute the same sets (``method="auto"`` picks the second whenever it applies):

* ``method="recursion"``: the backward recursion above, on any representation;
* ``method="trajectory"``: every smoothed range is a coordinate projection of one set, the set of all
  trajectories (x_0, …, x_T) consistent with y_{0:T} (`trajectory_set`). It is assembled once, with
  O(T) variables and constraints, and shared by all projections: a sparse extended CZ when X0, W and
  V flatten to CZs, otherwise one CVXPY problem compiled once (`TrajectorySet`), so horizons of
  hundreds of steps stay cheap for any representation.
"""

from __future__ import annotations

from typing import Any

from .._validation import check_system, measured
from ..filters._polygon_form import noise_polygon
from ..filters.classical import classical_filter, first_inconsistency
from ..filters.consistency import check_on_inconsistent, report_inconsistency
from ..filters.steps import _check_state_set
from ..results import SetEstimates
from ..sets.algebra import generalized_intersection, minkowski_sum, translate
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet
from ..sets.polygon import Polygon
from ..trajectories import trajectory_set
from ..trajectories.posterior_views import smoothed_ranges_from_trajectories
from ..trajectories.recursion_certificates import certified_against_data

_METHODS = ("auto", "recursion", "trajectory")


def optimal_smoother(system, X0: ConvexSet, ys: Any, *, method: str = "auto",
                     posteriors: list[ConvexSet] | None = None,
                     on_inconsistent: str = "warn") -> SetEstimates:
    """Smoothed ranges ⟦x_k | y_{0:T}⟧ for k = 0..T (smoothing paper Corollary 1, Algorithm 1).

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
        Initial prior range ⟦x_0⟧.
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T.
    method : {'auto', 'recursion', 'trajectory'}
        'recursion': the backward recursion of Algorithm 1 (any representation). 'trajectory':
        projections of the trajectory set (`setsmooth.trajectories.trajectory_set`, any
        representation), the same sets with O(T) instead of O(T²) constraints (36× faster certified
        hulls at T = 50 for CZs, ``benchmarks/bench_smoothing.py``; for sets without a CZ form one
        compiled CVXPY problem, ``benchmarks/bench_long_horizon.py``). 'auto' (default): the
        trajectory form unless ``posteriors`` are given, the recursion then.
    posteriors : list of ConvexSet, optional
        Output of `classical_filter` for the same data, to avoid filtering twice. Only the recursion
        uses them ('auto' then takes the recursion). A `SetEstimates` is checked against
        ``system``, ``X0`` and ``ys``; outer bounds (a reduced filter) give outer bounds.
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when the data contradict the model. Every smoothed set is then empty (no
        trajectory explains y_{0:T}), which one emptiness program on ⟦x_T | y_{0:T}⟧ decides; the
        sets are returned as `EmptySet`s, and 'warn' issues a `ModelInvalidationWarning` naming the
        filter's first empty step, its measurement and its distance from the predicted output set
        (`first_inconsistency`, from ``posteriors`` when they are the exact filter's); 'raise' raises
        `ModelInvalidatedError`; 'ignore' skips the check. With outer-bound ``posteriors`` an empty
        last posterior proves the inconsistency too; a non-empty one proves nothing.

    Returns
    -------
    SetEstimates
        A list of sets, ``smoothed[k]`` = ⟦x_k | y_{0:T}⟧ (``smoothed[T]`` is the last posterior),
        with interval-hull tubes and the data it was computed from.

    Raises
    ------
    TypeError
        When ``system`` is not a setsmooth system (a `control.StateSpace`: see
        `LinearSystem.from_statespace`).
    ValueError
        For an unknown ``method``, ``posteriors`` with ``method='trajectory'`` (that form never reads
        them), or ``posteriors`` of the wrong length or computed from other data (another system
        object, other measurements or another X0), or an ``X0`` that is not a set of dimension n;
        `ModelInvalidatedError` (a ValueError) for inconsistent data with
        ``on_inconsistent='raise'``.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> smoothed = ss.optimal_smoother(system, ss.Box([-5.0], [5.0]), [[0.0], [3.0]])
    >>> [S.interval_hull().hi.round(6).tolist() for S in smoothed]   # y_1 = 3 pins x_1 = 2, x_0 = 1
    [[1.0], [2.0]]
    """
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    if method == "trajectory" and posteriors is not None:
        raise ValueError("posteriors= is only used by method='recursion'; the trajectory form never "
                         "reads them (pass method='recursion', or drop posteriors)")
    check_on_inconsistent(on_inconsistent)
    given, as_given = system, ys   # the inconsistency is reported in the user's terms (y_k with D u_k)
    system, ys = measured(system, ys)
    if method == "auto":
        method = "trajectory" if posteriors is None else "recursion"
    if method == "trajectory":
        _check_state_set(X0, "X0", system.n)
        smoothed = SetEstimates(smoothed_ranges_from_trajectories(trajectory_set(system, X0, ys), system.n),
                                system=system, X0=X0, ys=ys, kind="smoothed")
        report_inconsistency(_emptied(smoothed, given, X0, as_given, None, on_inconsistent), on_inconsistent)
        return smoothed
    if posteriors is None:   # Algorithm 1 reads these CZs; the smoother reports inconsistency itself
        posteriors = classical_filter(system, X0, ys, form="recursion", on_inconsistent="ignore")
    elif len(posteriors) != len(ys):
        raise ValueError(f"posteriors must hold one set per measurement ({len(ys)}), got {len(posteriors)}")
    if isinstance(posteriors, SetEstimates):
        posteriors.check_same_data(system, X0, ys)
    deviations = getattr(posteriors, "_recursion_deviations", None)
    if deviations is not None and deviations.matches(posteriors):
        # The filter's recursion ran about the nominal trajectory: so does the backward pass (the
        # same sets, `setsmooth.trajectories.nominal`).
        smoothed = deviations.form.to_states(smooth(deviations.form.system, deviations.deviations))
    else:
        smoothed = smooth(system, posteriors)
    outer = getattr(posteriors, "outer", False)
    if isinstance(posteriors, SetEstimates) and not outer:
        # Exact sets of these data: certified against the data
        # (`setsmooth.trajectories.recursion_certificates`).
        smoothed = certified_against_data(smoothed, system, X0, ys, "smoothed")
    smoothed = SetEstimates(smoothed, system=system, X0=X0, ys=ys, kind="smoothed", outer=outer)
    report_inconsistency(_emptied(smoothed, given, X0, as_given, posteriors, on_inconsistent),
                         on_inconsistent)
    return smoothed


def _emptied(smoothed: SetEstimates, system, X0: ConvexSet, ys, posteriors, on_inconsistent: str):
    """When ⟦x_T | y_{0:T}⟧ is empty every smoothed set is (no trajectory explains the data): mark them
    `EmptySet` and return the filter's first inconsistency; else None (also with 'ignore').

    ``system`` and ``ys`` are as the user gave them, so the inconsistency quotes y_k with its
    feedthrough D_k u_k, as the filter's does (`first_inconsistency` takes it off again)."""
    if on_inconsistent == "ignore" or not len(smoothed) or not smoothed[-1].is_empty():
        return None
    smoothed[:] = [EmptySet(system.n) for _ in range(len(smoothed))]
    exact = isinstance(posteriors, SetEstimates) and not posteriors.outer
    return first_inconsistency(system, X0, ys, posteriors if exact else None)


def smooth(system, posteriors: list[ConvexSet]) -> list[ConvexSet]:
    """The backward pass of smoothing Algorithm 1 on given posteriors (any representation).

    Parameters
    ----------
    system : LinearSystem
    posteriors : list of ConvexSet
        ⟦x_k | y_{0:k}⟧ for k = 0..T, each of dimension n (validated once, before the loop).

    Returns
    -------
    list of ConvexSet
        ``smoothed[k]`` = ⟦x_k | y_{0:T}⟧.
    """
    check_system(system)
    if len(posteriors) < 1:
        raise ValueError("posteriors must hold at least one set")
    for k, P in enumerate(posteriors):
        _check_state_set(P, f"posteriors[{k}]", system.n)
    T = len(posteriors) - 1
    smoothed: list[ConvexSet] = [posteriors[T]]
    for k in range(T - 1, -1, -1):
        smoothed.append(_smoothing_step(system, k, posteriors[k], smoothed[-1]))
    return smoothed[::-1]


def smoothing_step(system, k: int, posterior: ConvexSet, next_smoothed: ConvexSet) -> ConvexSet:
    """⟦x_k | y_{0:T}⟧ from ⟦x_k | y_{0:k}⟧ and ⟦x_{k+1} | y_{0:T}⟧ (smoothing (15)/(25); CZ: (24)).

    Parameters
    ----------
    system : LinearSystem
    k : int
    posterior : ConvexSet
        ⟦x_k | y_{0:k}⟧, of dimension n.
    next_smoothed : ConvexSet
        ⟦x_{k+1} | y_{0:T}⟧, of dimension n.

    Returns
    -------
    ConvexSet
        {x ∈ posterior : A_k x ∈ next_smoothed ⊕ E_k(−W) − B_k u_k}; E_k(−W) is the system's cached
        image when E is constant, and a zero B_k u_k adds no translation.
    """
    _check_state_set(posterior, "posterior", check_system(system).n)
    _check_state_set(next_smoothed, "next_smoothed", system.n)
    return _smoothing_step(system, k, posterior, next_smoothed)


def _smoothing_step(system, k: int, posterior: ConvexSet, next_smoothed: ConvexSet) -> ConvexSet:
    # Trusted operands (matrices validated by the LinearSystem, sets by the public door), so the set
    # algebra is called directly. An empty next_smoothed needs no case here: the algebra absorbs it.
    noise = system.process_noise_image(k, negated=True)
    if isinstance(next_smoothed, Polygon):
        # Polygons charge every rounding to their pad; the algebra's image E_k(−W) is computed in
        # floating point, so its polygon comes with that rounding charged too.
        noise = noise_polygon(system, k, negated=True) or noise
    reachable_from = minkowski_sum(next_smoothed, noise)
    u = system.nonzero_input(k)
    if u is not None:
        reachable_from = translate(reachable_from, -u)
    return generalized_intersection(posterior, system.A_at(k), reachable_from)
