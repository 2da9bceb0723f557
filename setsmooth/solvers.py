"""Every convex program in setsmooth is solved here, along one of two paths.

* The **generic path** states a set's membership with CVXPY (``ConvexSet.constraints``) and maximizes
  ``dᵀx`` with the direction as a ``cp.Parameter``: the problem is compiled once per set and re-solved
  for every direction. It works for any set and is the reference the closed forms are tested against.
* The **fast path** for constrained zonotopes Z(G, c, A, b, h) substitutes ``x = Gξ + c`` out and
  hands Clarabel the linear program

      maximize (Gᵀd)ᵀξ   subject to   Aξ = b,  -h ≤ ξ ≤ h   (rows with infinite h omitted)

  as sparse matrices. The factor set {ξ : Aξ = b, |ξ| ≤ h} is set up in Clarabel once (equilibration,
  KKT assembly, symbolic factorization) and every direction only replaces the objective. One LP per
  direction on that instance measured faster than stacking the directions block-diagonally into one
  LP, whose single step length holds every block back (1.6× at ng = 100, nc = 40, 20 directions).

Status policy: a solved LP gives a value, an infeasible one means the set is empty (``-inf``), a dual
infeasible one means the support is unbounded (``+inf``); any other status raises `SolverError`
carrying it. A reduced-accuracy status is accepted only where the returned number is a weak-duality
bound that is valid whatever the solver's accuracy (``certified=True``), or verified to
``SOLVER_CHECK_TOL`` (by us on the fast path, by Clarabel's reduced tolerances on the generic path).

Unbounded directions are not left to the solver's dual-infeasibility detection, which stalls or even
reports an arbitrary 'optimum' on LPs with free variables: with free factors (h = ∞) or a recession
direction, boundedness is decided by a recession program, which is feasible and bounded.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from functools import lru_cache
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


def _settings(*, refine: bool = False) -> clarabel.DefaultSettings:
    """Clarabel's settings; ``refine`` turns iterative refinement back on (membership programs)."""
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.direct_solve_method = "qdldl"
    # Iterative refinement of the KKT solves takes ~40% of Clarabel's time on CZ support LPs
    # (measured at ng = 100, nc = 40) and did not change any support value beyond 1e-12 on 1,300
    # random, vertex-degenerate, badly scaled and filter-generated CZ LPs checked against HiGHS; with
    # it on, two of the badly scaled ones stalled (InsufficientProgress). Tolerances are unchanged.
    settings.iterative_refinement_enable = refine
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
             context: str, refine: bool = False) -> LPSolution:
    """Minimize ``qᵀx`` subject to the first ``n_eq`` rows of ``Ax = b`` and the rest ``Ax ≤ b``
    (``refine``: with Clarabel's iterative refinement, see `_settings`)."""
    cones = []
    if n_eq:
        cones.append(clarabel.ZeroConeT(n_eq))
    if n_ineq:
        cones.append(clarabel.NonnegativeConeT(n_ineq))
    nvar = q.shape[0]
    if not cones:  # no constraint at all: bounded only for q == 0
        x = np.zeros(nvar)
        status = "optimal" if not np.any(q) else "unbounded"
        return LPSolution(status, x, np.zeros(0), 0.0)
    solver = clarabel.DefaultSolver(_zero_cost(nvar), q, A, b, cones, _settings(refine=refine))
    return _lp_solution(solver.solve(), n_eq, context)


def _lp_solution(sol, n_eq: int, context: str, solve_time: float | None = None) -> LPSolution:
    """Translate a Clarabel solution into an `LPSolution` (status policy in the module docstring);
    ``solve_time`` replaces Clarabel's own when given."""
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
    return LPSolution(status, np.asarray(sol.x), np.asarray(sol.z)[:n_eq],
                      float(sol.solve_time) if solve_time is None else solve_time)


