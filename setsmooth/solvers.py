"""Every convex program in setsmooth is solved here, along one of two paths.

* The **generic path** states a set's membership with CVXPY (``ConvexSet.constraints``) and maximizes
  ``dᵀx`` with the direction as a ``cp.Parameter``: the problem is compiled once per set and re-solved
  for every direction. It works for any set and is the reference the closed forms are tested against.
* The **fast path** for constrained zonotopes Z(G, c, A, b, h) substitutes ``x = Gξ + c`` out and
  hands Clarabel the linear program

      maximize (Gᵀd)ᵀξ   subject to   Aξ = b,  -h ≤ ξ ≤ h   (rows with infinite h omitted)

  as sparse matrices. All directions of a query are stacked block-diagonally into one LP, so an interval
  hull costs one solver call. The assembled constraint blocks are cached per number of directions.

Status policy: a solved LP gives a value, an infeasible one means the set is empty (``-inf``), a dual
infeasible one means the support is unbounded (``+inf``); any other status raises `SolverError`
carrying it. A reduced-accuracy status is accepted only where the returned number is a weak-duality
bound that is valid whatever the solver's accuracy (``certified=True``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import clarabel
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from . import tolerances as tol

if TYPE_CHECKING:  # pragma: no cover
    from .sets.base import ConvexSet

__all__ = ["SolverError", "FactorConstraints", "CZProgram", "GenericProgram"]


class SolverError(RuntimeError):
    """A convex program ended in a status that yields no trustworthy answer.

    Attributes
    ----------
    status : str
        The solver's status (Clarabel's ``SolverStatus`` name or CVXPY's status string).
    """

    def __init__(self, status: str, context: str = ""):
        self.status = str(status)
        where = f" while {context}" if context else ""
        super().__init__(f"solver returned status {self.status!r}{where}")


# --------------------------------------------------------------------------------------------------
# Clarabel, directly
# --------------------------------------------------------------------------------------------------

_SOLVED = "Solved"
_ALMOST_SOLVED = "AlmostSolved"
_INFEASIBLE = ("PrimalInfeasible",)
_UNBOUNDED = ("DualInfeasible",)


def _settings() -> clarabel.DefaultSettings:
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.direct_solve_method = "qdldl"
    settings.tol_gap_abs = tol.SOLVER_TOL
    settings.tol_gap_rel = tol.SOLVER_TOL
    settings.tol_feas = tol.SOLVER_TOL
    settings.max_iter = 200
    return settings


@dataclass(frozen=True)
class LPSolution:
    """What one Clarabel call returned: ``status`` in {'optimal', 'inaccurate', 'infeasible',
    'unbounded'}, the primal ``x``, the equality multipliers ``z_eq`` and Clarabel's ``solve_time``."""

    status: str
    x: np.ndarray
    z_eq: np.ndarray
    solve_time: float


def solve_lp(q: np.ndarray, A: sp.csc_matrix, b: np.ndarray, n_eq: int, n_ineq: int,
             context: str) -> LPSolution:
    """Minimize ``qᵀx`` subject to the first ``n_eq`` rows of ``Ax = b`` and the rest ``Ax ≤ b``."""
    cones = []
    if n_eq:
        cones.append(clarabel.ZeroConeT(n_eq))
    if n_ineq:
        cones.append(clarabel.NonnegativeConeT(n_ineq))
    nvar = q.shape[0]
    P = sp.csc_matrix((nvar, nvar))
    if not cones:  # no constraint at all: bounded only for q == 0
        x = np.zeros(nvar)
        status = "optimal" if not np.any(q) else "unbounded"
        return LPSolution(status, x, np.zeros(0), 0.0)
    solver = clarabel.DefaultSolver(P, q, A, b, cones, _settings())
    sol = solver.solve()
    name = str(sol.status).split(".")[-1]
    if name == _SOLVED:
        status = "optimal"
    elif name == _ALMOST_SOLVED:
        status = "inaccurate"
    elif name in _INFEASIBLE:
        status = "infeasible"
    elif name in _UNBOUNDED:
        status = "unbounded"
    else:
        raise SolverError(name, context)
    return LPSolution(status, np.asarray(sol.x), np.asarray(sol.z)[:n_eq], float(sol.solve_time))


#: Directions are stacked into one LP while the stacked program has at most this many variables;
#: beyond it one LP per direction is faster (measured: 6 directions × 4208 factors take 0.47 s
#: stacked and 6 × 0.043 s one by one in Clarabel).
STACK_MAX_VARIABLES = 3000


