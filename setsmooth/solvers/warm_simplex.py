"""HiGHS's simplex method on one presolved factor set, warm-started across objectives.

The support fallback (`presolve.simplex`) solves the same constraints {Âη = b̂, |η_B| ≤ 1} for
many objectives: the 2n directions of an interval hull, and their certified twins. SciPy's
``linprog`` builds and solves each from scratch; here one HiGHS model is kept per presolved program
and thread (`instances.cached_instance`), only its costs change, and every solve starts from the
previous optimal basis, which stays primal feasible for a new objective, within a batch of queries
(`new_batch`); a batch starts from the program's feasible basis. From a feasible basis the primal
method answers (only the costs changed: straight to its phase two), from scratch the dual one. On
the recursion smoother's sets (3,000 factors, 2,000 rows) the cold solves took ~2,300 iterations
each; from the last optimum the primal method takes ~80.

The tolerance ladder is `presolve.SIMPLEX_TOLERANCES`, each rung capped and timed as there
(`presolve._rung_iterations`, `presolve.rung_seconds`); a rung that does not settle is dropped
with its basis (``clearSolver``), so the next, looser rung starts cold and cannot inherit a cycling
basis, and after a rung that ran out of time the dual method no longer perturbs the costs (and
the caller asks the interior-point method first for the rest of the batch, `timed_out_in_batch`).
"""

from __future__ import annotations

import itertools
import os
import sys
import threading

import numpy as np
import scipy.sparse as sp

from .presolve import SIMPLEX_TOLERANCES, _rung_iterations, rung_seconds

__all__ = ["WarmSimplex", "current_batch", "factor_model", "new_batch", "settled_point"]

_UNSET = object()
_DUAL, _PRIMAL = 1, 4  # HiGHS's simplex_strategy values

#: HiGHS's simplex variant for a solve from a primal feasible basis (the batch's start, the last
#: optimum): ``_PRIMAL`` (see `WarmSimplex._set_rung`; ``benchmarks/bench_warm_simplex.py`` compares
#: it with ``_DUAL``, the variant of every cold solve).
WARM_STRATEGY = _PRIMAL

#: HiGHS's simplex_scale_strategy for the feasible basis, tried in turn (None: HiGHS's default; see
#: `WarmSimplex._feasible_basis`).
FEASIBLE_BASIS_SCALINGS = (0, None)

_batches = threading.local()
_batch_ids = itertools.count(1)  # batch ids unique across threads (next() is atomic under the GIL)


def current_batch() -> int:
    """This thread's current batch (`new_batch`): an id no other batch of any thread shares."""
    batch = getattr(_batches, "current", None)
    if batch is None:
        batch = _batches.current = next(_batch_ids)
    return batch


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
    _batches.current = next(_batch_ids)


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


def factor_model(A: sp.spmatrix, b: np.ndarray, bounded: np.ndarray):
    """A quiet ``highspy.Highs`` holding min 0ᵀη subject to Aη = b, |η_j| ≤ 1 where ``bounded``
    (the costs are set per objective)."""
    import highspy

    A = sp.csc_matrix(A)
    m, p = A.shape
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
    return h