def _csc(M) -> sp.csc_matrix:
    """M as a canonical CSC matrix (sorted, unique row indices), built directly from a dense array:
    scipy's generic conversion costs as much as Clarabel's whole solve of a small CZ."""
    if sp.issparse(M):
        M = sp.csc_matrix(M)
        if not M.has_canonical_format:
            M = M.copy()
            M.sum_duplicates()
        return M
    M = np.asarray(M, dtype=float)
    cols, rows = np.nonzero(M.T)
    itype = _index_type(M.size)
    indptr = np.zeros(M.shape[1] + 1, dtype=itype)
    np.cumsum(np.bincount(cols, minlength=M.shape[1]), out=indptr[1:])
    return sp.csc_matrix((M[rows, cols], rows.astype(itype), indptr), shape=M.shape)


def _index_type(largest: int) -> type:
    # scipy stores indices as int32 when they fit and checks (costly) whatever it is given.
    return np.int32 if largest < np.iinfo(np.int32).max else np.int64


@lru_cache(maxsize=64)
def _zero_cost(n: int) -> sp.csc_matrix:
    """The zero quadratic cost of an LP with n variables (shared: Clarabel copies its input)."""
    itype = _index_type(n)
    return sp.csc_matrix((np.zeros(0), np.zeros(0, dtype=itype), np.zeros(n + 1, dtype=itype)),
                         shape=(n, n))


#: The recession programs that decide unbounded directions stack their objectives into one LP while
#: it has at most this many variables, and go one objective at a time beyond (support LPs are never
#: stacked: one LP per direction on a shared Clarabel instance measured faster).
STACK_MAX_VARIABLES = 3000


