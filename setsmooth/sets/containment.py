"""Set containment S ⊆ T, decided by support functions where a convex program decides it.

* T with an H-representation {x : Hx ≤ k} (`Box`, `HPolytope`, ℝⁿ): S ⊆ T ⟺ h_S(H_i) ≤ k_i for every
  row, one support program of S per row: **exact**, for any S. Where S flattens to a constrained
  zonotope the values are certified upper bounds (weak duality), so a verdict "contained" holds in
  floating point.
* T a `Zonotope` (or a CZ without constraints and with finite bounds): the same test on the facets of
  T (the normals of every n − 1 generators, within the affine hull of T): **exact**, as long as T has
  at most ``MAX_ZONOTOPE_FACETS`` candidate facets.
* T a constrained zonotope: S ⊆ T for a CZ S by the **sufficient** linear condition below (an LP);
  a failed test proves nothing unless a support value of S exceeds T's interval hull, which proves
  S ⊄ T. With Z_i = {G_i ξ + c_i : A_i ξ = b_i, |ξ| ≤ h_i}, Z₁ ⊆ Z₂ when there are Γ, β, Λ₁, Λ₂ with

      G₁ = G₂Γ + Λ₁A₁,   c₁ − c₂ = G₂β − Λ₁b₁,   A₂Γ = Λ₂A₁,   A₂β − b₂ = −Λ₂b₁,
      Σ_j |Γ_ij| h₁_j + |β_i| ≤ h₂_i,

  because then ξ₂ = Γξ₁ + β maps every factor of Z₁ to a factor of Z₂ naming the same point (the
  zonotope-containment condition of Sadraddini and Tedrake, extended here to constraints and to
  the factor bounds h ∈ [0, ∞]).

Every test returns a `Containment`, truthy when containment is established, which says whether the
test was exact. Tolerances: ``h_S(H_i) ≤ k_i + Σ_j |H_ij| m_j`` with the margins m of
`ConvexSet.contains` (relative to T's own scale) or the absolute ∞-norm ``tol`` given.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from math import comb

import cvxpy as cp
import numpy as np
import scipy.linalg
import scipy.sparse as sp

from .. import tolerances as tol_policy
from .._validation import real_number
from ..solvers import SolverError
from ..solvers.cvxpy_problems import solve_problem
from .base import ConvexSet, _same_dim
from .constrained_zonotope import ConstrainedZonotope
from .empty import EmptySet
from .hpolytope import _as_hpolytope
from .membership import default_margins
from .zonotope import Zonotope

#: Largest number of (n−1)-subsets of generators enumerated for the exact zonotope test; above it
#: the sufficient CZ test is used.
MAX_ZONOTOPE_FACETS = 20_000


@dataclass(frozen=True)
class Containment:
    """The answer of a containment test S ⊆ T; ``bool(answer)`` is ``contained``.

    Attributes
    ----------
    contained : bool
        True: S ⊆ T is established (up to the tolerance). False: with ``exact`` it is refuted;
        without, it is only not established (the sufficient test failed).
    exact : bool
        Whether the test decides containment both ways (an H-representation or zonotope facets of
        T), or only a sufficient condition was tested (False).
    certified : bool
        Whether a True verdict rests on floating-point upper bounds of S's support values
        (weak duality), so that it holds however the solver performed.
    violation : float
        How far containment fails: the largest excess of S over T's faces per unit ∞-norm margin,
        max_i (h_S(H_i) − k_i)/‖H_i‖₁ (≤ 0 when contained); for the sufficient CZ test
        max_i(Σ_j|Γ_ij|h₁_j + |β_i|)/h₂_i − 1. ``inf`` when S is unbounded along a face, ``nan``
        when the sufficient test failed without a certificate of non-containment.
    method : str
        'empty', 'halfspaces', 'zonotope facets', 'cz sufficient' or 'interval hull'.
    """

    contained: bool
    exact: bool
    certified: bool
    violation: float
    method: str

    def __bool__(self) -> bool:
        return self.contained


def is_subset(S, T, tol: float | None = None) -> Containment:
    """Decide S ⊆ T (exactly where T has an H-representation or is a zonotope).

    Parameters
    ----------
    S, T : ConvexSet
        Of the same dimension. T a `Box`, `HPolytope`, `Reals`, `EmptySet`, `Zonotope` (exact for
        any S), or any set that flattens to a constrained zonotope (a sufficient test, for S that
        flattens to one too).
    tol : float, optional
        Absolute ∞-norm margin: S ⊆ T ⊕ [−tol, tol]ⁿ is tested. By default relative to T's scale,
        the margins of `ConvexSet.contains`.

    Returns
    -------
    Containment

    Raises
    ------
    TypeError
        When T has no representation these tests cover (an ellipsoid, a lazy set of those), or T
        is a constrained zonotope and S does not flatten to one.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope([[1.0, 1.0], [0.0, 1.0]], [0.0, 0.0])
    >>> bool(Z.is_subset(ss.Box([-2, -1], [2, 1]))), bool(ss.Box([-2, -1], [2, 1]) <= Z)
    (True, False)
    """
    if not isinstance(T, ConvexSet) or not isinstance(S, ConvexSet):
        raise TypeError(f"containment needs two ConvexSets, got {type(S).__name__} and {type(T).__name__}")
    _same_dim(S, T, "containment")
    if tol is not None:
        tol = real_number(tol, "tol")
        if not np.isfinite(tol) or tol < 0:
            raise ValueError(f"tol must be a finite non-negative number, got {tol}")
    if S.is_empty():
        return Containment(True, True, True, -np.inf, "empty")
    if isinstance(T, EmptySet) or T.is_empty():
        return Containment(False, True, False, np.inf, "empty")
    halfspaces = _halfspaces(T)
    if halfspaces is not None:
        H, k, method = halfspaces
        return _halfspace_test(S, T, H, k, tol, method)
    cz_T = T._flat_cz
    if cz_T is None:
        raise TypeError(f"S ⊆ T is decided for T with an H-representation, a zonotope or a constrained "
                        f"zonotope; {type(T).__name__} is none of these")
    cz_S = S._flat_cz
    if cz_S is None:
        raise TypeError(f"S ⊆ T for a constrained zonotope T is tested for S that flattens to a "
                        f"constrained zonotope; {type(S).__name__} does not")
    answer = _cz_sufficient(cz_S, cz_T, tol)
    if answer.contained:
        return answer
    refuted = _halfspace_test(S, T, *_hull_halfspaces(T), tol, "interval hull")
    if not refuted.contained:
        return refuted  # S leaves T's interval hull: exactly not contained
    return answer


def _halfspaces(T):
    """(H, k, method) of an exact H-representation of T, or None."""
    P = _as_hpolytope(T)
    if P is not None:  # HPolytope, Box (finite faces), ℝⁿ (no rows)
        return np.asarray(P.H), np.asarray(P.k), "halfspaces"
    if isinstance(T, Zonotope):
        G, c = np.asarray(T.G), np.asarray(T.c)
    elif isinstance(T, ConstrainedZonotope) and T.nc == 0 and np.isfinite(T.h).all():
        G = T.G.toarray() if sp.issparse(T.G) else np.asarray(T.G)
        G, c = G * T.h, np.asarray(T.c)
    else:
        return None
    facets = zonotope_halfspaces(G, c)
    return None if facets is None else (*facets, "zonotope facets")


def zonotope_halfspaces(G: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """An H-representation {x : Hx ≤ k} of the zonotope Z(G, c), or None when it has more than
    ``MAX_ZONOTOPE_FACETS`` candidate facets.

    The affine hull c + range(G) gives the equalities Nᵀ(x − c) = 0 (two rows each, N spanning the
    null space of Gᵀ); within it, every r − 1 generators (r = rank G) spanning a hyperplane give the
    facet normals ±v with offsets vᵀc + Σ_j |vᵀg_j|.

    Returns
    -------
    (H, k) or None
    """
    n, m = G.shape
    scale = max(np.abs(G).max(initial=0.0), 1.0)
    U, sv, _ = np.linalg.svd(G, full_matrices=True)
    r = int(np.sum(sv > tol_policy.RANK_TOL * scale * max(n, m)))
    if comb(m, max(r - 1, 0)) > MAX_ZONOTOPE_FACETS:
        return None
    rows = [U[:, r:].T, -U[:, r:].T]
    basis = U[:, :r]
    Gr = basis.T @ G  # generators in coordinates of the affine hull, (r, m)
    normals = []
    if r == 1:
        normals.append(np.ones(1))
    elif r > 1:
        for subset in itertools.combinations(range(m), r - 1):
            null = scipy.linalg.null_space(Gr[:, subset].T, rcond=tol_policy.RANK_TOL * max(n, m))
            if null.shape[1] == 1:
                normals.append(null[:, 0])
    if normals:
        V = np.unique(np.round(_unit_sign(np.array(normals)), 12), axis=0) @ basis.T
        rows += [V, -V]
    H = np.vstack([row for row in rows if row.size]) if any(row.size for row in rows) \
        else np.zeros((0, n))
    k = H @ c + np.abs(H @ G).sum(axis=1)
    return H, k


def _unit_sign(V: np.ndarray) -> np.ndarray:
    """Rows normalized to unit length with their first nonzero entry positive (for de-duplication)."""
    V = V / np.linalg.norm(V, axis=1, keepdims=True)
    first = np.argmax(np.abs(V) > 1e-9, axis=1)
    return V * np.sign(V[np.arange(len(V)), first])[:, None]


def _hull_halfspaces(T):
    hull = T.interval_hull()
    eye = np.eye(T.dim)
    H, k = np.vstack([eye, -eye]), np.concatenate([hull.hi, -hull.lo])
    keep = np.isfinite(k)
    return H[keep], k[keep]


def _margins(T, tol: float | None) -> np.ndarray:
    """The ∞-norm margins of T's faces: ``tol`` given, else those of `ConvexSet.contains` at T's centre."""
    if tol is not None:
        return np.full(T.dim, tol)
    hull = T.interval_hull()
    with np.errstate(invalid="ignore"):
        centre = np.where(np.isfinite(hull.lo) & np.isfinite(hull.hi), (hull.lo + hull.hi) / 2, 0.0)
    return default_margins(T, centre)


def _halfspace_test(S, T, H: np.ndarray, k: np.ndarray, tol: float | None, method: str) -> Containment:
    exact = method != "interval hull"
    if H.shape[0] == 0:
        return Containment(True, exact, True, -np.inf, method)
    values, certified = _support_values(S, H)
    slack = np.abs(H) @ _margins(T, tol)
    with np.errstate(invalid="ignore"):
        excess = (values - k) / np.maximum(np.abs(H).sum(axis=1), np.finfo(float).tiny)
    violation = float(np.max(excess))
    contained = bool(np.all(values <= k + slack))
    # Zonotope facets and offsets are computed in floating point: exact up to rounding, not certified.
    sound = certified and contained and method == "halfspaces"
    return Containment(contained, exact, sound, violation, method)


def _support_values(S, H: np.ndarray) -> tuple[np.ndarray, bool]:
    """Support values of S on the rows of H: certified upper bounds where S flattens to a CZ."""
    if S._flat_cz is not None:
        try:
            return S.support_many(H, certified=True), True
        except (SolverError, ValueError):
            pass  # no sound bound for some row: the solver's values
    return S.support_many(H), False


def _cz_sufficient(Z1, Z2, tol: float | None) -> Containment:
    """The linear sufficient condition of the module docstring, as one LP (CVXPY, Clarabel)."""
    G1, A1, G2, A2 = (M.toarray() if sp.issparse(M) else np.asarray(M) for M in (Z1.G, Z1.A, Z2.G, Z2.A))
    c1, b1, h1, c2, b2, h2 = (np.asarray(v, dtype=float) for v in (Z1.c, Z1.b, Z1.h, Z2.c, Z2.b, Z2.h))
    n, (ng1, ng2), (nc1, nc2) = Z1.dim, (Z1.ng, Z2.ng), (Z1.nc, Z2.nc)
    Gam, beta, t = cp.Variable((ng2, ng1)), cp.Variable(ng2), cp.Variable()
    L1 = cp.Variable((n, nc1)) if nc1 else None
    L2 = cp.Variable((nc2, nc1)) if nc1 and nc2 else None
    lhs1 = G2 @ Gam + (L1 @ A1 if L1 is not None else 0)
    lhs2 = G2 @ beta - (L1 @ b1 if L1 is not None else 0)
    cons = [lhs1 == G1, lhs2 == c1 - c2]
    if nc2:
        cons += [A2 @ Gam == (L2 @ A1 if L2 is not None else np.zeros((nc2, ng1))),
                 A2 @ beta - b2 == (-(L2 @ b1) if L2 is not None else np.zeros(nc2))]
    free1, bounded2 = ~np.isfinite(h1), np.isfinite(h2)
    if free1.any():  # a free factor of Z₁ must not move a bounded factor of Z₂
        cons.append(Gam[np.flatnonzero(bounded2)][:, np.flatnonzero(free1)] == 0)
    h1f = np.where(free1, 0.0, h1)
    if bounded2.any():
        idx = np.flatnonzero(bounded2)
        load = cp.abs(Gam[idx]) @ h1f + cp.abs(beta[idx])
        cons.append(load <= cp.multiply(t, h2[idx]))
        objective = cp.Minimize(t)
    else:
        objective = cp.Minimize(0)
        cons.append(t == 0)
    problem = cp.Problem(objective, cons)
    try:
        status = solve_problem(problem, "testing constrained-zonotope containment", "containment")
    except SolverError:
        status = "failed"
    if status != "optimal":
        return Containment(False, False, False, np.nan, "cz sufficient")
    # The solver's Γ, β, Λ satisfy the equalities to its accuracy; the residual, measured in T's
    # margins, must be within the tolerance, and the load within the bounds.
    Gv, bv = np.asarray(Gam.value), np.asarray(beta.value)
    L1v = np.asarray(L1.value) if L1 is not None else np.zeros((n, 0))
    res = np.abs(G1 - G2 @ Gv - L1v @ A1) @ np.where(free1, 0.0, h1) \
        + np.abs(c1 - c2 - G2 @ bv + L1v @ b1)
    if (np.abs(G1 - G2 @ Gv - L1v @ A1)[:, free1] > tol_policy.SOLVER_CHECK_TOL).any():
        return Containment(False, False, False, np.nan, "cz sufficient")
    if nc2:  # ξ₂ = Γξ₁ + β must satisfy A₂ξ₂ = b₂ to the solver's accuracy, relative to the rows
        L2v = np.asarray(L2.value) if L2 is not None else np.zeros((nc2, nc1))
        res2 = np.abs(A2 @ Gv - L2v @ A1) @ h1f + np.abs(A2 @ bv - b2 + L2v @ b1)
        rows = np.abs(A2) @ np.where(bounded2, h2, 1.0) + np.abs(b2)
        if np.any(res2 > tol_policy.SOLVER_CHECK_TOL * np.maximum(rows, 1.0)):
            return Containment(False, False, False, np.nan, "cz sufficient")
    margins = _margins(Z2, tol)
    load = float(t.value) if bounded2.any() else 0.0
    contained = bool(np.all(res <= margins) and load <= 1.0 + tol_policy.SOLVER_CHECK_TOL)
    return Containment(contained, False, False, load - 1.0 if contained else np.nan, "cz sufficient")
