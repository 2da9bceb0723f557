"""OIT-inspired filtering (stability paper Algorithm 2) and the OIT-CZ SMF (Algorithm 3).

Both are stable with respect to the initial condition (Theorems 3 and 4): the classical filter
(Algorithm 1) runs while k is small, an empty estimate is reset from a box in the observable
coordinates (Line 5), and from then on the estimate forgets the initial condition's observable part.

Line 5 (θ-doubling). θ starts at 1 and doubles until the estimate is non-empty, each verdict one
emptiness program (`ConvexSet.is_empty`, decided against ``EMPTINESS_TOL``).

Lemma 1 (θ̄_k). For k ≥ k_* the filter started from a box B_θ in the observable coordinates stops
changing once θ ≥ θ̄_k. With at least μ_o measurements in the window the observable part of the
window's start is bounded by the data alone, so for θ beyond that bound the box constraint is inactive
and the set *equals* the one started from θ = ∞ (every coordinate, not only P_o's): θ = ∞ (an
unbounded factor, Definition 7) is exactly Lemma 1's limit, with no tolerance to decide. Both filters
use it (Algorithm 2 Line 7 and Algorithm 3 Line 8 for δ̄ ≤ k < 2δ̄).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validation import measured
from ..results import SetEstimates, Tubes
from ..sets.algebra import cartesian_product, linear_map
from ..sets.box import Box
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet
from ..sets.reals import Reals
from ._oit_support import Structure, structure
from .classical import _first_empty
from .consistency import check_on_inconsistent, outer_inconsistency, report_inconsistency
from .steps import _check_state_set, _predict, _update

__all__ = ["oit_inspired_filter", "OITResult"]

#: Line 5 doubles θ at most this many times (θ ≤ 2⁶⁰) before declaring the data inconsistent.
MAX_DOUBLINGS = 60


@dataclass(frozen=True)
class OITResult(Tubes):
    """What `oit_cz_filter` returns: the `Estimates` protocol (``lo``, ``hi``, ``centers``,
    ``diameters()``, ``first_empty``, ``contains_trajectory``, ``plot_tubes``; ``result[k]`` is Z_k)
    and the algorithm's own record.

    ``lo`` and ``hi`` are the certified hulls computed during the run when ``hulls=True`` (with their
    timings), else the estimates' interval hulls, computed on first use. Every Z_k contains the exact
    posterior ⟦x_k | y_{0:k}⟧ from k = δ̄ on, so an empty Z_k proves the data inconsistent with the
    model; a non-empty one does not prove them consistent.

    Attributes
    ----------
    estimates : SetEstimates of ConstrainedZonotope
        Z_k for k = 0..T (extended CZs; from k = δ̄ on they all share one constraint matrix per
        window prior, see `setsmooth.filters._window`), with ``outer=True``.
    resets : list of int
        The steps k < δ̄ at which Z_k was empty and Line 5 reset it.
    thetas : dict
        θ used by each reset (k -> θ).
    delta_bar : int
    hulls : tuple of ndarray or None
        (lo, hi), shape (T+1, n): certified interval hulls of the estimates, when requested (and always
        computed for systems that are not observable, whose Lines 8–12 need them); NaN rows at empty
        estimates. ``lo`` and ``hi`` are the same arrays.
    alpha : ndarray, shape (T+1,)
        α_k of Line 12 for k ≥ δ̄ (NaN before, and for observable systems).
    c_obar : ndarray, shape (T+1, n − n_o)
        ĉ^ō_k of Line 11 for k ≥ δ̄ (NaN before): T̂^ō_k = B_{α_k}[ĉ^ō_k] in the coordinates x̃ = Px.
    step_seconds, hull_seconds : ndarray, shape (T+1,)
        CPU time (this process) of each step of the filter, and of the interval hull taken for ``hulls=True``
        after it (zero otherwise). For systems that are not observable every hull the algorithm
        needs is step time.
    """

    estimates: list
    resets: list
    thetas: dict
    delta_bar: int
    hulls: tuple | None = None
    alpha: np.ndarray = field(default_factory=lambda: np.zeros(0))
    c_obar: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    step_seconds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    hull_seconds: np.ndarray = field(default_factory=lambda: np.zeros(0))

    kind = "OIT-CZ"

    def __post_init__(self) -> None:
        if not isinstance(self.estimates, SetEstimates):
            object.__setattr__(self, "estimates", SetEstimates(self.estimates, kind=self.kind, outer=True))

    @property
    def lo(self) -> np.ndarray:
        """Lower edges of the interval hulls, shape (T+1, n); NaN rows at empty estimates."""
        return self.estimates.lo if self.hulls is None else self.hulls[0]

    @property
    def hi(self) -> np.ndarray:
        """Upper edges of the interval hulls, shape (T+1, n); NaN rows at empty estimates."""
        return self.estimates.hi if self.hulls is None else self.hulls[1]

    @property
    def system(self):
        return self.estimates.system

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray:
        """Whether each x_k lies in Z_k (exact membership; `SetEstimates.contains_trajectory`)."""
        return self.estimates.contains_trajectory(xs, tol)

    def __len__(self) -> int:
        return len(self.estimates)

    def __getitem__(self, k):
        return self.estimates[k]

    def __iter__(self):
        return iter(self.estimates)


def oit_inspired_filter(system, X0: ConvexSet, ys: Any, *, delta: int | None = None,
                        decomposition=None, on_inconsistent: str = "warn") -> SetEstimates:
    """Stability paper Algorithm 2 (OIT-inspired filtering) with exact sets of any representation.

    For k < k_s (k_s = ``delta``) the classical filter (Algorithm 1) from X0, where an empty estimate is
    reset by Line 5: F_{k,0}(P⁻¹(B_θ[0] × ⟦x̂_0^ō⟧)) with θ = 1, 2, 4, … until it is non-empty. At
    k = k_s, Line 7 with Lemma 1's θ̄_k = ∞ (exact, see the module docstring): F_{k_s,0}(P⁻¹(ℝ^{n_o} ×
    ⟦x̂_0^ō⟧)); afterwards Line 7 recursively, F_{k,0} = f_k ∘ F_{k−1,0} (the classical step).

    Parameters
    ----------
    system : LinearSystem
        Time-invariant A and C (the decomposition is of (A, C)).
    X0 : ConvexSet
        The initial condition ⟦x̂_0⟧ (bounded).
    ys : array_like, shape (T+1, m)
    delta : int, optional
        The switching time k_s ≥ k_* = max{μ_o − 1 + n_λ0, 1} of Lemma 1; default k_*.
    decomposition : optional
        An observability decomposition (`setsmooth.analysis.observability_decomposition`) to use
        instead of computing one (e.g. MATLAB's P of the paper's Fig. 3).
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when an estimate is empty, which no reset repairs: from k_s on every estimate
        contains the exact posterior, so the data contradict the model (a non-empty estimate does
        not prove them consistent; `setsmooth.filters.consistency`). Before k_s an empty estimate is
        reset (Line 5: the initial condition was wrong, not the model), unless no θ ≤ 2⁶⁰ gives a
        non-empty one. 'warn' issues a `ModelInvalidationWarning` naming the first such step, its
        measurement and its distance from the output set predicted from the estimate before it;
        'raise' raises `ModelInvalidatedError`. The estimates are `EmptySet` from there on.

    Returns
    -------
    SetEstimates
        The estimates ⟦x̂_k | y_{0:k}⟧, k = 0..T (``outer=True``).

    Raises
    ------
    ValueError
        If ``delta`` < k_* or the system is time varying; `ModelInvalidatedError` (a ValueError) for
        inconsistent data with ``on_inconsistent='raise'``.
    """
    given, system, ys = system, *measured(system, ys)
    _check_state_set(X0, "X0", system.n)
    check_on_inconsistent(on_inconsistent)
    st = _structure(system, decomposition)
    k_s = st.k_star if delta is None else _check_int(delta, "delta", st.k_star)
    T = ys.shape[0] - 1
    X0_obar = linear_map(st.P_obar, X0) if not st.observable else None
    estimates: list[ConvexSet] = []
    for k in range(T + 1):
        if k < k_s:
            prior = X0 if k == 0 else _predict(system, k - 1, estimates[-1])
            Z = _update(system, k, prior, ys[k])
            if Z.is_empty():
                reset = _reset(system, ys, k, st, X0_obar)
                if reset is None:  # no θ: the data contradict the model
                    estimates += [EmptySet(system.n) for _ in range(k, T + 1)]
                    break
                Z = reset[0]
        elif k == k_s:
            Z = _run(system, ys, 0, k, _prior_from(st, Reals(st.n_o), X0_obar))
        else:
            Z = _update(system, k, _predict(system, k - 1, estimates[-1]), ys[k])
        estimates.append(Z)
    if T >= k_s and not isinstance(estimates[-1], EmptySet):
        # From k_s on the estimates are one recursion: emptiness is monotone, settled by bisection.
        first = k_s + _first_empty(estimates[k_s:])
        estimates[first:] = [EmptySet(system.n) for _ in range(first, T + 1)]
    result = SetEstimates(estimates, system=system, X0=X0, ys=ys, kind="OIT-inspired", outer=True)
    if on_inconsistent != "ignore":
        report_inconsistency(outer_inconsistency(system, X0, ys, result, "OIT-inspired", given),
                             on_inconsistent)
    return result


# -- shared pieces -------------------------------------------------------------------------------------
def _structure(system, decomposition) -> Structure:
    if set(system.time_varying) & {"A", "C", "E", "F"}:
        raise ValueError("the OIT filters need a time-invariant system (constant A, C, E, F)")
    return structure(system.A_at(0), system.C_at(0), decomposition)


def _check_int(value: Any, name: str, lowest: int) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {value!r}")
    if value < lowest:
        raise ValueError(f"{name} must be >= k_* = max(mu_o - 1 + n_lambda0, 1) = {lowest} "
                         f"(Lemma 1), got {value}")
    return int(value)


def _prior_from(st: Structure, T_o: ConvexSet, T_obar: ConvexSet | None) -> ConvexSet:
    """P⁻¹(T_o × T_ō) (U = P⁻¹); T_o alone for observable systems."""
    if st.observable:
        return linear_map(st.U, T_o)
    return linear_map(st.U, cartesian_product(T_o, T_obar))


def _run(system, ys: np.ndarray, i: int, k: int, prior: ConvexSet) -> ConvexSet:
    """F_{k,i}(prior) by the classical recursion (stability (7)), exact in any representation."""
    return _run_with_prior(system, ys, i, k, prior)[0]


def _run_with_prior(system, ys: np.ndarray, i: int, k: int, prior: ConvexSet):
    """(F_{k,i}(prior), the prior at k it was updated from)."""
    Z = _update(system, i, prior, ys[i])
    for j in range(i + 1, k + 1):
        prior = _predict(system, j - 1, Z)
        Z = _update(system, j, prior, ys[j])
    return Z, prior


def _reset(system, ys: np.ndarray, k: int, st: Structure, X0_obar):
    """Line 5: F_{k,0}(P⁻¹(B_θ[0] × ⟦x̂_0^ō⟧)) for θ = 1, 2, 4, … until non-empty.

    Returns (Z_k, the prior at k it came from, θ), or None when no θ ≤ 2^MAX_DOUBLINGS gives a
    non-empty estimate: the measurements contradict the model.
    """
    theta = 1.0
    for _ in range(MAX_DOUBLINGS + 1):
        box = Box(np.full(st.n_o, -theta), np.full(st.n_o, theta))
        Z, prior = _run_with_prior(system, ys, 0, k, _prior_from(st, box, X0_obar))
        if not Z.is_empty():
            return Z, prior, theta
        theta *= 2.0
    return None