class FactorConstraints:
    """The factor set {ξ : Aξ = b, -h ≤ ξ ≤ h} of a constrained zonotope, assembled for Clarabel.

    It depends on (A, b, h) only, so every linear map, translation and projection of a CZ shares one
    instance, and with it the cached constraint blocks and the emptiness verdict.

    Notes
    -----
    One copy of the factor set is set up in Clarabel on the first query and kept: every later
    objective (direction, map, projection, emptiness) reuses it. The blocks ``kron(I_k, A)`` and the
    finite-bound rows of ``k`` stacked copies are cached per ``k``.
    """

    def __init__(self, A, b: np.ndarray, h: np.ndarray):
        self.A = _csc(A)  # canonical: `block` relies on sorted, unique row indices
        self.b = b
        self.h = h
        self.ng = self.A.shape[1]
        self.nc = self.A.shape[0]
        self.finite = np.flatnonzero(np.isfinite(h))
        self.free = np.flatnonzero(~np.isfinite(h))
        self._stacks: dict[int, tuple[sp.csc_matrix, np.ndarray]] = {}
        self._empty: bool | None = None
        self._solver: clarabel.DefaultSolver | None = None

    def __getstate__(self):
        # A Clarabel instance cannot be pickled (process pools); it is set up again on demand.
        return {**self.__dict__, "_solver": None}

    def block(self, k: int) -> tuple[sp.csc_matrix, np.ndarray]:
        """Rows [kron(I,A); kron(I,E); kron(I,-E)] and right-hand sides for k stacked copies."""
        cached = self._stacks.get(k)
        if cached is not None:
            return cached
        # Assembled from index arrays: scipy's kron/vstack cost more than Clarabel's whole solve of a
        # small CZ. One copy, column by column: A[:, j], then +1 in row nc + p and −1 in row
        # nc + nf + p when j is the p-th factor with a finite bound.
        A, fin = self.A, self.finite
        nc, nf, ng = self.nc, fin.size, self.ng
        a_count = np.diff(A.indptr)
        col_nnz = a_count.copy()
        col_nnz[fin] += 2
        indptr = np.zeros(ng + 1, dtype=np.int64)
        np.cumsum(col_nnz, out=indptr[1:])
        nnz = int(indptr[-1])
        a_dest = np.arange(A.nnz) + np.repeat(indptr[:-1] - A.indptr[:-1], a_count)
        upper = indptr[1:][fin] - 2
        rows = np.empty(nnz, dtype=np.int64)
        rows[a_dest] = A.indices
        rows[upper] = nc + np.arange(nf)
        rows[upper + 1] = nc + nf + np.arange(nf)
        data = np.empty(nnz)
        data[a_dest] = A.data
        data[upper] = 1.0
        data[upper + 1] = -1.0
        hf = self.h[fin]
        rhs = np.concatenate([self.b, hf, hf])
        if k > 1:  # copy i's equality, upper and lower rows follow those of the copies before it
            step = np.where(rows < nc, nc, nf)
            base = np.where(rows < nc, 0, np.where(rows < nc + nf, (k - 1) * nc, (k - 1) * (nc + nf)))
            copies = np.arange(k)[:, None]
            rows = (rows + base + step * copies).ravel()
            data = np.tile(data, k)
            indptr = np.append((indptr[:-1] + nnz * copies).ravel(), k * nnz)
            rhs = np.concatenate([np.tile(self.b, k), np.tile(hf, k), np.tile(hf, k)])
        itype = _index_type(k * max(nnz, nc + 2 * nf))
        M = sp.csc_matrix((data, rows.astype(itype), indptr.astype(itype)),
                          shape=(k * (nc + 2 * nf), k * ng))
        self._stacks[k] = (M, rhs)
        return M, rhs

    def solve(self, Q: np.ndarray, context: str) -> LPSolution:
        """Minimize Σ_i Q_iᵀξ_i over k stacked copies of the factor set (Q has shape (k, ng)).

        One copy (k = 1) is solved on the factor set's kept Clarabel instance, which only has its
        objective replaced.
        """
        k = Q.shape[0]
        nf = self.finite.size
        if k > 1 or self.nc + nf == 0:
            M, rhs = self.block(k)
            return solve_lp(Q.reshape(-1), M, rhs, k * self.nc, 2 * k * nf, context)
        q = Q.reshape(-1)
        if self._solver is None:
            M, rhs = self.block(1)
            cones = [clarabel.ZeroConeT(self.nc)] if self.nc else []
            if nf:
                cones.append(clarabel.NonnegativeConeT(2 * nf))
            self._solver = clarabel.DefaultSolver(_zero_cost(self.ng), q, M, rhs, cones, _settings())
            return _lp_solution(self._solver.solve(), self.nc, context)
        self._solver.update(q=q)
        start = time.perf_counter()
        sol = self._solver.solve()
        # Clarabel's solve_time of a re-solve counts the set-up again (and a timer that grows with
        # every solve), so a re-solve is timed by its own call.
        return _lp_solution(sol, self.nc, context, time.perf_counter() - start)

    def unbounded_objectives(self, g: np.ndarray, scale: np.ndarray, context: str) -> np.ndarray:
        """Which objectives grow without bound along the recession cone of the factor set.

        The recession cone is {ξ : Aξ = 0, ξ_j = 0 where h_j < ∞}, so only the free factors matter:
        ``g`` has one row per objective, restricted to them (shape (k, number of free factors)). An
        objective is unbounded on a non-empty factor set exactly when the gain
        max{gᵢᵀη : A_F η = 0, |η| ≤ 1} = min_λ ‖gᵢ − A_Fᵀλ‖₁ is positive, that is when no multiplier
        cancels the reduced cost on the free factors (the condition `CZProgram._dual_bound` checks).
        This program is feasible (η = 0) and bounded, so Clarabel decides it reliably, unlike the dual
        infeasibility of the support LP, on which it may stall. Gains above ``REDUCED_COST_TOL·scale``
        count as positive.
        """
        k, nf = g.shape
        AF = self.A[:, self.free]
        gains = np.empty(k)
        width = max(k, 1) if k * nf <= STACK_MAX_VARIABLES else 1
        for start in range(0, k, width):
            rows = slice(start, start + width)
            m = g[rows].shape[0]
            eye = sp.identity(m, format="csc")
            M = sp.vstack([sp.kron(eye, AF), sp.identity(m * nf), -sp.identity(m * nf)],
                          format="csc")
            rhs = np.concatenate([np.zeros(m * self.nc), np.ones(2 * m * nf)])
            sol = solve_lp(-g[rows].reshape(-1), M, rhs, m * self.nc, 2 * m * nf, context)
            if sol.status != "optimal":
                raise SolverError(sol.status, context)
            gains[rows] = np.einsum("ij,ij->i", g[rows], sol.x.reshape(m, nf))
        return gains > tol.REDUCED_COST_TOL * scale

    def is_empty(self) -> bool:
        """Feasibility of {ξ : Aξ = b, |ξ| ≤ h} (cached)."""
        if self._empty is None:
            if self.nc == 0:
                self._empty = False  # ξ = 0 is feasible since h ≥ 0
            else:
                context = "deciding emptiness of a constrained zonotope"
                try:
                    sol = self.solve(np.zeros((1, self.ng)), context)
                    if sol.status == "inaccurate":
                        raise SolverError(_ALMOST_SOLVED, context)
                    self._empty = sol.status == "infeasible"
                except SolverError:
                    if not self.free.size:
                        raise
                    # Free factors can stall the infeasibility certificate; the least ℓ1 residual
                    # of Aξ = b over the bounds is a feasible, bounded program instead.
                    self._empty = self._least_residual(context) > \
                        tol.SOLVER_CHECK_TOL * (1.0 + np.abs(self.b).max(initial=0.0))
        return self._empty

    def _least_residual(self, context: str) -> float:
        """min{‖Aξ − b‖₁ : |ξ_j| ≤ h_j}, as an LP in (ξ, t) with −t ≤ Aξ − b ≤ t."""
        M, rhs = self.block(1)
        bounds, hf = M[self.nc:], rhs[self.nc:]
        eye = sp.identity(self.nc, format="csc")
        rows = sp.vstack([sp.hstack([self.A, -eye]), sp.hstack([-self.A, -eye]),
                          sp.hstack([bounds, sp.csc_matrix((bounds.shape[0], self.nc))])],
                         format="csc")
        q = np.concatenate([np.zeros(self.ng), np.ones(self.nc)])
        sol = solve_lp(q, rows, np.concatenate([self.b, -self.b, hf]), 0, rows.shape[0], context)
        if sol.status != "optimal":
            raise SolverError(sol.status, context)
        return float(q @ sol.x)


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
        self.G = sp.csc_matrix(G) if sp.issparse(G) else G
        self.c = c
        self.factors = factors
        self.A, self.b, self.h = factors.A, factors.b, factors.h
        self.ng, self.nc, self.finite = factors.ng, factors.nc, factors.finite
        #: Clarabel's own solve time summed over the LPs of the last `support` call, seconds.
        self.last_solve_time = 0.0

    def _solve(self, Q: np.ndarray, context: str) -> LPSolution:
        sol = self.factors.solve(Q, context)
        self.last_solve_time += sol.solve_time
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
        self.last_solve_time = 0.0
        try:
            return self._support_direct(D, certified)
        except SolverError:
            if not self.factors.free.size:
                raise
        # With free factors an unbounded direction makes the LP dual infeasible, which Clarabel
        # often fails to certify (it stalls: InsufficientProgress, MaxIterations, AlmostSolved).
        # Boundedness is then settled by the recession program and only bounded directions are
        # solved, so that a failure among those is a genuine one.
        return self._support_settling_recession(D, certified)

    def _support_direct(self, D: np.ndarray, certified: bool) -> tuple[np.ndarray, np.ndarray]:
        # One LP per direction on the factor set's Clarabel instance. Dual infeasibility alone does
        # not prove feasibility, so emptiness is settled before an unbounded direction is believed.
        k, n = D.shape
        GtD = np.asarray((self.G.T @ D.T).T)  # (k, ng): objective of each direction
        Q = -GtD
        values = np.full(k, np.inf)
        points = np.full((k, n), np.nan)
        solved, xs, zs, status = [], [], [], "optimal"
        for i in range(k):
            sol = self._solve(Q[i:i + 1], "computing a support function of a constrained zonotope")
            if sol.status == "infeasible" or (sol.status == "unbounded" and self.factors.is_empty()):
                return np.full(k, -np.inf), np.full((k, n), np.nan)
            if sol.status != "unbounded":
                solved.append(i)
                xs.append(sol.x)
                zs.append(sol.z_eq)
                status = "inaccurate" if sol.status == "inaccurate" else status
        if solved:  # finished together, as one stacked solution
            rows = slice(None) if len(solved) == k else np.array(solved)
            together = LPSolution(status, np.concatenate(xs), np.concatenate(zs), 0.0)
            values[rows], points[rows] = self._finish(D[rows], GtD[rows], together, certified)
        return values, points

    def _support_settling_recession(self, D: np.ndarray, certified: bool):
        k, n = D.shape
        values = np.full(k, np.inf)
        points = np.full((k, n), np.nan)
        if self.factors.is_empty():
            return np.full(k, -np.inf), points
        GtD = np.asarray((self.G.T @ D.T).T)
        scale = 1.0 + np.abs(GtD).max(axis=1, initial=0.0)
        unbounded = self.factors.unbounded_objectives(
            GtD[:, self.factors.free], scale, "deciding which support functions are unbounded")
        bounded = np.flatnonzero(~unbounded)
        width = max(bounded.size, 1) if bounded.size * self.ng <= STACK_MAX_VARIABLES else 1
        for start in range(0, bounded.size, width):
            rows = bounded[start:start + width]
            sol = self._solve(-GtD[rows], "computing support functions of a constrained zonotope")
            if sol.status != "optimal" and sol.status != "inaccurate":
                raise SolverError(sol.status, "computing support functions in directions shown to "
                                  "be bounded on a non-empty constrained zonotope")
            values[rows], points[rows] = self._finish(D[rows], GtD[rows], sol, certified)
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
        if self.factors.free.size:
            # A bounded direction has multipliers that cancel the objective on the free factors. A
            # 'Solved' report without them is the solver's mistake on an unbounded direction (seen
            # with huge or arbitrary primal points), which `support` settles by recession instead.
            lam = sol.z_eq.reshape(k, self.nc)
            free = self.factors.free
            leak = np.abs(GtD[:, free] - np.asarray((self.A[:, free].T @ lam.T).T)).max(axis=1)
            if np.any(leak > tol.REDUCED_COST_TOL * (1.0 + np.abs(GtD).max(axis=1, initial=0.0))):
                raise SolverError("UncertifiableReducedCost", "computing support functions: no "
                                  "multiplier cancels the objective on the free factors")
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
        """Whether some ξ with Aξ = b, |ξ| ≤ h has ‖Gξ + c − p‖∞ ≤ margin.

        Decided by the distance program min{t : |Gξ + c − p| ≤ t, t ≥ margin, Aξ = b, |ξ| ≤ h},
        which is feasible whenever Z is and bounded below, rather than by the feasibility of
        ``t = margin``: an interior-point method certifies infeasibility less reliably
        (AlmostPrimalInfeasible) than it solves. The explicit row t ≥ margin matters: without it a
        member (distance 0) leaves no slack and Clarabel often stops at AlmostSolved. The optimum is
        compared with ``margin`` up to the solver's accuracy.
        """
        context = "deciding membership in a constrained zonotope"
        M, rhs = self.factors.block(1)
        n = self.G.shape[0]
        ones = sp.csc_matrix(np.ones((n, 1)))
        t_row = sp.csc_matrix(([-1.0], ([0], [self.ng])), shape=(1, self.ng + 1))
        # Equalities first (Aξ = b), then the bound rows, ±(Gξ + c − p) ≤ t and −t ≤ −margin.
        rows = sp.vstack([sp.hstack([M, sp.csc_matrix((M.shape[0], 1))]),
                          sp.hstack([self.G, -ones]), sp.hstack([-self.G, -ones]), t_row],
                         format="csc")
        r = np.concatenate([rhs, p - self.c, self.c - p, [-margin]])
        q = np.zeros(self.ng + 1)
        q[-1] = 1.0
        # With iterative refinement: without it, 2 in 1,500 members of random CZs with free factors
        # came out as non-members or AlmostSolved (t* a few 1e-9 above the margin).
        sol = solve_lp(q, rows, r, self.nc, rows.shape[0] - self.nc, context, refine=True)
        if sol.status == "infeasible":
            return False
        if sol.status != "optimal":
            raise SolverError(_ALMOST_SOLVED if sol.status == "inaccurate" else sol.status, context)
        scale = max(np.abs(p).max(initial=0.0), np.abs(self.c).max(initial=0.0),
                    np.abs(self.b).max(initial=0.0))
        return bool(sol.x[-1] <= margin + tol.scaled(tol.SOLVER_TOL, scale))


