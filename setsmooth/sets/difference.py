"""The Pontryagin (Minkowski) difference S ⊖ T = {x : x + T ⊆ S}.

Not ``S - T``: that operator is the Minkowski sum S ⊕ (−T) = {s − t}, which grows S, while S ⊖ T
shrinks it (for T ∋ 0). The two are related by (S ⊖ T) ⊕ T ⊆ S.

* S a `Box`: the box [lo + h_T(−e_i), hi − h_T(e_i)], **exact** for any bounded T.
* S an `HPolytope` {Hx ≤ k}: {x : Hx ≤ k − h_T(H_i)}, **exact** for any bounded T (one support
  value of T per row). Where T flattens to a constrained zonotope its support values are certified
  upper bounds, so the computed polytope lies inside the exact difference in floating point.
* S a constrained zonotope (or a set that flattens to one), T a `Box` or `Zonotope` Z(G_T, c_T)
  with m generators:

  - ``method='exact'``: S ⊖ T = ∩_v (S − v) over the vertices v of T, built as
    (((S − c_T) ⊖ [−g₁, g₁]) ⊖ [−g₂, g₂]) ⋯ with S′ ⊖ [−g, g] = (S′ − g) ∩ (S′ + g): exact, with
    2^m copies of S's factors (refused above ``MAX_EXACT_GENERATORS`` generators);
  - ``method='outer'``: ∩_p (S − p) over the 2n vertices p of T extreme along ±e_i: contains the
    exact difference (any points of T give an outer bound), 2n copies of S;
  - ``method='inner'``: Z(G, c − c_T, A, b, h − |Γ|𝟙) for a Γ with GΓ = G_T and AΓ = 0 (one LP
    choosing the least shrinking Γ): every x in it has x + T ⊆ S, since ξ + Γη is a factor of S
    for |η| ≤ 1. Contained in the exact difference; `EmptySet` when no such Γ exists.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol_policy
from ..solvers import SolverError
from ..solvers.cvxpy_problems import solve_problem
from .base import ConvexSet, _same_dim
from .box import Box
from .constrained_zonotope import ConstrainedZonotope
from .empty import EmptySet
from .hpolytope import HPolytope
from .reals import Reals
from .zonotope import Zonotope

#: Largest number of generators of T for the exact CZ difference (2^m copies of S).
MAX_EXACT_GENERATORS = 10

_METHODS = ("exact", "outer", "inner")


def pontryagin_difference(S, T, method: str = "exact"):
    """S ⊖ T = {x : x + T ⊆ S} (see the module docstring for what is exact).

    Parameters
    ----------
    S : Box, HPolytope, or a set that flattens to a constrained zonotope
    T : ConvexSet
        Bounded. Any such set for a Box or HPolytope S; a `Box` or `Zonotope` (or a CZ without
        constraints and with finite bounds) for a constrained-zonotope S.
    method : {'exact', 'outer', 'inner'}
        For a constrained-zonotope S only (the Box and H-polytope differences are always exact).

    Returns
    -------
    ConvexSet
        A Box, HPolytope or ConstrainedZonotope (`EmptySet` when empty in closed form; ℝⁿ as
        `Reals` when T is empty).

    Raises
    ------
    ValueError
        For an unknown ``method``, a dimension mismatch, an unbounded T, or more than
        ``MAX_EXACT_GENERATORS`` generators with ``method='exact'``.
    TypeError
        For an S or T these constructions do not cover.

    Examples
    --------
    >>> import setsmooth as ss
    >>> D = ss.Box([-2, -1], [2, 1]).pontryagin_difference(ss.Box([-0.5, -0.5], [0.5, 0.5]))
    >>> D.lo.tolist(), D.hi.tolist()
    ([-1.5, -0.5], [1.5, 0.5])
    """
    if not isinstance(S, ConvexSet) or not isinstance(T, ConvexSet):
        raise TypeError(f"the Pontryagin difference needs two ConvexSets, got {type(S).__name__} "
                        f"and {type(T).__name__}")
    _same_dim(S, T, "Pontryagin difference")
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    if T.is_empty():
        return Reals(S.dim)
    if isinstance(S, EmptySet):
        return S
    if isinstance(S, Box) or isinstance(S, HPolytope):
        H, k = (S.to_hpolytope().H, S.to_hpolytope().k) if isinstance(S, Box) else (S.H, S.k)
        shift = _bounded_support(T, np.asarray(H))
        if isinstance(S, Box):
            eye = np.eye(S.dim)
            lo = np.where(np.isfinite(S.lo), S.lo + _bounded_support(T, -eye), -np.inf)
            hi = np.where(np.isfinite(S.hi), S.hi - _bounded_support(T, eye), np.inf)
            return EmptySet(S.dim) if np.any(lo > hi) else Box._trusted(lo, hi)
        return HPolytope._trusted(np.asarray(H), np.asarray(k) - shift, S.dim)
    cz = S._flat_cz
    if cz is None:
        raise TypeError(f"the Pontryagin difference is built for a Box, an HPolytope or a set that "
                        f"flattens to a constrained zonotope; {type(S).__name__} is none of these")
    GT, cT = _zonotope_form(T)
    if method == "inner":
        return _inner(cz, GT, cT)
    if method == "outer":
        signs = np.sign(np.vstack([GT, -GT]))  # vertex extreme along ±e_i: c_T + G_T sign(±G_Tᵀe_i)
        signs[signs == 0] = 1.0
        points = np.unique(signs @ GT.T + cT, axis=0)
        return _intersect_translates(cz, points)
    if GT.shape[1] > MAX_EXACT_GENERATORS:
        raise ValueError(f"the exact difference with {GT.shape[1]} generators of T needs "
                         f"2^{GT.shape[1]} copies of S (at most {MAX_EXACT_GENERATORS} generators); "
                         "use method='inner' or 'outer'")
    out = cz._translate(-cT)
    for g in GT.T:
        if np.any(g):
            out = out._translate(-g)._generalized_intersection(np.eye(S.dim), out._translate(g))
    return out


def _bounded_support(T, D: np.ndarray) -> np.ndarray:
    """h_T on the rows of D: certified upper bounds where T flattens to a CZ; T must be bounded."""
    values = None
    if T._flat_cz is not None:
        try:
            values = T.support_many(D, certified=True)
        except (SolverError, ValueError):
            values = None
    if values is None:
        values = T.support_many(D)
    if not np.all(np.isfinite(values)):
        raise ValueError("the Pontryagin difference needs a bounded T")
    return values


def _zonotope_form(T) -> tuple[np.ndarray, np.ndarray]:
    """(G_T, c_T) of a Box, Zonotope or unconstrained CZ with finite bounds."""
    if isinstance(T, Box):
        if not T.is_bounded:
            raise ValueError("the Pontryagin difference needs a bounded T")
        T = T.to_zonotope()
    if isinstance(T, Zonotope):
        return np.asarray(T.G), np.asarray(T.c)
    if isinstance(T, ConstrainedZonotope) and T.nc == 0:
        if not np.isfinite(T.h).all():
            raise ValueError("the Pontryagin difference needs a bounded T")
        G = T.G.toarray() if sp.issparse(T.G) else np.asarray(T.G)
        return G * T.h, np.asarray(T.c)
    raise TypeError(f"the Pontryagin difference of a constrained zonotope is built for T a Box or a "
                    f"Zonotope; got {type(T).__name__}")


def _intersect_translates(cz, points: np.ndarray):
    """∩_p (Z − p), as one CZ."""
    out = cz._translate(-points[0])
    for p in points[1:]:
        out = out._generalized_intersection(np.eye(cz.dim), cz._translate(-p))
    return out


def _inner(cz, GT: np.ndarray, cT: np.ndarray):
    """Z(G, c − c_T, A, b, h − |Γ|𝟙) for the least-shrinking Γ with GΓ = G_T, AΓ = 0."""
    G = cz.G.toarray() if sp.issparse(cz.G) else np.asarray(cz.G)
    A = cz.A.toarray() if sp.issparse(cz.A) else np.asarray(cz.A)
    h = np.asarray(cz.h)
    bounded = np.flatnonzero(np.isfinite(h))
    Gam = cp.Variable((cz.ng, GT.shape[1]))
    cons = [G @ Gam == GT]
    if cz.nc:
        cons.append(A @ Gam == 0)
    load = cp.sum(cp.abs(Gam[bounded]), axis=1) if bounded.size else None
    if load is not None:
        cons.append(load <= h[bounded])
        objective = cp.Minimize(cp.sum(cp.multiply(1.0 / np.maximum(h[bounded], np.finfo(float).tiny),
                                                   load)))
    else:
        objective = cp.Minimize(0)
    try:
        status = solve_problem(cp.Problem(objective, cons), "inner Pontryagin difference", "difference")
    except SolverError:
        status = "failed"
    if status != "optimal":
        return EmptySet(cz.dim)
    gamma = np.asarray(Gam.value)
    # The solver's Γ meets GΓ = G_T and AΓ = 0 to its accuracy: the inner bound holds up to that
    # residual, which is checked against SOLVER_CHECK_TOL relative to G_T.
    residual = np.abs(G @ gamma - GT).max(initial=0.0)
    scale = max(np.abs(GT).max(initial=0.0), 1e-300)
    if residual > tol_policy.SOLVER_CHECK_TOL * scale:
        return EmptySet(cz.dim)
    shrink = np.abs(gamma).sum(axis=1)
    new_h = np.where(np.isfinite(h), h - shrink, np.inf)
    if np.any(new_h < -tol_policy.SOLVER_CHECK_TOL * np.where(np.isfinite(h), np.maximum(h, 1.0), 1.0)):
        return EmptySet(cz.dim)
    new_h = np.maximum(new_h, 0.0)
    return ConstrainedZonotope._trusted(cz.G, np.asarray(cz.c) - cT, cz.A, cz.b, new_h)
