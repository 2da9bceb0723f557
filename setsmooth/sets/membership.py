"""Membership margins relative to the set's own scale, and membership programs with per-coordinate margins.

``S.contains(p)`` without ``tol`` decides p ∈ S ⊕ [−m, m] for the margin vector

    m_i = MEMBERSHIP_TOL · w_i + MAGNITUDE_TOL · max(|p_i|, |lo_i|, |hi_i|),

where [lo, hi] is the interval hull of S (computed once and kept on the set) and w = hi − lo its
widths: a margin relative to the extent of the set in each coordinate, plus the rounding level of
the coordinates' magnitude. An absolute margin such as ``MEMBERSHIP_TOL · max(1, |p|)`` made a box of
width 1e-9 contain a point fifty widths away. Coordinates along which S is unbounded have no width;
they keep the absolute margin ``MEMBERSHIP_TOL · max(1, |p_i|)``.

A per-coordinate margin is decided in normalized coordinates x ↦ (x − p)/s with s = m/MEMBERSHIP_TOL, so
that every program sees a set of unit size and a margin ``MEMBERSHIP_TOL`` that its accuracy
(``SOLVER_TOL``) resolves, however small or large the set's own units are.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .. import tolerances as tol
from ..solvers import SolverError
from ..solvers.cvxpy_problems import solve_problem
from .base import ConvexSet

#: Smallest normalization scale: keeps (x − p)/s finite for a set that is a single point at 0.
_TINY_SCALE = float(np.sqrt(np.finfo(float).tiny))


def default_margins(S, p: np.ndarray, path: str = "auto") -> np.ndarray | None:
    """The default per-coordinate membership margins of ``S`` at ``p`` (None when S is empty).

    Parameters
    ----------
    S : ConvexSet
    p : ndarray, shape (S.dim,)
    path : {'auto', 'generic'}
        The path of the interval hull that sets the scale.

    Returns
    -------
    ndarray, shape (S.dim,) or None
        Positive margins, see the module docstring.
    """
    hull = S.interval_hull(path=path)
    if hull.is_empty():
        return None
    lo, hi = np.asarray(hull.lo, dtype=float), np.asarray(hull.hi, dtype=float)
    bounded = np.isfinite(lo) & np.isfinite(hi)
    with np.errstate(invalid="ignore"):
        width = np.where(bounded, hi - lo, 0.0)
    magnitude = np.max(np.abs(np.vstack([p, np.where(np.isfinite(lo), lo, 0.0),
                                         np.where(np.isfinite(hi), hi, 0.0)])), axis=0)
    margin = tol.MEMBERSHIP_TOL * width + tol.MAGNITUDE_TOL * magnitude
    unbounded = tol.MEMBERSHIP_TOL * np.maximum(1.0, np.abs(p))
    return np.where(bounded, np.maximum(margin, tol.MEMBERSHIP_TOL * _TINY_SCALE), unbounded)


def settled_without_hull(S, p: np.ndarray) -> bool | None:
    """The default membership verdict when two cheap programs settle it, else None.

    The interval hull behind `default_margins` costs 2·dim support programs when the set has no
    closed form for it (a constrained zonotope, an H-polytope); most points are settled without it:

    * inside with margin 0 ⟹ inside with any margin (one program);
    * for a CZ, outside with the margins of its generator box c ± Σ_j|G_ij|h_j, free factors at
      h_j = β ≥ ‖ξ_F‖∞ (the box contains the set, so its widths bound the hull's) ⟹ outside with
      the hull's margins.

    Only points within that bound of the boundary need the hull. Applies to sets whose membership
    program is solved in the set's own scale (CZ forms) or in closed form (H-polytopes); None for the
    others, and when the hull is cheap or already known.
    """
    hulls = getattr(S, "__dict__", {}).get("_interval_hulls", {})
    if ("auto", None) in hulls or _has_closed_form_hull(S):
        return None
    cz = S._flat_cz
    if cz is None:
        if getattr(S, "_exact_membership_form", False) and S._contains(p, 0.0):
            return True
        return None
    # Free factors (the states of a trajectory CZ) enter at their rigorous bound β ≥ ‖ξ_F‖∞
    # (`FactorConstraints.free_bound`, shared with the membership program's units), which the set's
    # points respect: the box below still contains the set.
    beta = cz.factors.cheap_free_bound()
    if beta is None or not np.isfinite(beta):
        return None
    h = np.asarray(cz.h)
    # Per coordinate, the generator box's half-width bounds the set's: the programs below run in
    # coordinates scaled by it, so a set thin along one axis is judged in that axis's units.
    reach = np.asarray(abs(cz.G) @ np.where(np.isfinite(h), h, beta)).ravel()
    magnitude = np.maximum(np.abs(p), np.abs(cz.c) + reach)
    scale = np.maximum(reach, np.maximum(tol.MAGNITUDE_TOL * magnitude, _TINY_SCALE))
    if cz._contains_normalized(p, scale, 0.0):
        return True
    upper = tol.MEMBERSHIP_TOL * 2 * reach + tol.MAGNITUDE_TOL * magnitude
    if not cz._contains(p, np.maximum(upper, tol.MEMBERSHIP_TOL * _TINY_SCALE)):
        return False
    return None


def _has_closed_form_hull(S) -> bool:
    return type(S).interval_hull is not ConvexSet.interval_hull


def normalization(p: np.ndarray, margin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(s, offset) of the normalized coordinates x ↦ (x − p)/s = x/s + offset, s = margin/MEMBERSHIP_TOL."""
    s = np.maximum(np.asarray(margin, dtype=float) / tol.MEMBERSHIP_TOL, _TINY_SCALE)
    return s, -p / s


def generic_contains(S, p: np.ndarray, margin) -> bool:
    """Membership by the generic CVXPY path, with a scalar or per-coordinate ∞-norm margin.

    Per-coordinate margins are decided by min{t : x = p + s∘y ∈ S, ‖y‖∞ ≤ t, t ≥ MEMBERSHIP_TOL}
    with s = margin/MEMBERSHIP_TOL: the set's constraints are stated at x = p + s∘y, so CVXPY folds
    the constants (a bound lo becomes lo − p) in floating point before the solver sees them, and
    the solver's accuracy applies to distances in units of s rather than to the coordinates'
    magnitude (a set of width 1e-9 placed at 1 is resolved).
    """
    if np.ndim(margin) == 0:
        return S._generic.contains(p, float(margin))
    s, _ = normalization(p, margin)
    try:
        return _normalized_distance_program(S, p, s, lambda y: p + cp.multiply(s, y), solve_problem)
    except SolverError:
        # The same program with x as its own variable: another conic form, which settled the
        # badly scaled cases (widths 1e3 and 1e-6 in one set) where the first stalled.
        def substituted(y):
            x = cp.Variable(S.dim)
            extra.append(x == p + cp.multiply(s, y))
            return x

        extra: list = []
        return _normalized_distance_program(S, p, s, substituted, solve_problem, extra)


def _normalized_distance_program(S, p, s, point, solve_problem, extra=None) -> bool:
    y, t = cp.Variable(S.dim), cp.Variable()
    x = point(y)
    # ±y ≤ t as linear rows rather than a norm: the conic form of ‖y‖∞ ≤ t stalled on sets whose
    # coordinates have widths 1e3 and 1e-6.
    cons = list(S.constraints(x)) + list(extra or []) + [y <= t, -y <= t, t >= tol.MEMBERSHIP_TOL]
    status = solve_problem(cp.Problem(cp.Minimize(t), cons), "deciding membership (generic path)",
                           "membership")
    if status == "infeasible":
        return False
    # t is in units of s, where the margin is MEMBERSHIP_TOL: the solver's accuracy is SOLVER_TOL.
    return bool(t.value <= tol.MEMBERSHIP_TOL + tol.SOLVER_TOL)