# --------------------------------------------------------------------------------------------------
# CVXPY, for any set
# --------------------------------------------------------------------------------------------------

# Clarabel's reduced-accuracy verdict ('AlmostSolved', CVXPY's optimal_inaccurate) is asked to mean
# residuals and gap within SOLVER_CHECK_TOL, the accuracy to which the fast path verifies such answers,
# so it is accepted. Second-order cones of flat sets (degenerate ellipsoids) often stall at a primal
# residual of a few 1e-9, just above SOLVER_TOL, after the gap has closed.
_CVXPY_OK = {cp.OPTIMAL, cp.OPTIMAL_INACCURATE}
_CVXPY_INFEASIBLE = {cp.INFEASIBLE}
_CVXPY_UNBOUNDED = {cp.UNBOUNDED}


def _solve_cvxpy(problem: cp.Problem, context: str) -> str:
    try:
        with warnings.catch_warnings():
            # An inaccurate status is reported by the status policy below, not by a warning.
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            problem.solve(solver=cp.CLARABEL, tol_gap_abs=tol.SOLVER_TOL,
                          tol_gap_rel=tol.SOLVER_TOL, tol_feas=tol.SOLVER_TOL,
                          reduced_tol_gap_abs=tol.SOLVER_CHECK_TOL,
                          reduced_tol_gap_rel=tol.SOLVER_CHECK_TOL,
                          reduced_tol_feas=tol.SOLVER_CHECK_TOL)
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
        self._recession: bool | None = None

    def support(self, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Support values and points for every row of ``D`` (see `CZProgram.support`).

        Interior-point solvers do not reliably certify an unbounded direction: they may stall, or
        even report an arbitrary finite optimum. So on a set that has a recession direction (decided
        once, `_has_recession`), every direction is checked by its recession gain as well.
        """
        k = D.shape[0]
        values = np.empty(k)
        points = np.full((k, self.dim), np.nan)
        for i, d in enumerate(D):
            self.d.value = d
            try:
                status = _solve_cvxpy(self.problem, "computing a support function (generic path)")
            except SolverError:
                if self.is_empty():
                    return np.full(k, -np.inf), np.full((k, self.dim), np.nan)
                if not (self._has_recession() and self._improves_along_a_ray()):
                    raise
                status = "unbounded"
            if status == "optimal" and self._has_recession() and self._improves_along_a_ray():
                status = "unbounded"
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

    # -- recession directions ------------------------------------------------------------------------
    # In Clarabel's conic form of the problem (minimize cᵀz subject to Az + s = b, s ∈ K, where z
    # stacks x and CVXPY's auxiliary variables) the recession directions are {z : Az + s = 0, s ∈ K}.
    # The gain max{−cᵀz : Az + s = 0, s ∈ K, ‖z‖∞ ≤ 1} is positive when the objective improves along
    # one. That program is feasible (z = 0) and bounded, so the solver decides it reliably.

    def _conic_form(self):
        """(c, A, cones) of the problem for the current direction, or None with variable bounds."""
        from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import dims_to_solver_cones

        data, _, _ = self.problem.get_problem_data(cp.CLARABEL)
        if data.get("lower_bounds") is not None or data.get("upper_bounds") is not None:
            return None  # bounds live outside A; such problems are left undecided
        return (np.asarray(data["c"], dtype=float), sp.csc_matrix(data["A"]),
                dims_to_solver_cones(data["dims"]))

    def _recession_gains(self, C: np.ndarray, A: sp.csc_matrix, cones: list) -> np.ndarray | None:
        """The gain of every row of ``C`` (objectives), as one stacked program; None if unsolved."""
        k, nz = C.shape
        eye = sp.identity(k, format="csc")
        rows = sp.vstack([sp.kron(eye, A), sp.identity(k * nz), -sp.identity(k * nz)],
                         format="csc")
        rhs = np.concatenate([np.zeros(k * A.shape[0]), np.ones(2 * k * nz)])
        sol = clarabel.DefaultSolver(sp.csc_matrix((k * nz, k * nz)), C.reshape(-1), rows, rhs,
                                     cones * k + [clarabel.NonnegativeConeT(2 * k * nz)],
                                     _settings()).solve()
        if str(sol.status).split(".")[-1] != _SOLVED:
            return None
        return -np.einsum("ij,ij->i", C, np.asarray(sol.x).reshape(k, nz))

    @staticmethod
    def _positive(gains: np.ndarray, C: np.ndarray) -> np.ndarray:
        return gains > tol.REDUCED_COST_TOL * (1.0 + np.abs(C).max(axis=1, initial=0.0))

    def _has_recession(self) -> bool:
        """Whether the constraints admit a recession direction moving x (cached; True if undecided)."""
        if self._recession is None:
            saved = self.d.value
            objectives = []
            for d in np.vstack([np.eye(self.dim), -np.eye(self.dim)]):
                self.d.value = d
                form = self._conic_form()
                if form is None:
                    break
                objectives.append(form[0])
            self.d.value = saved
            gains = None if form is None else self._recession_gains(np.array(objectives), *form[1:])
            self._recession = gains is None or bool(self._positive(gains, np.array(objectives)).any())
        return self._recession

    def _improves_along_a_ray(self) -> bool:
        """Whether the current direction's objective has a positive recession gain (False if
        undecided)."""
        form = self._conic_form()
        if form is None:
            return False
        c = form[0][None, :]
        gains = self._recession_gains(c, *form[1:])
        return gains is not None and bool(self._positive(gains, c)[0])

    def is_empty(self) -> bool:
        """Feasibility of the set's constraints."""
        if self._empty is None:
            problem = cp.Problem(cp.Minimize(0), self.constraints)
            self._empty = _solve_cvxpy(problem, "deciding emptiness (generic path)") == "infeasible"
        return self._empty

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether a member lies within ∞-distance ``margin`` of ``p``."""
        # The distance program with the row t ≥ margin, as in CZProgram.contains: without that row 11
        # in 2,000 membership programs of flat sets (degenerate ellipsoid ∩ subspace) stalled.
        t = cp.Variable()
        problem = cp.Problem(cp.Minimize(t), self.constraints + [cp.norm(self.x - p, "inf") <= t,
                                                                 t >= margin])
        if _solve_cvxpy(problem, "deciding membership (generic path)") == "infeasible":
            return False
        return bool(t.value <= margin + tol.scaled(tol.SOLVER_TOL, np.abs(p).max(initial=0.0)))

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
