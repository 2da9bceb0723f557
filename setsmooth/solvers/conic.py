"""A CVXPY problem handed to Clarabel by us: equilibrated, verified, settled when nearly empty.

CVXPY compiles a problem to Clarabel's conic form

    minimize qᵀz   subject to   Az + s = b,   s ∈ K = {0}^{n₀} × ℝ₊^{n₁} × SOC × …

and `ConicForm` solves it directly rather than through ``Problem.solve``, for four reasons:

* **Scale.** Rows and columns are equilibrated (Ruiz: each row block and column divided by the square
  root of its largest entry, repeated) without bounds on the factors, starting from the sizes the
  bounds and defining equalities give the variables (a variable defined by one equality, like x in
  x = Gη + c, has the size of that row's other terms: Ruiz cannot split such a row's scale between
  the row and the variable). Clarabel's own equilibration stops at 1e±4, so a constraint row
  written 1e12 times smaller than another is satisfied "to 1e-9" by any point and silently
  dropped: the same set represented two ways gave different answers.
* **Verification.** An answer is returned only if, in the equilibrated data, the primal point
  satisfies every row to ``SOLVER_CHECK_TOL`` relative to that row's own terms Σⱼ|A_ij z_j| + |b_i|,
  the multipliers satisfy every dual row likewise, and the duality gap closes likewise (each with a
  floor at the solver's accuracy on the unit-size data, for terms that vanish at the solution).
  Clarabel's own tolerances are global norms, under which a row of 1e-8-sized terms may be violated
  by 100 %. The first answer's gap must close relative to its own terms without the floor (else an
  objective of 1e-7-sized terms passes with two correct digits). An answer failing the check is
  solved once more with the variables rescaled to the sizes of its entries; failing again,
  `SolverError('UnverifiedSolution')`.
* **Status.** A failure carries Clarabel's own status name and the program kind (CVXPY maps
  NumericalError, InsufficientProgress and others to one 'solver_error').
* **Nearly empty sets.** Emptiness is decided by the elastic program

      t* = min { t : Az + s = b + t·e, s ∈ K (zero rows as −t ≤ b − Az ≤ t), t ≥ 0 },

  e the cone's unit (1 on linear rows, (1, 0, …, 0) on a second-order cone), on the equilibrated
  data. It is feasible and bounded whatever the data, so an interior-point method solves it where it
  fails to certify the infeasibility of a set emptied by a gap of 1e-8. The set counts as empty iff
  t* > ``EMPTINESS_TOL``·max(1, ‖b‖∞). A program that fails on a set found non-empty is solved again
  on the set relaxed by t̄ = max(2t*, EMPTINESS_TOL·max(1, ‖b‖∞)): it has an interior, and is within
  the emptiness tolerance of the set.
"""

from __future__ import annotations

from dataclasses import dataclass

import clarabel
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from . import clarabel_lp
from .clarabel_lp import SolverError
from .conic_checks import Magnitudes, violations
from .conic_scaling import bound_sizes, groups, ruiz

__all__ = ["ConicForm", "ConicSolution"]

_SOLVED = ("Solved", "AlmostSolved")

#: Range of variable sizes kept apart when rescaling to a solution (`ConicForm._rescale_to`): the
#: span of double precision beyond the solver's accuracy.
_MAGNITUDE_RANGE = 1e-14


@dataclass(frozen=True)
class ConicSolution:
    """A verified answer: ``status`` in {'optimal', 'infeasible', 'unbounded'}, the primal ``z``
    (original scaling; NaN unless optimal) and its objective ``value``."""

    status: str
    z: np.ndarray
    value: float


def _status_name(status) -> str:
    return str(status).split(".")[-1]


class _Unverified(Exception):
    def __init__(self, z: np.ndarray, what: str):
        super().__init__(what)
        self.z, self.what = z, what


