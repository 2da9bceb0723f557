"""HiGHS's simplex method on one presolved factor set, warm-started across the objectives of a batch.

The support programs solve the same constraints {Âη = b̂, |η_B| ≤ 1} for many objectives: the 2n
directions of an interval hull, and their certified twins. One HiGHS model is kept per presolved
program and thread (`instances.cached_instance`), only its costs change, and every solve of a
*batch* (one support call, named by the caller's token) starts from the previous optimal basis,
which stays primal feasible for a new objective; a batch starts from the program's feasible basis.
From a feasible basis the primal method answers (only the costs changed: straight to its phase
two), from scratch the dual one. On the recursion smoother's sets (3,000 factors, 2,000 rows) the
cold solves took ~2,300 iterations each; from the last optimum the primal method takes ~80.

A batch's answers are a function of the program and the batch's objectives alone, the same in every
thread and whatever other sets sharing the program were queried before: the optimal vertex of a
degenerate program depends on the start, and warm starts across batches made threads sharing a
factor set differ from the serial run by 1e-15 of a hull. The batch is an argument, not state of
the thread.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .highs import (_DUAL, _PRIMAL, SIMPLEX_TOLERANCES, factor_model, rung_caps, set_rung,
                    settled_point, verdict)
from .instances import cached_instance

__all__ = ["WarmSimplex", "simplex", "checked_simplex", "WARM_MODEL_KEY"]

#: The key of a program's warm model in the per-thread instance cache.
WARM_MODEL_KEY = "warm simplex"

_NO_BATCH = object()

#: HiGHS's simplex variant for a solve from a primal feasible basis (the batch's start, the last
#: optimum): the primal method, about 10× faster there than the dual one, the variant of every cold
#: solve (``benchmarks/bench_warm_simplex.py``; evidence: docs/numerical_core.md).
WARM_STRATEGY = _PRIMAL

#: HiGHS's simplex_scale_strategy for the feasible basis, tried in turn (None: HiGHS's default; see
#: `WarmSimplex._feasible_basis`).
FEASIBLE_BASIS_SCALINGS = (0, None)


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
        self._h = factor_model(A, b, bounded)
        self._columns = np.arange(p, dtype=np.int32)
        self._start = None  # the feasible basis, found when the first batch starts
        self._started = False
        self._batch: object = _NO_BATCH  # the first solve of any batch starts from the start
        default = self._h.getOptionValue("simplex_scale_strategy")  # (status, value) in recent highspy
        self._scaling = default[1] if isinstance(default, tuple) else default
        self._warm = False  # whether HiGHS holds a primal feasible basis (the primal method's start)
        #: Whether the last `minimize` answer came from the primal method (`simplex` asks the dual
        #: method again only then).
        self.answered_by_primal = False

    def _feasible_basis(self):
        """The basis every batch starts from: the optimal basis of the zero objective (a feasible
        vertex), or None (cold starts) when that program does not settle at the first rung.

        HiGHS's own scaling is off for this solve first: the presolved program is equilibrated
        already, and unscaled it is about 2.5× faster (`benchmarks/bench_warm_simplex.py`). Scaling
        is back on for the directions, and for a retry when the unscaled solve does not settle.
        """
        h, p = self._h, self.shape[1]
        h.changeColsCost(p, self._columns, np.zeros(p))
        set_rung(h, SIMPLEX_TOLERANCES[0], rung_caps(sum(self.shape), 2)[0])
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
        """Back to the batch's start: the program's feasible basis, or a cold start when it has
        none. (HiGHS keeps some state of earlier solves through ``clearSolver``, and a fresh
        model does not remove it either: a batch's first answer can differ by ~1e-15 relative
        with the batches solved before it.)"""
        if not self._started:
            self._start, self._started = self._feasible_basis(), True
        self._h.clearSolver()
        self._warm = self._start is not None
        if self._warm:
            self._h.setBasis(self._start)

    def minimize(self, q: np.ndarray, batch: object, dual: bool = False
                 ) -> tuple[str, np.ndarray, np.ndarray]:
        """(status name, η, λ̂) through the rungs ``SIMPLEX_TOLERANCES``.

        The primal method from the current basis (the batch's last optimum, or its start), the dual
        method where there is none; ``dual``: the dual method from the batch's start (a second
        opinion on an objective whose primal answer was loose). A solve of another ``batch`` than
        the last starts from the program's feasible basis.

        Status names: 'AlmostSolved' for an optimum (checked by the caller), 'PrimalInfeasible',
        'DualInfeasible', 'MaxIterations' or 'NumericalError' for the last rung's failure."""
        m, p = self.shape
        h = self._h
        if batch is not self._batch or dual:
            self._batch = batch
            self._restart()
        h.changeColsCost(p, self._columns, np.asarray(q, dtype=float))
        name = "NumericalError"
        self.answered_by_primal = False
        for tolerance, cap in zip(SIMPLEX_TOLERANCES, rung_caps(m + p, len(SIMPLEX_TOLERANCES))):
            primal = self._warm and not dual
            set_rung(h, tolerance, cap, WARM_STRATEGY if primal else _DUAL)
            h.run()
            point = settled_point(h)
            if point is not None:
                self._warm = h.getModelStatus() == self._status.kOptimal  # a basis known feasible
                self.answered_by_primal = primal
                return ("AlmostSolved", *point)
            name = verdict(h)
            if name in ("PrimalInfeasible", "DualInfeasible"):
                break  # the caller's to judge
            h.clearSolver()  # the next rung starts cold
            self._warm = False
        h.clearSolver()
        self._warm = False
        return name, np.full(p, np.nan), np.full(m, np.nan)


def simplex(pre, q: np.ndarray, batch: object) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀη over the presolved program by the warm-started simplex method of ``batch``: (status
    name, η, λ̂ in Clarabel's convention q + Âᵀλ̂ = 0 on the free factors).

    The primal method from the batch's last basis, and the dual method from the batch's start when
    the primal answer fails `Presolved.checked_gap` at ``ACCURATE_GAP_TOL`` (on ill-conditioned
    programs the primal method's duals can be loose: gaps of 2.7e-7 to 8e-7 on 4 of 8 objectives of
    the test suite's cycling program, where the dual method's are below 3e-9)."""
    return checked_simplex(pre, q, batch)[:3]


def checked_simplex(pre, q: np.ndarray, batch: object
                    ) -> tuple[str, np.ndarray, np.ndarray, float]:
    """`simplex` and the answer's `Presolved.checked_gap` (inf when it is not an optimum or fails
    the check), so that the caller need not check it again."""
    model = cached_instance(pre, WARM_MODEL_KEY, lambda: WarmSimplex(pre.A, pre.b, pre.bounded))
    answer = model.minimize(q, batch)
    gap = _gap_or_inf(pre, q, answer)
    if gap > tol.ACCURATE_GAP_TOL and model.answered_by_primal:
        again = model.minimize(q, batch, dual=True)
        again_gap = _gap_or_inf(pre, q, again)
        if again_gap < gap or np.isinf(gap):
            answer, gap = again, again_gap
    return (*answer, gap)


def _gap_or_inf(pre, q: np.ndarray, answer: tuple) -> float:
    """`Presolved.checked_gap` of a simplex answer; inf when it is not an optimum or fails."""
    name, eta, z = answer
    gap = pre.checked_gap(q, eta, z) if name == "AlmostSolved" else None
    return np.inf if gap is None else gap