class FactorConstraints:
    """The factor set {ξ : Aξ = b, -h ≤ ξ ≤ h} of a constrained zonotope, assembled for Clarabel.

    It depends on (A, b, h) only, so every linear map, translation and projection of a CZ shares one
    instance, and with it the cached constraint blocks and the emptiness verdict.

    Notes
    -----
    The blocks ``kron(I_k, A)`` and the finite-bound rows are cached per number ``k`` of stacked
    directions; an interval hull always stacks ``2n`` directions, so it is assembled once.
    """

    def __init__(self, A, b: np.ndarray, h: np.ndarray):
        self.A = sp.csc_matrix(A)
        self.b = b
        self.h = h
        self.ng = self.A.shape[1]
        self.nc = self.A.shape[0]
        self.finite = np.flatnonzero(np.isfinite(h))
        self._stacks: dict[int, tuple[sp.csc_matrix, np.ndarray]] = {}
        self._empty: bool | None = None

    def block(self, k: int) -> tuple[sp.csc_matrix, np.ndarray]:
        """Rows [kron(I,A); kron(I,E); kron(I,-E)] and right-hand sides for k stacked copies."""
        cached = self._stacks.get(k)
        if cached is not None:
            return cached
        nf = self.finite.size
        E = sp.csc_matrix((np.ones(nf), (np.arange(nf), self.finite)), shape=(nf, self.ng))
        eye = sp.identity(k, format="csc")
        M = sp.vstack([sp.kron(eye, self.A), sp.kron(eye, E), sp.kron(eye, -E)], format="csc")
        hf = self.h[self.finite]
        rhs = np.concatenate([np.tile(self.b, k), np.tile(hf, k), np.tile(hf, k)])
        self._stacks[k] = (M, rhs)
        return M, rhs

    def solve(self, Q: np.ndarray, context: str) -> LPSolution:
        """Minimize Σ_i Q_iᵀξ_i over k stacked copies of the factor set (Q has shape (k, ng))."""
        k = Q.shape[0]
        M, rhs = self.block(k)
        return solve_lp(Q.reshape(-1), M, rhs, k * self.nc, 2 * k * self.finite.size, context)

    def is_empty(self) -> bool:
        """Feasibility of {ξ : Aξ = b, |ξ| ≤ h} (cached)."""
        if self._empty is None:
            if self.nc == 0:
                self._empty = False  # ξ = 0 is feasible since h ≥ 0
            else:
                sol = self.solve(np.zeros((1, self.ng)), "deciding emptiness of a constrained zonotope")
                if sol.status == "inaccurate":
                    raise SolverError(_ALMOST_SOLVED, "deciding emptiness of a constrained zonotope")
                self._empty = sol.status == "infeasible"
        return self._empty