class ConicForm:
    """One compiled conic program (A, b, K), equilibrated once, solved for any objective q.

    Parameters
    ----------
    A : sparse matrix, shape (m, nz)
    b : ndarray, shape (m,)
    dims : cvxpy ConeDims
        The cone sizes in CVXPY's order (zero, nonneg, soc, then others).
    context, kind : str
        What is being computed and the program kind, for `SolverError`.
    P : sparse matrix, optional
        A quadratic term ½zᵀPz of the objective (symmetric, positive semidefinite).
    """

    def __init__(self, A, b: np.ndarray, dims, context: str, kind: str, P=None):
        from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import dims_to_solver_cones

        self.A = sp.csc_matrix(A)
        self.b = np.asarray(b, dtype=float)
        #: The quadratic part ½zᵀPz of the objective (None: a linear objective).
        self.P = None if P is None else sp.csc_matrix(P)
        self.m, self.nz = self.A.shape
        self.n_zero, self.n_nonneg = int(dims.zero), int(dims.nonneg)
        self.soc = [int(k) for k in dims.soc]
        self.cones = dims_to_solver_cones(dims)
        n_soc = sum(self.soc)
        #: Only zero, linear and second-order cones can be relaxed and verified here.
        self.plain = self.n_zero + self.n_nonneg + n_soc == self.m
        self.context, self.kind = context, kind
        self._use_scaling(*self._equilibrate())
        self._elastic: float | None = None

    def _use_scaling(self, r: np.ndarray, c: np.ndarray, beta: float) -> None:
        self.row_scale = r
        self.As = sp.csc_matrix(sp.diags(r) @ self.A @ sp.diags(c))
        self.bs = beta * r * self.b
        self._sizes: Magnitudes | None = None  # made at the first answer checked (`sizes`)
        #: z = col_scale · z' for the solution z' of the scaled program (q' = col_scale · q up to
        #: the positive factor β, which does not move the minimizer).
        self.col_scale = c / beta

    @property
    def sizes(self) -> Magnitudes:
        """`conic_checks.Magnitudes` of the scaled matrix: what every answer's check measures
        against, made once per scaling."""
        if self._sizes is None:
            self._sizes = Magnitudes.of(self.As)
        return self._sizes

    # -- scaling -------------------------------------------------------------------------------------
    def _groups(self) -> np.ndarray:
        """Start row of every block of rows sharing one scaling factor (`conic_scaling.groups`)."""
        return groups(self.n_zero, self.n_nonneg, self.soc, self.m)

    def _equilibrate(self) -> tuple[np.ndarray, np.ndarray, float]:
        """Ruiz scaling of [A b] from the variables' bound sizes (`conic_scaling`)."""
        start = bound_sizes(self.A, self.b, self.n_zero, self.n_nonneg)
        return ruiz(self.A, self.b, self._groups(), start)

    def _rescale_to(self, z: np.ndarray) -> None:
        """Rescale so that the variables of the solution z (original scaling) are all of size ~1
        (those far below the largest, at `_MAGNITUDE_RANGE` of it), then each row block to size 1.

        A retry after an answer failed verification: Ruiz balances the data, not the solution, and
        a factor bounded by 1e-8 next to one of size 1e4 stays below the solver's absolute accuracy.
        """
        size = np.abs(z / self.col_scale)  # in the current scaled variables
        largest = size.max(initial=0.0)
        if largest == 0:
            return
        # Relative sizes in [_MAGNITUDE_RANGE, 1]: the largest variables keep their scale, the small
        # ones are scaled up to it.
        c = self.col_scale * np.maximum(size / largest, _MAGNITUDE_RANGE)
        M = abs(self.A) @ sp.diags(c)
        rows = np.maximum(np.asarray(M.max(axis=1).todense()).ravel(), np.abs(self.b))
        starts = self._groups()
        block = np.repeat(np.maximum.reduceat(rows, starts), np.diff(np.append(starts, self.m)))
        self._use_scaling(1.0 / np.where(block > 0, block, 1.0), c, 1.0)

    # -- solving -------------------------------------------------------------------------------------
    def _unit(self) -> np.ndarray:
        """e: 1 on linear rows, (1, 0, …, 0) on each second-order cone."""
        e = np.zeros(self.m)
        e[self.n_zero:self.n_zero + self.n_nonneg] = 1.0
        row = self.n_zero + self.n_nonneg
        for k in self.soc:
            e[row] = 1.0
            row += k
        return e

    def _relaxed_data(self, relax: float, elastic: bool):
        """(A, b, cones) of the relaxed program, in scaled variables (and t last when elastic)."""
        Z = self.As[: self.n_zero]
        rest = self.As[self.n_zero:]
        e = self._unit()[self.n_zero:]
        bz, brest = self.bs[: self.n_zero], self.bs[self.n_zero:]
        blocks = [-Z, Z, rest]
        rhs = [-bz + relax, bz + relax, brest + relax * e]
        tcol = [np.full(self.n_zero, -1.0), np.full(self.n_zero, -1.0), -e]
        A = sp.vstack(blocks, format="csc")
        b = np.concatenate(rhs)
        n_lin = 2 * self.n_zero + self.n_nonneg
        cones = [clarabel.NonnegativeConeT(n_lin)] if n_lin else []
        cones += [clarabel.SecondOrderConeT(k) for k in self.soc]
        if elastic:
            A = sp.hstack([A, sp.csc_matrix(np.concatenate(tcol)[:, None])], format="csc")
            # t ≥ 0 as one more linear row, placed with the other linear rows.
            t_row = sp.csc_matrix(([-1.0], ([0], [self.nz])), shape=(1, self.nz + 1))
            A = sp.vstack([A[:n_lin], t_row, A[n_lin:]], format="csc")
            b = np.concatenate([b[:n_lin], [0.0], b[n_lin:]])
            cones = [clarabel.NonnegativeConeT(n_lin + 1)] + cones[1 if n_lin else 0:]
        return A, b, cones

    def _clarabel(self, q, A, b, cones, P=None):
        s = clarabel_lp.settings(refine=True)
        s.reduced_tol_gap_abs = s.reduced_tol_gap_rel = s.reduced_tol_feas = tol.SOLVER_CHECK_TOL
        n = q.shape[0]
        P = sp.csc_matrix((n, n)) if P is None else sp.triu(P, format="csc")
        return clarabel.DefaultSolver(P, q, sp.csc_matrix(A), b, cones, s).solve()

    def _scaled_quadratic(self, factor: float):
        if self.P is None:
            return None
        C = sp.diags(self.col_scale)
        return sp.csc_matrix(C @ self.P @ C) / factor

    def bscale(self) -> float:
        return max(1.0, float(np.abs(self.bs).max(initial=0.0)))

    def elastic(self) -> float:
        """t* of the elastic program (module docstring), in the equilibrated rows (cached)."""
        if self._elastic is None:
            if not self.plain:
                raise SolverError("Unsupported", f"{self.context}: the elastic program handles "
                                  "zero, linear and second-order cones only", kind=self.kind)
            A, b, cones = self._relaxed_data(0.0, elastic=True)
            q = np.zeros(self.nz + 1)
            q[-1] = 1.0
            sol = self._clarabel(q, A, b, cones)
            name = _status_name(sol.status)
            if name not in _SOLVED:
                raise SolverError(name, f"{self.context} (elastic program)", kind=self.kind)
            self._elastic = max(0.0, float(np.asarray(sol.x)[-1]))
        return self._elastic

    def is_empty(self) -> bool:
        """Whether no z satisfies the constraints (elastic program, `EMPTINESS_TOL`)."""
        if self.m == 0:
            return False
        return self.elastic() > tol.EMPTINESS_TOL * self.bscale()

    def solve(self, q: np.ndarray) -> ConicSolution:
        """Minimize qᵀz (q in the original scaling) with the status policy of the module docstring.

        Raises
        ------
        SolverError
            With Clarabel's status name, or 'UnverifiedSolution' when an answer fails the check.
        """
        q = np.asarray(q, dtype=float)
        try:
            sol = self._solve_verified(q, 0.0)
        except SolverError:
            if not self.plain:
                raise
            sol = None
        if sol is not None and sol.status != "infeasible":
            return sol
        # Infeasible, or no trustworthy answer: settle emptiness by the elastic program, then solve
        # the set relaxed within the emptiness tolerance, which has an interior.
        if self.is_empty():
            return ConicSolution("infeasible", np.full(self.nz, np.nan), np.nan)
        relax = max(2.0 * self.elastic(), tol.EMPTINESS_TOL * self.bscale())
        sol = self._solve_verified(q, relax)
        if sol.status == "infeasible":
            raise SolverError("PrimalInfeasible", f"{self.context}: a relaxation of a set found "
                              "non-empty was reported infeasible", kind=self.kind)
        return sol

    def _solve_verified(self, q: np.ndarray, relax: float) -> ConicSolution:
        """`_solve`; an answer failing verification (the first strictly: its gap relative to its
        own terms, without the floor) is solved once more, rescaled to it."""
        try:
            return self._solve(q, relax, strict=True)
        except _Unverified as failed:
            # The retry's scaling serves this objective only: kept, it would make later answers
            # (and the recession tests, posed in the scaled variables) depend on the query history.
            saved = self.row_scale, self.As, self.bs, self.col_scale, self._sizes
            self._rescale_to(failed.z)
        try:
            return self._solve(q, relax)
        except _Unverified as failed:
            raise SolverError("UnverifiedSolution", f"{self.context}: the solution failed the "
                              f"check of {failed.what}, also after rescaling to it",
                              kind=self.kind) from None
        finally:
            self.row_scale, self.As, self.bs, self.col_scale, self._sizes = saved

    def _solve(self, q: np.ndarray, relax: float, strict: bool = False) -> ConicSolution:
        qs = self.col_scale * q
        Ps = self._scaled_quadratic(1.0)
        q_size = max(np.abs(qs).max(initial=0.0), 0.0 if Ps is None else abs(Ps).max())
        if q_size > 0:  # a positive factor does not move the minimizer
            qs = qs / q_size
            Ps = None if Ps is None else Ps / q_size
        if relax == 0.0:
            A, b, cones, n_zero = self.As, self.bs, self.cones, self.n_zero
        else:
            (A, b, cones), n_zero = self._relaxed_data(relax, elastic=False), 0
        if A.shape[0] == 0 and Ps is None:
            if np.any(q):
                return ConicSolution("unbounded", np.full(self.nz, np.nan), -np.inf)
            return ConicSolution("optimal", np.zeros(self.nz), 0.0)
        sol = self._clarabel(qs, A, b, cones, Ps)
        name = _status_name(sol.status)
        if name == "PrimalInfeasible":
            return ConicSolution("infeasible", np.full(self.nz, np.nan), np.inf)
        if name == "DualInfeasible":
            return ConicSolution("unbounded", np.full(self.nz, np.nan), -np.inf)
        if name not in _SOLVED:
            raise SolverError(name, self.context, kind=self.kind)
        zs = np.asarray(sol.x)
        z = self.col_scale * zs
        if self.plain:
            sizes = self.sizes if relax == 0.0 else Magnitudes.of(A)
            bad = violations(qs, zs, np.asarray(sol.z), A, sizes, b, n_zero,
                             A.shape[0] - sum(self.soc), self.soc, Ps, strict)
            if bad:
                raise _Unverified(z, ", ".join(bad))
        value = float(q @ z) if self.P is None else float(q @ z + 0.5 * z @ (self.P @ z))
        return ConicSolution("optimal", z, value)
