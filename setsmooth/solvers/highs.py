"""HiGHS through highspy: the simplex and interior-point backends of the factor-set programs.

Every HiGHS solve here is bounded by iteration counts only (``simplex_iteration_limit``,
``ipm_iteration_limit``), never by time: the same program gives the same answer on any machine under
any load. A solve runs through a ladder of feasibility tolerances (`SIMPLEX_TOLERANCES`,
`DECISION_TOLERANCES`), each rung capped (`rung_iterations`); a rung that does not settle is
dropped with its basis (``clearSolver``), so the next, looser one starts cold and cannot inherit a
cycling basis. Every answer is checked independently by the caller (`Presolved.checked_gap`, or
the certificate bracket of `CZProgram`), and certified bounds hold for any multipliers, so a looser
rung costs tightness, never soundness.

Multipliers are returned in Clarabel's sign convention: for min qᵀη subject to Âη = b̂ the row
multipliers λ̂ satisfy q + Âᵀλ̂ = 0 on the free factors (HiGHS's row duals y are ∂(min)/∂b̂, so
λ̂ = −y); for rows·x ≤ r, z ≥ 0 with q + rowsᵀz = 0.
"""

from __future__ import annotations

import os
import struct
import sys
import threading

import numpy as np
import scipy.sparse as sp

__all__ = ["SIMPLEX_TOLERANCES", "DECISION_TOLERANCES", "IPM_OPTIMALITY_TOLERANCE", "quiet_highs",
           "rung_iterations", "rung_caps", "lp_model", "factor_model", "settled_point", "ladder",
           "DirectionModels", "simplex_cold", "simplex_inequalities", "simplex_box_equalities", "interior_point"]

#: HiGHS's primal and dual feasibility tolerances for the support programs, tried in turn (None:
#: HiGHS's defaults, 1e-7). The defaults alone left duality gaps of ~1e-7 of the objective's scale,
#: which a certified bound built on the multipliers keeps; but on degenerate, ill-conditioned
#: programs (σ_min(Â) ≈ 6e-8) the tight tolerance alone cycles for hundreds of thousands of
#: iterations where the defaults need a few hundred. Each rung is therefore capped.
SIMPLEX_TOLERANCES = (1e-10, 1e-9, None)

#: The ladder of the programs whose optimal value decides something (the elastic phase-one program:
#: empty iff its optimum exceeds ``EMPTINESS_TOL`` = 1e-8; the recession program: unbounded iff its
#: gain exceeds ``REDUCED_COST_TOL``). They stop at 1e-9, an order below those thresholds.
DECISION_TOLERANCES = (1e-10, 1e-9)

#: HiGHS's ``ipm_optimality_tolerance``: two orders below ``tolerances.ACCURATE_GAP_TOL``, the
#: relative gap the caller's check accepts (HiGHS's default is 1e-8, that gap itself).
IPM_OPTIMALITY_TOLERANCE = 1e-10

_DUAL, _PRIMAL = 1, 4  # HiGHS's simplex_strategy values


def rung_iterations(size: int, last: bool) -> int:
    """Iteration cap of a rung for a program of ``size`` = rows + columns: size + 200 for the tight
    rungs (their successful solves need about size/2), 20·size + 1000 for the last (a guard against
    cycling)."""
    return 20 * size + 1000 if last else size + 200


def rung_caps(size: int, rungs: int) -> list[int]:
    """The iteration caps of a ladder of ``rungs`` rungs (`rung_iterations`)."""
    return [rung_iterations(size, rung == rungs - 1) for rung in range(rungs)]


_BANNER_LOCK = threading.Lock()
_banner_shown = False


def quiet_highs():
    """A ``highspy.Highs`` with its output off. HiGHS prints a banner to the process's standard
    output when the first model of a process is made, before any option can be set; that one
    construction runs with file descriptor 1 pointed at the null device (a library must not print
    on its users' terminals)."""
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
    return h


def lp_model(A: sp.spmatrix, row_lower: np.ndarray, row_upper: np.ndarray, col_lower: np.ndarray,
             col_upper: np.ndarray, solver: str = "simplex"):
    """A quiet ``highspy.Highs`` holding min 0ᵀx subject to row_lower ≤ Ax ≤ row_upper and
    col_lower ≤ x ≤ col_upper (±inf allowed); costs are set per objective."""
    import highspy

    if not (sp.issparse(A) and A.format == "csc"):
        A = sp.csc_matrix(A)
    m, p = A.shape
    inf = highspy.kHighsInf
    h = quiet_highs()
    h.setOptionValue("solver", solver)
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = p, m
    lp.col_cost_ = np.zeros(p)
    lp.col_lower_ = np.clip(np.asarray(col_lower, dtype=float), -inf, inf)
    lp.col_upper_ = np.clip(np.asarray(col_upper, dtype=float), -inf, inf)
    lp.row_lower_ = np.clip(np.asarray(row_lower, dtype=float), -inf, inf)
    lp.row_upper_ = np.clip(np.asarray(row_upper, dtype=float), -inf, inf)
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = A.indptr
    lp.a_matrix_.index_ = A.indices
    lp.a_matrix_.value_ = A.data
    lp.a_matrix_.num_col_, lp.a_matrix_.num_row_ = p, m
    h.passModel(lp)
    return h


