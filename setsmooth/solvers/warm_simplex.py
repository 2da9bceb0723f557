"""HiGHS's simplex method on one presolved factor set, warm-started across objectives.

The support fallback (`presolve.simplex`) solves the same constraints {Âη = b̂, |η_B| ≤ 1} for
many objectives: the 2n directions of an interval hull, and their certified twins. SciPy's
``linprog`` builds and solves each from scratch; here one HiGHS model is kept per presolved program
and thread (`instances.cached_instance`), only its costs change, and every solve starts from the
previous optimal basis, which stays primal feasible for a new objective, within a batch of queries
(`new_batch`); a batch starts from the program's feasible basis. On the recursion smoother's sets
(3,000 factors, 2,000 rows) the cold solves took ~2,300 iterations each.

The tolerance ladder is `presolve.SIMPLEX_TOLERANCES`, each rung capped as there
(`presolve._rung_iterations`); a rung that does not settle is dropped with its basis
(``clearSolver``), so the next, looser rung starts cold and cannot inherit a cycling basis.
"""

from __future__ import annotations

import os
import sys
import threading

import numpy as np
import scipy.sparse as sp

__all__ = ["WarmSimplex", "new_batch"]

_UNSET = object()
_batches = threading.local()


def new_batch() -> None:
    """Start a batch of queries in this thread: the next solve on every model starts from its
    program's feasible basis, and the batch's later solves from the last one's optimal basis.

    A batch is one `CZProgram` support call (the directions of one set's hull): its answers are a
    function of the program and the directions alone, the same in every thread and whatever other
    sets sharing the program were queried before. Warm-starting across batches too would leave
    each answer depending on the order of the queries: the optimal vertex of a degenerate program
    depends on the start, and threads sharing a factor set (the posterior views) then differed
    from the serial run by 1e-15 of a hull. Starting every objective from the feasible basis
    instead costs 1.9× on the recursion smoother's hulls (reliability case 043 at noise 1e-6).
    """
    _batches.current = getattr(_batches, "current", 0) + 1

_BANNER_LOCK = threading.Lock()
_banner_shown = False


def _quiet_highs():
    """A ``highspy.Highs`` with its output off. HiGHS prints a two-line banner to the process's
    standard output when the first model of a process is made, before any option can be set; that
    one construction runs with file descriptor 1 pointed at the null device (a library must not
    print on its users' terminals)."""
    global _banner_shown
    import highspy

    with _BANNER_LOCK:
        if _banner_shown:
            h = highspy.Highs()
        else:
            sys.stdout.flush()
            saved = os.dup(1)
            devnull = os.open(os.devnull, os.O_WRONLY)
            try:
                os.dup2(devnull, 1)
                h = highspy.Highs()
            finally:
                os.dup2(saved, 1)
                os.close(saved)
                os.close(devnull)
                _banner_shown = True
    h.setOptionValue("output_flag", False)
    h.setOptionValue("solver", "simplex")
    return h