def settled_point(h) -> tuple[np.ndarray, np.ndarray] | None:
    """(η, λ̂) of a ``highspy.Highs`` run that stopped at 'Optimal', or at 'Unknown' with a valid
    primal and dual solution (an answer for the caller's independent check,
    `presolve.Presolved.checked_gap`); None otherwise. λ̂ is in Clarabel's convention: HiGHS's row
    duals y are ∂(min)/∂b̂, i.e. q = Âᵀy + (bound duals), so λ̂ = −y."""
    import highspy

    status = highspy.HighsModelStatus
    model_status = h.getModelStatus()
    if model_status not in (status.kOptimal, status.kUnknown):
        return None
    sol = h.getSolution()
    if model_status != status.kOptimal and not (sol.value_valid and sol.dual_valid):
        return None
    return np.array(sol.col_value, dtype=float), -np.array(sol.row_dual, dtype=float)


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

        m, p = A.shape
        self.shape = (m, p)
        self._status = highspy.HighsModelStatus
        h = factor_model(A, b, bounded)
        self._h = h
        self._columns = np.arange(p, dtype=np.int32)
        self._start = _UNSET  # the feasible basis, found when the first batch starts
        self._batch = None
        self._timed_out_batch = None  # the batch in which a rung last ran out of time
        default = h.getOptionValue("simplex_scale_strategy")  # a (status, value) pair in recent highspy
        self._scaling = default[1] if isinstance(default, tuple) else default
        self._warm = False  # whether HiGHS holds a primal feasible basis (the primal method's start)
        #: Whether the last `minimize` answer came from the primal method (`presolve.simplex` asks
        #: the dual method again only then: a ladder that fell through to the cold dual rungs has
        #: had its dual answer, and repeating it doubled the time of a cycling program).
        self.answered_by_primal = False

    def timed_out_in_batch(self) -> bool:
        """Whether a rung of this model ran out of time (`presolve.rung_seconds`) in the current
        batch of this thread (`new_batch`): the caller then asks another method first for the
        batch's remaining objectives (`factor_set.AFTER_TIME_OUT_ATTEMPTS`)."""
        return self._timed_out_batch == current_batch()

    def _set_rung(self, tolerance: float | None, cap: int, primal: bool = False,
                  perturbed: bool = True) -> None:
        """HiGHS's primal and dual feasibility tolerance (None: its default, 1e-7), iteration cap,
        time limit (`presolve.rung_seconds`), simplex variant: the primal method (from a
        primal feasible basis), else the dual one, and whether the dual method perturbs the costs
        (HiGHS's default; see `minimize` for when it does not).

        From a feasible basis only the costs have changed, so the primal method goes straight to
        its phase two; the dual method must first restore dual feasibility. On the recursion
        smoother's hull of reliability case 058 (2,806 rows, 5,475 factors) the 12 directions took
        986 primal iterations (0.24 s) against 3,700 dual ones (2.5 s), to the same values.
        The primal method's duals can be loose on ill-conditioned programs: `presolve.simplex`
        then asks the dual method from the batch's start."""
        value = 1e-7 if tolerance is None else tolerance
        self._h.setOptionValue("primal_feasibility_tolerance", value)
        self._h.setOptionValue("dual_feasibility_tolerance", value)
        self._h.setOptionValue("simplex_iteration_limit", int(cap))
        # HiGHS's time limit is on the model's run time summed over all its solves: from now.
        self._h.setOptionValue("time_limit", self._h.getRunTime() + rung_seconds(sum(self.shape)))
        self._h.setOptionValue("simplex_strategy", WARM_STRATEGY if primal else _DUAL)
        self._h.setOptionValue("dual_simplex_cost_perturbation_multiplier",
                               1.0 if perturbed else 0.0)

    def _feasible_basis(self):
        """The basis every batch starts from: the optimal basis of the zero objective (a feasible
        vertex), or None (cold starts) when that program does not settle at the first rung's
        tolerance.

        HiGHS's own scaling is off for this solve first: the presolved program is equilibrated
        already (`presolve.presolve`), and on the recursion smoother's hull of reliability case 058
        the zero objective took 0.35 s unscaled against 0.88 s scaled, the directions from either
        basis reaching the same values (`benchmarks/bench_warm_simplex.py`). Scaling is back on for
        the directions, whose optimality is judged in HiGHS's scaled units, and for a retry when
        the unscaled solve does not settle.
        """
        h, p = self._h, self.shape[1]
        h.changeColsCost(p, self._columns, np.zeros(p))
        self._set_rung(SIMPLEX_TOLERANCES[0], _rung_iterations(sum(self.shape), False))
        basis = None
        for scaling in FEASIBLE_BASIS_SCALINGS:
            h.setOptionValue("simplex_scale_strategy", self._scaling if scaling is None else scaling)
            h.run()
            if h.getModelStatus() == self._status.kOptimal:
                basis = h.getBasis()
            h.clearSolver()
            if basis is not None:
                break
        h.setOptionValue("simplex_scale_strategy", self._scaling)
        return basis

    def _restart(self) -> None:
        """Back to the batch's start: the program's feasible basis (found at the first batch), or
        nothing (a cold start) when it has none. No state of earlier solves (edge weights,
        perturbations) carries over."""
        if self._start is _UNSET:
            self._start = self._feasible_basis()
        self._h.clearSolver()
        self._warm = self._start is not None
        if self._warm:
            self._h.setBasis(self._start)

    def minimize(self, q: np.ndarray, tolerances: tuple, caps: list[int], dual: bool = False
                 ) -> tuple[str, np.ndarray, np.ndarray]:
        """(status name, η, λ̂) through the rungs (``tolerances[i]``: HiGHS's primal and dual
        feasibility tolerance, None for its defaults; ``caps[i]``: the rung's iteration cap).

        The primal method from the current basis (the last optimum of the batch, or its start),
        the dual method where there is none; ``dual``: the dual method from the batch's start (a
        second opinion on an objective whose primal answer was loose).

        Status names as `presolve.simplex`: 'AlmostSolved' for an optimum (checked by the caller),
        'PrimalInfeasible', 'DualInfeasible', 'MaxIterations' or 'NumericalError' for the last
        rung's failure; λ̂ in Clarabel's convention q + Âᵀλ̂ = 0 on the free factors."""
        m, p = self.shape
        h, status = self._h, self._status
        batch = current_batch()
        if batch != self._batch or dual:
            self._batch = batch
            self._restart()
        h.changeColsCost(p, self._columns, np.asarray(q, dtype=float))
        name = "NumericalError"
        self.answered_by_primal = False
        perturbed = True
        for tolerance, cap in zip(tolerances, caps):
            primal = self._warm and not dual
            self._set_rung(tolerance, cap, primal=primal, perturbed=perturbed)
            h.run()
            model_status = h.getModelStatus()
            if model_status == status.kTimeLimit:
                # HiGHS's dual method looping in the primal clean-up that follows its removal of
                # the cost perturbation (`presolve.RUNG_SECONDS_FLOOR`): the later rungs solve
                # unperturbed. On the program that hung, the unperturbed dual method settled the
                # same objective in 2,191 iterations, 0.2 s.
                perturbed = False
                self._timed_out_batch = batch
            point = settled_point(h)
            if point is not None:
                # 'Unknown' with a primal and dual solution: HiGHS stopped short of confirming
                # optimality, often at the optimum (reliability case 184, k = 8: the primal
                # method's 'Unknown' point had residual 3e-10 and the optimal value to 1e-12,
                # where the cold rungs that followed failed or left residuals of 1e-5). The
                # caller's independent check (`Presolved.checked_gap`) decides either way.
                self._warm = model_status == status.kOptimal  # a basis known primal feasible
                self.answered_by_primal = primal
                return ("AlmostSolved", *point)
            if model_status == status.kInfeasible:
                name = "PrimalInfeasible"
            elif model_status in (status.kUnbounded, status.kUnboundedOrInfeasible):
                name = "DualInfeasible"
            else:
                name = ("MaxIterations"
                        if model_status in (status.kIterationLimit, status.kTimeLimit)
                        else "NumericalError")
                h.clearSolver()  # the next rung starts cold
                self._warm = False
                continue
            break  # an infeasible or unbounded verdict is the caller's to judge
        h.clearSolver()
        self._warm = False
        return name, np.full(p, np.nan), np.full(m, np.nan)