class CZProgram:
    """The support-function LP of one constrained zonotope Z(G, c, A, b, h).

    Parameters
    ----------
    G : ndarray or sparse matrix, shape (n, ng)
    c : ndarray, shape (n,)
    factors : FactorConstraints
        The shared factor set of the CZ. Arguments are trusted (validated by the caller).
    """

    def __init__(self, G, c: np.ndarray, factors: FactorConstraints):
        self.G = sp.csc_matrix(G)
        self.c = c
        self.factors = factors
        self.A, self.b, self.h = factors.A, factors.b, factors.h
        self.ng, self.nc, self.finite = factors.ng, factors.nc, factors.finite
        #: Clarabel's own solve time of the last call, seconds (for benchmarks).
        self.last_solve_time = 0.0

    def _solve(self, Q: np.ndarray, context: str) -> LPSolution:
        sol = self.factors.solve(Q, context)
        self.last_solve_time = sol.solve_time
        return sol

    # -- queries -----------------------------------------------------------------------------------
    def support(self, D: np.ndarray, certified: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Support values and support points for every row of ``D``.

        Returns
        -------
        values : ndarray, shape (k,)
            ``h_Z(d)``; ``-inf`` when Z is empty, ``+inf`` along unbounded directions.
        points : ndarray, shape (k, n)
            A maximizer per direction (NaN where the value is infinite).
        """
        k, n = D.shape
        if k > 1 and k * self.ng > STACK_MAX_VARIABLES:
            return self._support_one_by_one(D, certified)
        GtD = np.asarray((self.G.T @ D.T).T)  # (k, ng): objective of each block
        sol = self._solve(-GtD, "computing support functions of a constrained zonotope")
        if sol.status == "infeasible":
            return np.full(k, -np.inf), np.full((k, n), np.nan)
        if sol.status == "unbounded":
            return self._support_one_by_one(D, certified)
        return self._finish(D, GtD, sol, certified)

    def _support_one_by_one(self, D: np.ndarray, certified: bool) -> tuple[np.ndarray, np.ndarray]:
        # Used for large programs, and when some direction is unbounded (which makes the stacked LP
        # dual infeasible as a whole). Dual infeasibility alone does not prove feasibility, so
        # emptiness is settled first.
        k, n = D.shape
        if self.factors.is_empty():
            return np.full(k, -np.inf), np.full((k, n), np.nan)
        values = np.empty(k)
        points = np.full((k, n), np.nan)
        for i in range(k):
            sol = self._solve(-np.asarray(self.G.T @ D[i]).reshape(1, -1),
                              "computing a support function of a constrained zonotope")
            if sol.status == "unbounded":
                values[i] = np.inf
                continue
            if sol.status == "infeasible":  # pragma: no cover - ruled out by is_empty above
                raise SolverError("PrimalInfeasible", "re-solving a feasible constrained zonotope")
            g = np.asarray(self.G.T @ D[i]).reshape(1, -1)
            v, p = self._finish(D[i:i + 1], g, sol, certified)
            values[i], points[i] = v[0], p[0]
        return values, points

    def _finish(self, D: np.ndarray, GtD: np.ndarray, sol: LPSolution, certified: bool):
        """Values and points from a solved stacked LP.

        ``certified`` returns the weak-duality bound. Otherwise the primal objective is returned; when
        Clarabel only reached reduced accuracy ('AlmostSolved') that objective is accepted only if we
        verify it: the primal point is feasible to ``SOLVER_CHECK_TOL`` and the always-valid dual bound
        agrees with it to ``SOLVER_CHECK_TOL`` (both relative to the problem's scale). Else SolverError.
        """
        k = D.shape[0]
        xi = sol.x.reshape(k, self.ng)
        points = np.asarray((self.G @ xi.T).T) + self.c
        offsets = D @ self.c
        primal = np.einsum("ij,ij->i", GtD, xi)
        if not certified and sol.status == "optimal":
            return offsets + primal, points
        bound = self._dual_bound(GtD, sol.z_eq.reshape(k, self.nc))
        if certified:
            return offsets + bound, points
        scale = 1.0 + np.abs(GtD).sum(axis=1) * np.max(self.h[self.finite], initial=1.0) \
            + np.abs(self.b).max(initial=0.0)
        residual = np.abs(np.asarray((self.A @ xi.T).T) - self.b).max(axis=1, initial=0.0)
        overshoot = np.max(np.abs(xi[:, self.finite]) - self.h[self.finite], axis=1, initial=0.0)
        checked = (np.abs(bound - primal) <= tol.SOLVER_CHECK_TOL * scale) \
            & (residual <= tol.SOLVER_CHECK_TOL * scale) & (overshoot <= tol.SOLVER_CHECK_TOL * scale)
        if not checked.all():
            raise SolverError(_ALMOST_SOLVED, "computing support functions: the reduced-accuracy "
                              "solution failed the duality-gap check (certified=True still returns a "
                              "valid upper bound)")
        return offsets + primal, points

    def _dual_bound(self, GtD: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """Weak-duality bound bᵀλ + Σ_j h_j |(Gᵀd − Aᵀλ)_j| ≥ max{(Gᵀd)ᵀξ : Aξ=b, |ξ|≤h}.

        Valid for every λ, so the returned bound encloses the true support value whatever the solver's
        accuracy; it is finite only when the reduced cost vanishes on the unbounded factors.
        """
        reduced = GtD - np.asarray((self.A.T @ lam.T).T)
        infinite = np.flatnonzero(~np.isfinite(self.h))
        if infinite.size:
            scale = 1.0 + np.abs(GtD).max(axis=1, initial=0.0)
            leak = np.abs(reduced[:, infinite]).max(axis=1)
            if np.any(leak > tol.REDUCED_COST_TOL * scale):
                raise SolverError("UncertifiableReducedCost",
                                  "certifying a support value: the reduced cost on an unbounded "
                                  f"factor is {leak.max():.3g}, not zero")
        hf = self.h[self.finite]
        return lam @ self.b + np.abs(reduced[:, self.finite]) @ hf

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether some ξ with Aξ = b, |ξ| ≤ h has ‖Gξ + c − p‖∞ ≤ margin."""
        M, rhs = self.factors.block(1)
        G = self.G
        n = G.shape[0]
        # Equalities first (Aξ = b), then the bound rows, then |Gξ + c − p| ≤ margin.
        rows = sp.vstack([M[: self.nc], M[self.nc:], G, -G], format="csc")
        r = np.concatenate([rhs[: self.nc], rhs[self.nc:], p - self.c + margin,
                            self.c - p + margin])
        sol = solve_lp(np.zeros(self.ng), rows, r, self.nc, 2 * self.finite.size + 2 * n,
                       "deciding membership in a constrained zonotope")
        if sol.status == "inaccurate":
            raise SolverError(_ALMOST_SOLVED, "deciding membership in a constrained zonotope")
        return sol.status == "optimal"


# --------------------------------------------------------------------------------------------------
# CVXPY, for any set
# --------------------------------------------------------------------------------------------------

_CVXPY_OK = {cp.OPTIMAL}
_CVXPY_INFEASIBLE = {cp.INFEASIBLE}
_CVXPY_UNBOUNDED = {cp.UNBOUNDED}


def _solve_cvxpy(problem: cp.Problem, context: str) -> str:
    try:
        problem.solve(solver=cp.CLARABEL, tol_gap_abs=tol.SOLVER_TOL, tol_gap_rel=tol.SOLVER_TOL,
                      tol_feas=tol.SOLVER_TOL)
    except cp.error.SolverError as exc:
        raise SolverError("solver_error", f"{context}: {exc}") from exc
    status = problem.status
    if status in _CVXPY_OK:
        return "optimal"
    if status in _CVXPY_INFEASIBLE:
        return "infeasible"
    if status in _CVXPY_UNBOUNDED:
        return "unbounded"
    raise SolverError(status, context)


class GenericProgram:
    """The CVXPY support-function problem of one set, compiled once, re-solved per direction.

    Parameters
    ----------
    convex_set : ConvexSet
        Any set; only its ``constraints(x)`` is used.
    """

    def __init__(self, convex_set: "ConvexSet"):
        self.dim = convex_set.dim
        self.x = cp.Variable(self.dim)
        self.d = cp.Parameter(self.dim)
        self.constraints = list(convex_set.constraints(self.x))
        self.problem = cp.Problem(cp.Maximize(self.d @ self.x), self.constraints)
        self._empty: bool | None = None

    def support(self, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Support values and points for every row of ``D`` (see `CZProgram.support`)."""
        k = D.shape[0]
        values = np.empty(k)
        points = np.full((k, self.dim), np.nan)
        for i, d in enumerate(D):
            self.d.value = d
            status = _solve_cvxpy(self.problem, "computing a support function (generic path)")
            if status == "infeasible":
                self._empty = True
                return np.full(k, -np.inf), np.full((k, self.dim), np.nan)
            if status == "unbounded":
                # As for the fast path, an unbounded report does not prove feasibility.
                if self.is_empty():
                    return np.full(k, -np.inf), np.full((k, self.dim), np.nan)
                values[i] = np.inf
                continue
            points[i] = self.x.value
            values[i] = float(self.problem.value)
        return values, points

    def is_empty(self) -> bool:
        """Feasibility of the set's constraints."""
        if self._empty is None:
            problem = cp.Problem(cp.Minimize(0), self.constraints)
            self._empty = _solve_cvxpy(problem, "deciding emptiness (generic path)") == "infeasible"
        return self._empty

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether a member lies within ∞-distance ``margin`` of ``p``."""
        problem = cp.Problem(cp.Minimize(0),
                             self.constraints + [cp.norm(self.x - p, "inf") <= margin])
        return _solve_cvxpy(problem, "deciding membership (generic path)") == "optimal"

    def closest_point(self, reference: np.ndarray, norm: float | str) -> np.ndarray | None:
        """A member minimizing ``‖x − reference‖`` (None for an empty set)."""
        problem = cp.Problem(cp.Minimize(cp.norm(self.x - reference, norm)), self.constraints)
        status = _solve_cvxpy(problem, "finding the closest point (generic path)")
        if status == "infeasible":
            return None
        return np.asarray(self.x.value, dtype=float)


def chebyshev_ball(H: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre and radius of the largest Euclidean ball inside {x : Hx ≤ k}.

    Returns a NaN centre and radius ``-inf`` for an empty polyhedron; raises ``ValueError`` when the
    inscribed radius is unbounded.
    """
    n = H.shape[1]
    x, r = cp.Variable(n), cp.Variable()
    norms = np.linalg.norm(H, axis=1)
    problem = cp.Problem(cp.Maximize(r), [H @ x + r * norms <= k, r >= 0])
    status = _solve_cvxpy(problem, "computing a Chebyshev centre")
    if status == "infeasible":
        return np.full(n, np.nan), -np.inf
    if status == "unbounded":
        raise ValueError("the polyhedron contains balls of every radius; it has no Chebyshev centre")
    return np.asarray(x.value, dtype=float), float(r.value)
