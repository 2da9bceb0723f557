"""Stability of the classical linear SMF (Algorithm 1) w.r.t. its initial condition: stability paper
Theorem 2 (stability criterion), Proposition 2 (necessary condition for a bounded gap) and
Corollary 1 (detectability suffices), checked for a given system and initial condition.

Each check returns a `CriterionResult` listing its conditions, whether each holds and why, and what
the statement then concludes. Theorem 2 and Corollary 1 are sufficient conditions: when they fail,
the result says so and does not claim instability (except where Proposition 2 gives it).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_matrix
from ..tolerances import MEMBERSHIP_TOL, RANK_TOL
from .observability import (ObservabilityDecomposition, is_marginally_stable, observability_decomposition,
                            spectral_radius)

__all__ = ["Condition", "CriterionResult", "check_stability_criterion", "check_bounded_gap_necessary",
           "check_egregium", "contains_set", "condition_i", "condition_ii"]

#: Largest dimension whose box corners are enumerated for a containment check (2^12 memberships).
_MAX_CORNER_DIM = 12


@dataclass(frozen=True)
class Condition:
    """One condition of a statement: its name, whether it holds, and why."""

    name: str
    holds: bool
    reason: str


@dataclass(frozen=True)
class CriterionResult:
    """The verdict of Theorem 2, Proposition 2 or Corollary 1 for one system and initial condition.

    Attributes
    ----------
    statement : str
        Which result of the paper was checked.
    conditions : tuple of Condition
    holds : bool
        Whether all conditions hold.
    conclusion : str
        What the statement then says about Algorithm 1 (or that it says nothing).
    """

    statement: str
    conditions: tuple[Condition, ...]
    holds: bool
    conclusion: str

    def __str__(self) -> str:
        lines = [f"{self.statement}: {'holds' if self.holds else 'does not hold'}"]
        lines += [f"  {c.name}: {'yes' if c.holds else 'no'} - {c.reason}" for c in self.conditions]
        lines.append(f"  => {self.conclusion}")
        return "\n".join(lines)


# -- containment of convex sets ---------------------------------------------------------------------

def _corners(S) -> np.ndarray | None:
    from ..sets import Box
    if isinstance(S, Box) and S.is_bounded and S.dim <= _MAX_CORNER_DIM:
        return np.array([[S.hi[i] if bit else S.lo[i] for i, bit in enumerate(bits)]
                         for bits in itertools.product((0, 1), repeat=S.dim)])
    if S.dim == 2:
        return S.vertices_2d()
    if S.dim == 1:
        hull = S.interval_hull()
        return np.array([hull.lo, hull.hi])
    return None


def contains_set(outer, inner, *, inner_map: Any = None, outer_map: Any = None) -> bool:
    """Whether M_o·outer ⊇ M_i·inner for convex sets (maps default to the identity), exactly.

    Decided by one of two exact routes: the vertices of ``inner`` (box corners up to dimension 12, or
    the polygon of a 2-D set, or the ends of an interval), mapped, must lie in the mapped outer set;
    or, when the mapped outer set has at most two dimensions, its polygon's (or interval's) facets
    must bound the support function of the mapped inner set. Membership uses the default margin.

    Raises
    ------
    NotImplementedError
        When neither route applies (no enumerable vertices and a mapped outer set of dimension > 2).
    """
    Mi = None if inner_map is None else as_matrix(inner_map, "inner_map", cols=inner.dim)
    Mo = None if outer_map is None else as_matrix(outer_map, "outer_map", cols=outer.dim)
    inner_m = inner if Mi is None else Mi @ inner
    outer_m = outer if Mo is None else Mo @ outer
    if inner_m.dim != outer_m.dim:
        raise ValueError(f"mapped sets differ in dimension: {inner_m.dim} and {outer_m.dim}")
    if inner.is_empty():
        return True
    if outer_m.is_empty():
        return False
    corners = _corners(inner)
    if corners is not None:
        points = corners if Mi is None else corners @ Mi.T
        return all(outer_m.contains(p) for p in points)
    if outer_m.dim <= 2:
        if outer_m.dim == 1:
            hull = outer_m.interval_hull()
            H, g = np.array([[1.0], [-1.0]]), np.array([hull.hi[0], -hull.lo[0]])
        else:
            V = outer_m.vertices_2d()
            E = np.roll(V, -1, axis=0) - V
            H = np.column_stack([E[:, 1], -E[:, 0]])              # outward normals (counter-clockwise)
            g = np.einsum("ij,ij->i", H, V)
        support = inner_m.support_many(H)
        return bool(np.all(support <= g + MEMBERSHIP_TOL * (1.0 + np.abs(g))))
    raise NotImplementedError(f"containment of {type(inner).__name__} in {type(outer).__name__} "
                              f"in dimension {outer_m.dim} needs enumerable vertices of the inner set")


# -- the conditions -------------------------------------------------------------------------------

def _decomposition(A: Any, C: Any, decomposition: ObservabilityDecomposition | None
                   ) -> ObservabilityDecomposition:
    if decomposition is not None:
        if not isinstance(decomposition, ObservabilityDecomposition):
            raise TypeError("decomposition must be an ObservabilityDecomposition, got "
                            f"{type(decomposition).__name__}")
        return decomposition
    return observability_decomposition(A, C)


def condition_i(dec: ObservabilityDecomposition, initial_condition, true_initial_set) -> Condition:
    """Theorem 2 (i): P_o⟦x̂_0⟧ ⊇ P_o⟦x_0⟧ (the observable part of the initial condition is right)."""
    for name, S in (("initial_condition", initial_condition), ("true_initial_set", true_initial_set)):
        if getattr(S, "dim", None) != dec.n:
            raise ValueError(f"{name} must be a ConvexSet of dimension n = {dec.n}")
    if dec.n_o == 0:
        return Condition("(i)", True, "n_o = 0: there is no observable part to contain")
    ok = contains_set(initial_condition, true_initial_set, inner_map=dec.P_o, outer_map=dec.P_o)
    why = ("P_o x̂_0-range contains P_o x_0-range" if ok else
           "some observable coordinate x̃^o_0 of the true initial set lies outside the initial "
           "condition's projection, so the estimate can become empty (ill-posed)")
    return Condition("(i)", ok, why)


def _sum_bounded(A_obar: np.ndarray, A_21: np.ndarray) -> tuple[bool, str]:
    """sup_k ‖Σ_{j<k} Ã_ō^j Ã_21‖ < ∞, given Ã_ō marginally stable.

    With eigenvalue 1 semisimple, ℝ^{n_ō} = ker(Ã_ō − I) ⊕ range(Ã_ō − I), both invariant; on the
    range Σ_{j<k} Ã_ō^j = (Ã_ō^k − I)(Ã_ō − I)⁻¹ stays bounded, on the kernel it grows like k. So the
    sum is bounded iff range(Ã_21) ⊆ range(Ã_ō − I).
    """
    N = A_obar - np.eye(A_obar.shape[0])
    aug = np.hstack([N, A_21])
    tol = RANK_TOL * max(1.0, np.linalg.norm(aug, 2)) * sum(aug.shape)
    r_N = int(np.sum(np.linalg.svd(N, compute_uv=False) > tol))
    r_aug = int(np.sum(np.linalg.svd(aug, compute_uv=False) > tol))
    if r_aug == r_N:
        return True, "range(Ã_21) ⊆ range(Ã_ō − I), so Σ_j Ã_ō^j Ã_21 stays bounded"
    return False, ("Ã_21 has a component along the eigenvalue 1 of Ã_ō, so Σ_j Ã_ō^j Ã_21 grows "
                   "linearly in k")


def condition_ii(dec: ObservabilityDecomposition) -> Condition:
    """Theorem 2 (ii): lim_k (Ã_ō^k + Σ_{i<k} Ã_ō^{k−1−i} Ã_21) < ∞.

    The two terms have different shapes (n_ō×n_ō, n_ō×n_o); read, as the proof uses them, as both
    staying bounded: Ã_ō marginally stable and sup_k ‖Σ_{j<k} Ã_ō^j Ã_21‖ < ∞.
    """
    if dec.n_obar == 0:
        return Condition("(ii)", True, "(A, C) is observable: there is no unobservable part")
    A_obar, A_21 = dec.A_obar, dec.A_21
    rho = spectral_radius(A_obar)
    if rho < 1.0 and not np.isclose(rho, 1.0, rtol=0, atol=1e-9):
        return Condition("(ii)", True, f"ρ(Ã_ō) = {rho:.6g} < 1: both terms converge")
    if not is_marginally_stable(A_obar):
        return Condition("(ii)", False, f"Ã_ō is not marginally stable (ρ = {rho:.6g}, or a defective "
                                        "eigenvalue on the unit circle): Ã_ō^k is unbounded")
    ok, why = _sum_bounded(A_obar, A_21)
    return Condition("(ii)", ok, "Ã_ō is marginally stable and " + why)


def _bounded(S, name: str) -> Condition:
    hull = S.interval_hull()
    ok = bool(hull.is_empty() or np.all(np.isfinite(hull.lo)) and np.all(np.isfinite(hull.hi)))
    return Condition(f"{name} bounded", ok, "its interval hull is finite" if ok else
                     "its interval hull is unbounded")


def check_stability_criterion(A: Any, C: Any, initial_condition, true_initial_set, *,
                              decomposition: ObservabilityDecomposition | None = None) -> CriterionResult:
    """Theorem 2 (stability criterion) of the stability paper for Algorithm 1 started at ``initial_condition``.

    Parameters
    ----------
    A, C : array_like
        System and output matrices (n×n, m×n).
    initial_condition : ConvexSet
        ⟦x̂_0⟧, the designer's initial condition.
    true_initial_set : ConvexSet
        ⟦x_0⟧, the true range of the initial state.
    decomposition : ObservabilityDecomposition, optional
        A decomposition (17) to use (computed from (A, C) otherwise); the verdict does not depend on it.

    Returns
    -------
    CriterionResult
        With conditions (i) and (ii); when both hold Algorithm 1 is stable (well-posed, bounded gap).

    Raises
    ------
    ValueError
        When a set's dimension is not n.
    NotImplementedError
        When (i) cannot be decided exactly: the true initial set is neither a box (n ≤ 12) nor 2-D and
        the observable part has more than two dimensions (see `contains_set`).

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth import analysis
    >>> A, C = [[1.0, 1.0], [0.0, 1.0]], [[1.0, 0.0]]
    >>> david = analysis.check_stability_criterion(A, C, ss.Box([-2, -2], [2, 2]), ss.Box([1, 1], [3, 3]))
    >>> david.holds, david.conditions[0].holds
    (False, False)
    """
    dec = _decomposition(A, C, decomposition)
    conds = (condition_i(dec, initial_condition, true_initial_set), condition_ii(dec))
    holds = all(c.holds for c in conds)
    if holds:
        conclusion = "Algorithm 1 is stable w.r.t. the initial condition: well-posed with a bounded gap"
    elif not conds[0].holds:
        conclusion = ("Theorem 2 does not apply: without (i) the estimate may become empty "
                      "(ill-posed); the theorem is only sufficient")
    else:
        conclusion = "Theorem 2 does not apply: the estimation gap is not guaranteed to stay bounded"
    return CriterionResult("Theorem 2 (stability criterion)", conds, holds, conclusion)


def check_bounded_gap_necessary(A: Any, C: Any, initial_condition, true_initial_set, *,
                                decomposition: ObservabilityDecomposition | None = None) -> CriterionResult:
    """Proposition 2: for bounded ⟦x̂_0⟧ with (i), a bounded gap requires Ã_ō marginally stable.

    Returns
    -------
    CriterionResult
        Conditions: ⟦x̂_0⟧ bounded, (i), Ã_ō marginally stable. When the first two hold and the third
        fails, the conclusion is that the estimation gap is not bounded for all such initial conditions.
    """
    dec = _decomposition(A, C, decomposition)
    bounded = _bounded(initial_condition, "⟦x̂_0⟧")
    cond_i = condition_i(dec, initial_condition, true_initial_set)
    if dec.n_obar == 0:
        marginal = Condition("Ã_ō marginally stable", True, "n_ō = 0")
    else:
        ok = is_marginally_stable(dec.A_obar)
        marginal = Condition("Ã_ō marginally stable", ok,
                             "every eigenvalue in the closed unit disk, those on the circle "
                             "non-defective" if ok else "an eigenvalue outside the unit disk or a "
                             "defective one on the unit circle")
    conds = (bounded, cond_i, marginal)
    holds = all(c.holds for c in conds)
    if not (bounded.holds and cond_i.holds):
        conclusion = "Proposition 2 does not apply (it assumes a bounded initial condition with (i))"
    elif marginal.holds:
        conclusion = "the necessary condition for a bounded estimation gap is met (it is not sufficient)"
    else:
        conclusion = "the estimation gap cannot be bounded for every such initial condition (Proposition 2)"
    return CriterionResult("Proposition 2 (necessary condition for a bounded gap)", conds, holds, conclusion)


def check_egregium(A: Any, C: Any, initial_condition, true_initial_set, *,
                   decomposition: ObservabilityDecomposition | None = None) -> CriterionResult:
    """Corollary 1 (Egregium): bounded ⟦x̂_0⟧ with (i) and (A, C) detectable ⇒ stable, uniformly bounded.

    Returns
    -------
    CriterionResult
        Conditions: ⟦x̂_0⟧ bounded, (i), detectable (ρ(Ã_ō) < 1).
    """
    dec = _decomposition(A, C, decomposition)
    rho = spectral_radius(dec.A_obar) if dec.n_obar else 0.0
    detect = Condition("(A, C) detectable", dec.is_detectable,
                       f"ρ(Ã_ō) = {rho:.6g}" + (" < 1" if dec.is_detectable else " ≥ 1"))
    conds = (_bounded(initial_condition, "⟦x̂_0⟧"), condition_i(dec, initial_condition, true_initial_set),
             detect)
    holds = all(c.holds for c in conds)
    conclusion = ("Algorithm 1 is stable w.r.t. the initial condition and its estimate is uniformly "
                  "bounded" if holds else "Corollary 1 does not apply (it is only sufficient)")
    return CriterionResult("Corollary 1 (Egregium)", conds, holds, conclusion)
