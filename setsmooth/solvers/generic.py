"""The generic path: any set's CVXPY constraints, solved by Clarabel through `solvers.conic`.

The support problem maximizes ``dᵀx`` with the direction as a ``cp.Parameter``: CVXPY compiles it to
conic form once per program, and since only the objective depends on d, every direction is one
Clarabel solve of the same equilibrated data with a new objective (`conic.ConicForm`: equilibration,
verification, Clarabel's status names, emptiness by the elastic program). It works for any set and is
the reference the closed forms are tested against. Programs are kept per thread
(`solvers.instances`), never on a set.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import clarabel
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from . import clarabel_lp
from .clarabel_lp import _SOLVED, SolverError
from .conic import ConicForm
from .cvxpy_problems import conic_form, solve_problem

if TYPE_CHECKING:  # pragma: no cover
    from ..sets.base import ConvexSet

__all__ = ["GenericProgram", "chebyshev_ball"]

_SUPPORT = "computing a support function (generic path)"


class GenericProgram:
    """The CVXPY support-function problem of one set, compiled once, re-solved per direction.

    Parameters
    ----------
    convex_set : ConvexSet
        Any set; only its ``constraints(x)`` is used (the program keeps no reference to the set).
    """

    def __init__(self, convex_set: "ConvexSet"):
        self.dim = convex_set.dim
        self.x = cp.Variable(self.dim)
        self.d = cp.Parameter(self.dim)
        self.constraints = list(convex_set.constraints(self.x))
        self.problem = cp.Problem(cp.Maximize(self.d @ self.x), self.constraints)
        self._form: ConicForm | None = None
        self._objective: np.ndarray | None = None  # q = objective @ d, shape (nz, dim)
        self._recession: bool | None = None

    def _compiled(self) -> tuple[ConicForm, np.ndarray]:
        """The conic form and the linear map d ↦ q of the objective (compiled on first use)."""
        if self._form is None:
            columns = []
            for e in np.eye(self.dim):
                self.d.value = e
                form, q, _, _ = conic_form(self.problem, _SUPPORT, "support")
                columns.append(q)
            Q = np.array(columns).T
            # The objective −dᵀx selects x from CVXPY's stacked variables: x = −Qᵀz.
            if not (np.count_nonzero(Q, axis=0) == 1).all() or not np.all(Q[Q != 0] == -1.0):
                raise ValueError("unexpected compiled objective: x is not a block of the variables")
            self._form, self._objective = form, Q
        return self._form, self._objective

    def support(self, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Support values and points for every row of ``D`` (see `CZProgram.support`).

        Interior-point solvers do not reliably certify an unbounded direction: they may stall, or
        even report an arbitrary finite optimum. So on a set that has a recession direction (decided
        once, `_has_recession`), every direction is checked by its recession gain as well.
        """
        k = D.shape[0]
        form, Q = self._compiled()
        values = np.empty(k)
        points = np.full((k, self.dim), np.nan)
        empty = (np.full(k, -np.inf), np.full((k, self.dim), np.nan))
        for i, d in enumerate(D):
            q = Q @ d
            try:
                sol = form.solve(q)
            except SolverError:
                if not (self._has_recession() and self._improves_along_a_ray(q)):
                    raise
                sol = None
            if sol is None or (sol.status == "optimal" and self._has_recession()
                               and self._improves_along_a_ray(q)):
                values[i] = np.inf
                continue
            if sol.status == "infeasible":
                return empty
            if sol.status == "unbounded":
                # As for the fast path, an unbounded report does not prove feasibility.
                if form.is_empty():
                    return empty
                if self._improves_along_a_ray(q, undecided=True):
                    values[i] = np.inf
                    continue
                # No recession direction gains more than REDUCED_COST_TOL: the direction is zero to
                # that tolerance (the solver saw it normalized), and any member attains it.
                sol = form.solve(np.zeros_like(q))
            points[i] = -Q.T @ sol.z
            values[i] = float(d @ points[i])
        return values, points

    # -- recession directions ------------------------------------------------------------------------
    # In the conic form (minimize qᵀz subject to Az + s = b, s ∈ K) the recession directions are
    # {z : Az + s = 0, s ∈ K}. The gain max{−qᵀz : Az + s = 0, s ∈ K, ‖z‖∞ ≤ 1} is positive when the
    # objective improves along one. That program is feasible (z = 0) and bounded, so the solver
    # decides it reliably. It is posed on the equilibrated data, where ‖z‖∞ ≤ 1 weighs the
    # variables alike and no row is negligible.

    def _recession_gains(self, C: np.ndarray) -> np.ndarray | None:
        """The gain of every row of ``C`` (objectives in the equilibrated variables); None if
        unsolved."""
        form, _ = self._compiled()
        if not form.plain:
            return None
        # Each objective normalized to size at most 1: the gain is then accurate to the solver's
        # absolute tolerance, and `_positive` compares it with REDUCED_COST_TOL, relative to the
        # objective's size and absolute below 1 (a direction of size 1e-16 counts as zero, as on
        # the fast path).
        size = np.abs(C).max(axis=1, keepdims=True)
        C = C / np.maximum(size, 1.0)
        k, nz = C.shape
        A = form.As
        eye = sp.identity(k, format="csc")
        rows = sp.vstack([sp.kron(eye, A), sp.identity(k * nz), -sp.identity(k * nz)],
                         format="csc")
        rhs = np.concatenate([np.zeros(k * A.shape[0]), np.ones(2 * k * nz)])
        sol = clarabel.DefaultSolver(sp.csc_matrix((k * nz, k * nz)), C.reshape(-1), rows, rhs,
                                     form.cones * k + [clarabel.NonnegativeConeT(2 * k * nz)],
                                     clarabel_lp.settings()).solve()
        if str(sol.status).split(".")[-1] != _SOLVED:
            return None
        return -np.einsum("ij,ij->i", C, np.asarray(sol.x).reshape(k, nz))

    @staticmethod
    def _positive(gains: np.ndarray, C: np.ndarray) -> np.ndarray:
        # `_recession_gains` normalizes every objective to size at most 1.
        return gains > tol.REDUCED_COST_TOL

    def _has_recession(self) -> bool:
        """Whether the constraints admit a recession direction moving x (cached; True if undecided)."""
        if self._recession is None:
            form, Q = self._compiled()
            if form.m == 0:
                self._recession = True
            else:
                C = np.vstack([Q.T, -Q.T]) * form.col_scale
                gains = self._recession_gains(C)
                self._recession = gains is None or bool(self._positive(gains, C).any())
        return self._recession

    def _improves_along_a_ray(self, q: np.ndarray, undecided: bool = False) -> bool:
        """Whether the objective q has a positive recession gain (``undecided`` when the gain
        program is not solved)."""
        form, _ = self._compiled()
        if form.m == 0:
            return bool(np.any(q))
        c = (form.col_scale * q)[None, :]
        gains = self._recession_gains(c)
        return undecided if gains is None else bool(self._positive(gains, c)[0])

    def is_empty(self) -> bool:
        """Feasibility of the set's constraints, by the elastic program of `solvers.conic`."""
        form, _ = self._compiled()
        return form.is_empty()

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether a member lies within ∞-distance ``margin`` of ``p``."""
        # The distance program with the row t ≥ margin, as in CZProgram.contains: without that row 11
        # in 2,000 membership programs of flat sets (degenerate ellipsoid ∩ subspace) stalled.
        t = cp.Variable()
        problem = cp.Problem(cp.Minimize(t), self.constraints + [cp.norm(self.x - p, "inf") <= t,
                                                                 t >= margin])
        if solve_problem(problem, "deciding membership (generic path)", "membership") == "infeasible":
            return False
        return bool(t.value <= margin + tol.scaled(tol.SOLVER_TOL, np.abs(p).max(initial=0.0)))

    def closest_point(self, reference: np.ndarray, norm: float | str) -> np.ndarray | None:
        """A member minimizing ``‖x − reference‖`` (None for an empty set)."""
        # The 2-norm as its square, a QP: strongly convex, so the point (not only the distance) is
        # accurate to the solver's tolerance; under ‖·‖₂ a flat optimum leaves it to √tolerance.
        distance = cp.sum_squares(self.x - reference) if norm == 2 else cp.norm(self.x - reference, norm)
        problem = cp.Problem(cp.Minimize(distance), self.constraints)
        status = solve_problem(problem, "finding the closest point (generic path)", "closest point")
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
    status = solve_problem(problem, "computing a Chebyshev centre", "chebyshev centre")
    if status == "infeasible":
        return np.full(n, np.nan), -np.inf
    if status == "unbounded":
        raise ValueError("the polyhedron contains balls of every radius; it has no Chebyshev centre")
    return np.asarray(x.value, dtype=float), float(r.value)
