"""The generic path: any set's CVXPY constraints, solved by Clarabel through CVXPY.

The support problem maximizes ``dᵀx`` with the direction as a ``cp.Parameter``: it is compiled once per
set and re-solved for every direction. It works for any set and is the reference the closed forms are
tested against.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import clarabel
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from . import clarabel_lp
from .clarabel_lp import _SOLVED, SolverError

if TYPE_CHECKING:  # pragma: no cover
    from ..sets.base import ConvexSet

__all__ = ["GenericProgram", "chebyshev_ball"]



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
                                     clarabel_lp.settings()).solve()
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