class WarmSimplex:
    """min qᵀη subject to Âη = b̂ and |η_j| ≤ 1 on the bounded factors, for one (Â, b̂) and any q.

    Parameters
    ----------
    A : sparse matrix, shape (m, p)
    b : ndarray, shape (m,)
    bounded : ndarray of bool, shape (p,)
        Which factors have |η_j| ≤ 1 (the others are free).

    Notes
    -----
    Not thread-safe: one instance per thread (`instances.cached_instance`).
    """

    def __init__(self, A: sp.spmatrix, b: np.ndarray, bounded: np.ndarray):
        import highspy

        A = sp.csc_matrix(A)
        m, p = A.shape
        self.shape = (m, p)
        self._status = highspy.HighsModelStatus
        h = _quiet_highs()
        inf = highspy.kHighsInf
        lp = highspy.HighsLp()
        lp.num_col_, lp.num_row_ = p, m
        lp.col_cost_ = np.zeros(p)
        lp.col_lower_ = np.where(bounded, -1.0, -inf)
        lp.col_upper_ = np.where(bounded, 1.0, inf)
        lp.row_lower_ = np.asarray(b, dtype=float)
        lp.row_upper_ = np.asarray(b, dtype=float)
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = A.indptr
        lp.a_matrix_.index_ = A.indices
        lp.a_matrix_.value_ = A.data
        lp.a_matrix_.num_col_, lp.a_matrix_.num_row_ = p, m
        h.passModel(lp)
        self._h = h
        self._columns = np.arange(p, dtype=np.int32)
        self._start = _UNSET  # the feasible basis, found when the first batch starts
        self._batch = None

    def _set_rung(self, tolerance: float | None, cap: int) -> None:
        """HiGHS's primal and dual feasibility tolerance (None: its default, 1e-7) and iteration cap."""
        value = 1e-7 if tolerance is None else tolerance
        self._h.setOptionValue("primal_feasibility_tolerance", value)
        self._h.setOptionValue("dual_feasibility_tolerance", value)
        self._h.setOptionValue("simplex_iteration_limit", int(cap))

    def _feasible_basis(self):
        """The basis every batch starts from: the optimal basis of the zero objective (a feasible
        vertex), or None (cold starts) when that program does not settle at the first rung's
        tolerance."""
        from .presolve import SIMPLEX_TOLERANCES, _rung_iterations

        h, p = self._h, self.shape[1]
        h.changeColsCost(p, self._columns, np.zeros(p))
        self._set_rung(SIMPLEX_TOLERANCES[0], _rung_iterations(sum(self.shape), False))
        h.run()
        basis = h.getBasis() if h.getModelStatus() == self._status.kOptimal else None
        h.clearSolver()
        return basis

    def minimize(self, q: np.ndarray, tolerances: tuple, caps: list[int]
                 ) -> tuple[str, np.ndarray, np.ndarray]:
        """(status name, η, λ̂) through the rungs (``tolerances[i]``: HiGHS's primal and dual
        feasibility tolerance, None for its defaults; ``caps[i]``: the rung's iteration cap).

        Status names as `presolve.simplex`: 'AlmostSolved' for an optimum (checked by the caller),
        'PrimalInfeasible', 'DualInfeasible', 'MaxIterations' or 'NumericalError' for the last
        rung's failure; λ̂ in Clarabel's convention q + Âᵀλ̂ = 0 on the free factors."""
        m, p = self.shape
        h, status = self._h, self._status
        batch = getattr(_batches, "current", 0)
        if batch != self._batch:
            self._batch = batch
            if self._start is _UNSET:
                self._start = self._feasible_basis()
            h.clearSolver()  # no state of earlier batches (edge weights, perturbations) carries over
            if self._start is not None:
                h.setBasis(self._start)
        h.changeColsCost(p, self._columns, np.asarray(q, dtype=float))
        name = "NumericalError"
        for tolerance, cap in zip(tolerances, caps):
            self._set_rung(tolerance, cap)
            h.run()
            model_status = h.getModelStatus()
            if model_status == status.kOptimal:
                sol = h.getSolution()
                # HiGHS's row duals are ∂(min)/∂b̂, i.e. q = Âᵀy + (bound duals): λ̂ = −y.
                return ("AlmostSolved", np.array(sol.col_value, dtype=float),
                        -np.array(sol.row_dual, dtype=float))
            if model_status == status.kInfeasible:
                name = "PrimalInfeasible"
            elif model_status in (status.kUnbounded, status.kUnboundedOrInfeasible):
                name = "DualInfeasible"
            else:
                name = ("MaxIterations" if model_status == status.kIterationLimit
                        else "NumericalError")
                h.clearSolver()  # the next rung starts cold
                continue
            break  # an infeasible or unbounded verdict is the caller's to judge
        h.clearSolver()
        return name, np.full(p, np.nan), np.full(m, np.nan)