def factor_model(A: sp.spmatrix, b: np.ndarray, bounded: np.ndarray, solver: str = "simplex"):
    """`lp_model` of the presolved factor set: Aη = b, |η_j| ≤ 1 where ``bounded``."""
    return lp_model(A, b, b, np.where(bounded, -1.0, -np.inf), np.where(bounded, 1.0, np.inf),
                    solver)


def settled_point(h) -> tuple[np.ndarray, np.ndarray] | None:
    """(x, −y) of a run that stopped at 'Optimal', or at 'Unknown' with a valid primal and dual
    solution (HiGHS stopped short of confirming optimality, often at the optimum: an answer for the
    caller's independent check); None otherwise. y are HiGHS's row duals."""
    import highspy

    status = highspy.HighsModelStatus
    model_status = h.getModelStatus()
    if model_status not in (status.kOptimal, status.kUnknown):
        return None
    sol = h.getSolution()
    if model_status != status.kOptimal and not (sol.value_valid and sol.dual_valid):
        return None
    x, y = _array(sol.col_value), _array(sol.row_dual)
    return x, np.negative(y, out=y)


def _array(values: list) -> np.ndarray:
    """A float array of one of highspy's solution lists, its doubles packed straight into the
    array's buffer (``struct.pack_into``: the same bits as ``np.array(values, dtype=float)``, about
    3× faster on the 4,000-entry lists of a warm solve, where ``np.array`` cost more than reading
    the list itself)."""
    out = np.empty(len(values))
    struct.pack_into(f"{len(values)}d", out, 0, *values)
    return out


def verdict(h) -> str:
    """The status name (Clarabel's vocabulary) of a run that did not settle."""
    import highspy

    status = highspy.HighsModelStatus
    names = {status.kInfeasible: "PrimalInfeasible", status.kUnbounded: "DualInfeasible",
             status.kUnboundedOrInfeasible: "DualInfeasible",
             status.kIterationLimit: "MaxIterations"}
    return names.get(h.getModelStatus(), "NumericalError")


def set_rung(h, tolerance: float | None, cap: int, strategy: int = _DUAL) -> None:
    """HiGHS's primal and dual feasibility tolerance (None: its default, 1e-7), simplex iteration
    cap and simplex variant for the next run of ``h``, with the dual method's cost perturbation off.

    The perturbation is why an iteration cap alone could not bound a run: after the perturbed
    problem is solved, HiGHS removes the perturbation and cleans up with its primal method, which
    the cap does not stop; unperturbed, the cap bounds the whole run (docs/numerical_core.md)."""
    value = 1e-7 if tolerance is None else tolerance
    h.setOptionValue("primal_feasibility_tolerance", value)
    h.setOptionValue("dual_feasibility_tolerance", value)
    h.setOptionValue("simplex_iteration_limit", int(cap))
    h.setOptionValue("simplex_strategy", strategy)
    h.setOptionValue("dual_simplex_cost_perturbation_multiplier", 0.0)


def cold_ladder(h, q: np.ndarray, tolerances: tuple) -> tuple[str, np.ndarray | None,
                                                             np.ndarray | None]:
    """min qᵀx on the model ``h`` from scratch through ``tolerances``: ('AlmostSolved', x, −y) at
    the first rung that settles, the verdict of the first infeasible or unbounded rung (the caller
    judges it), or the last rung's failure, with None for x and y."""
    p = h.getNumCol()
    h.changeColsCost(p, np.arange(p, dtype=np.int32), np.asarray(q, dtype=float))
    return ladder(h, tolerances)


def ladder(h, tolerances: tuple) -> tuple[str, np.ndarray | None, np.ndarray | None]:
    """The dual simplex method on the model ``h`` as it stands (from its current basis, if it has
    one) through ``tolerances``, a rung that does not settle dropped with its basis so that the next
    starts cold: ('AlmostSolved', x, −y) at the first rung that settles, the verdict of the first
    infeasible or unbounded rung, or the last rung's failure, with None for x and y."""
    name = "NumericalError"
    for tolerance, cap in zip(tolerances, rung_caps(h.getNumCol() + h.getNumRow(), len(tolerances))):
        set_rung(h, tolerance, cap)
        h.run()
        point = settled_point(h)
        if point is not None:
            return ("AlmostSolved", *point)
        name = verdict(h)
        if name in ("PrimalInfeasible", "DualInfeasible"):
            break
        h.clearSolver()
    return name, None, None


class DirectionModels:
    """One HiGHS model per objective over a constraint matrix shared by a sequence of programs
    min q_jᵀξ s.t. Aξ = b, |ξ_i| ≤ h_i (ξ_i free where ``free``), of which only b and h change:
    each objective's model keeps its optimal basis from one program to the next and is re-solved
    by the dual simplex method through ``SIMPLEX_TOLERANCES`` (`ladder`). A change of b and h
    leaves a basis dual feasible (the objective did not change), so the dual method starts at once;
    nothing is presolved or rebuilt per program. The state of one sequence: one thread at a time.

    Parameters
    ----------
    A : scipy.sparse.csc_matrix, shape (m, p)
    Q : ndarray, shape (K, p)
        The objectives (minimized).
    free : ndarray of bool, shape (p,)
    """

    def __init__(self, A: sp.csc_matrix, Q: np.ndarray, free: np.ndarray):
        self.A, self.Q, self.free = A, Q, free
        self.fin = np.flatnonzero(~free).astype(np.int32)
        self.rows = np.arange(A.shape[0], dtype=np.int32)
        self.models: list | None = None

    def solve(self, j: int, b: np.ndarray, h: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
        """Objective ``j`` over {Aξ = b, |ξ| ≤ h} from its model's last basis: (status name, ξ, λ̂)
        as `ladder` gives them (λ̂ in Clarabel's convention), NaNs where the ladder did not settle."""
        m, p = self.A.shape
        if self.models is None:
            lower = np.where(self.free, -np.inf, -h)
            self.models = [lp_model(self.A, b, b, lower, -lower) for _ in self.Q]
            for model, q in zip(self.models, self.Q):
                model.changeColsCost(p, np.arange(p, dtype=np.int32), q)
        model = self.models[j]
        model.changeRowsBounds(m, self.rows, b, b)
        if self.fin.size:
            model.changeColsBounds(self.fin.size, self.fin, -h[self.fin], h[self.fin])
        name, x, lam = ladder(model, SIMPLEX_TOLERANCES)
        return name, (np.full(p, np.nan) if x is None else x), (np.full(m, np.nan) if lam is None else lam)


def simplex_cold(pre, q: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀη over the presolved program by HiGHS's dual simplex method from scratch (HiGHS's own
    presolve and scaling), through ``SIMPLEX_TOLERANCES``: (status name, η, λ̂), NaNs unless
    'AlmostSolved' (an optimum for the caller to check)."""
    m, p = pre.A.shape
    name, eta, lam = cold_ladder(factor_model(pre.A, pre.b, pre.bounded), q, SIMPLEX_TOLERANCES)
    if eta is None:
        return name, np.full(p, np.nan), np.full(m, np.nan)
    return name, eta, lam


def simplex_inequalities(q: np.ndarray, rows: sp.csc_matrix, r: np.ndarray
                         ) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀx subject to rows·x ≤ r (x free), through ``DECISION_TOLERANCES``: ('optimal', x, z)
    with z ≥ 0 and q + rowsᵀz = 0, or (the status name, NaNs, NaNs). The fallback of the
    always-feasible programs (phase one, the relaxed support program)."""
    k, n = rows.shape
    h = lp_model(rows, np.full(k, -np.inf), r, np.full(n, -np.inf), np.full(n, np.inf))
    name, x, z = cold_ladder(h, q, DECISION_TOLERANCES)
    if x is None:
        return name, np.full(n, np.nan), np.full(k, np.nan)
    return "optimal", x, z


def simplex_box_equalities(q: np.ndarray, A: sp.csc_matrix) -> tuple[str, np.ndarray]:
    """min qᵀη subject to Aη = 0, |η| ≤ 1 through ``DECISION_TOLERANCES``: ('optimal', η) or (the
    status name, NaNs). The fallback of the recession program (feasible at η = 0, bounded)."""
    m, n = A.shape
    h = factor_model(A, np.zeros(m), np.ones(n, dtype=bool))
    name, eta, _ = cold_ladder(h, q, DECISION_TOLERANCES)
    return ("optimal", eta) if eta is not None else (name, np.full(n, np.nan))


def interior_point(pre, q: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀη over the presolved program by HiGHS's interior-point method from scratch, without
    crossover: (status name, η, λ̂) as `simplex_cold`.

    Every other HiGHS backend ends in a simplex basis. On nearly flat sets the optimal bases are
    nearly singular and all of them can fail together, where the interior solution (not a vertex;
    the value and the multipliers are what callers use, and the check judges them) settles
    (docs/numerical_core.md).
    """
    m, p = pre.A.shape
    h = factor_model(pre.A, pre.b, pre.bounded, solver="ipm")
    h.changeColsCost(p, np.arange(p, dtype=np.int32), np.asarray(q, dtype=float))
    h.setOptionValue("run_crossover", "off")
    h.setOptionValue("ipm_optimality_tolerance", IPM_OPTIMALITY_TOLERANCE)
    h.setOptionValue("ipm_iteration_limit", rung_iterations(m + p, False))
    h.run()
    point = settled_point(h)
    if point is not None:
        return ("AlmostSolved", *point)
    return verdict(h), np.full(p, np.nan), np.full(m, np.nan)
