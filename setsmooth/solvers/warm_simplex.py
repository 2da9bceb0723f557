"""HiGHS's simplex method on one presolved factor set, warm-started across the objectives of a batch.

The support programs solve the same constraints {Âη = b̂, |η_B| ≤ 1} for many objectives: the 2n
directions of an interval hull, and their certified twins. One HiGHS model is kept per presolved
program and thread (`instances.cached_instance`), only its costs change, and every solve of a
*batch* (one support call, named by the caller's token) starts from the previous optimal basis,
which stays primal feasible for a new objective; a batch starts from the program's feasible basis.
From a feasible basis the primal method answers (only the costs changed: straight to its phase
two), from scratch the dual one. On the recursion smoother's sets (3,000 factors, 2,000 rows) the
cold solves took ~2,300 iterations each; from the last optimum the primal method takes ~80.

A small program solves a batch's objectives at once instead, as one block-diagonal LP (`Batch`): on
an interval hull of a 2-D set with 20 factors one HiGHS run costs what the warm runs cost each.

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
from .highs import (_DUAL, _PRIMAL, SIMPLEX_TOLERANCES, cold_ladder, factor_model, rung_caps,
                    set_rung, settled_point, verdict)
from .instances import cached_instance

__all__ = ["Batch", "WarmSimplex", "simplex", "checked_simplex", "WARM_MODEL_KEY", "BLOCK_SIZE_MAX"]

#: The key of a program's warm model in the per-thread instance cache.
WARM_MODEL_KEY = "warm simplex"

_NO_BATCH = object()

#: Largest k·(m + p) of a batch of k objectives over an (m, p) program that is solved as one block
#: LP (`Batch`): below it one HiGHS run on the k copies costs less than the feasible basis and the k
#: warm runs, whose fixed cost per run dominates on small programs. Certified interval hulls of
#: random CZs, CPU ms per hull, warm runs against the block: k(m + p) = 112: 5.98 / 4.70, 252:
#: 8.60 / 7.07, 448: 12.2 / 10.8, 1,008: 24.4 / 25.1, 2,800: 99 / 127.
BLOCK_SIZE_MAX = 800


class Batch:
    """The token of one support call: its objectives, so that a small program solves them at once.

    The answers of a batch are a function of the program and the batch's objectives alone
    (module docstring). On a program with k·(m + p) ≤ ``BLOCK_SIZE_MAX`` the batch's k objectives
    are solved as one LP over k copies of the program, min Σ_j q_jᵀη_j subject to Âη_j = b̂ and the
    bounds, block-diagonal, so that its optimum is every copy's optimum and its row duals are every
    copy's; an objective the block did not settle goes the warm way.

    Parameters
    ----------
    objectives : ndarray, shape (k, ng)
        The maximized objectives on the original factors, in the order they will be asked (k = 0:
        not listed ahead, never solved as one block LP).
    own_model : bool
        Solve on a model of the batch's own (a twin of the thread's kept one, starting from the
        same feasible basis) instead of the kept one: for batches asked in turn, each continuing
        from its own last optimum (`shared_supports`'s chains). It lives as long as the batch.
    """

    def __init__(self, objectives: np.ndarray, *, own_model: bool = False):
        self.objectives = objectives
        self._own: dict | None = {} if own_model else None

    def model(self, pre) -> "WarmSimplex":
        """The warm model of the presolved program ``pre`` that this batch's solves use."""
        kept = cached_instance(pre, WARM_MODEL_KEY, lambda: WarmSimplex(pre.A, pre.b, pre.bounded))
        if self._own is None:
            return kept
        own = self._own.get(id(pre))
        if own is None or own[0] is not pre:
            own = self._own[id(pre)] = (pre, kept.twin())
        return own[1]

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
        self._data = (A, b, bounded)
        self._model = None  # the HiGHS model, made on the first warm solve (`_h`)
        self._cost = np.zeros(p)  # the model's cost vector (`_set_cost`)
        self._start = None  # the feasible basis, found when the first batch starts
        self._started = False
        self._batch: object = _NO_BATCH  # the first solve of any batch starts from the start
        self._scaling = None  # HiGHS's default simplex_scale_strategy, read with the model
        self._warm = False  # whether HiGHS holds a primal feasible basis (the primal method's start)
        self._block: tuple[object, dict] | None = None  # (batch, its answers by objective)
        #: Whether the last `minimize` answer came from the primal method (`simplex` asks the dual
        #: method again only then).
        self.answered_by_primal = False

    @property
    def _h(self):
        """The HiGHS model of the program (made on first use: a batch its block LP settles needs
        none)."""
        if self._model is None:
            self._model = factor_model(*self._data)
            default = self._model.getOptionValue("simplex_scale_strategy")  # (status, value) or value
            self._scaling = default[1] if isinstance(default, tuple) else default
        return self._model

    def _feasible_basis(self):
        """The basis every batch starts from: the optimal basis of the zero objective (a feasible
        vertex), or None (cold starts) when that program does not settle at the first rung.

        HiGHS's own scaling is off for this solve first: the presolved program is equilibrated
        already, and unscaled it is about 2.5× faster (`benchmarks/bench_warm_simplex.py`). Scaling
        is back on for the directions, and for a retry when the unscaled solve does not settle.
        """
        h, p = self._h, self.shape[1]
        self._set_cost(np.zeros(p))
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

    def twin(self) -> "WarmSimplex":
        """A model of the same program whose batches start from this one's feasible basis (found
        here first if it is not yet)."""
        if not self._started:
            self._start, self._started = self._feasible_basis(), True
        other = WarmSimplex(*self._data)
        other._start, other._started = self._start, True
        return other

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
        self._set_cost(np.asarray(q, dtype=float))
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

    def _set_cost(self, q: np.ndarray) -> None:
        """The model's costs to ``q``, passing only the entries that differ: an objective of a
        large program touches a few factors, and the full vector cost 0.3 ms a solve (4,208
        columns). The model holds the same costs, bit for bit (−0.0 too), either way."""
        changed = np.flatnonzero(q.view(np.int64) != self._cost.view(np.int64)).astype(np.int32)
        if changed.size:
            self._h.changeColsCost(changed.size, changed, q[changed])
            self._cost = q.copy()

    def block_answer(self, pre, q: np.ndarray, batch: Batch) -> tuple | None:
        """The answer of the block LP of ``batch`` (`Batch`) for the objective ``q`` with its
        `Presolved.checked_gaps` gap, (status, η, λ̂, gap), or None when the block did not settle it
        (or the batch is too large, or q is not one of its objectives)."""
        if self._block is None or self._block[0] is not batch:
            self._block = (batch, self._solve_block(pre, batch))
        answers = self._block[1]
        return answers.get(q.tobytes()) if answers else None

    def _solve_block(self, pre, batch: Batch) -> dict:
        m, p = self.shape
        k = batch.objectives.shape[0]
        if k * (m + p) > BLOCK_SIZE_MAX or k < 2:
            return {}
        Q, _ = pre.minimized(batch.objectives)
        h = factor_model(_block_diagonal(pre.A, k), np.tile(pre.b, k), np.tile(pre.bounded, k))
        h.setOptionValue("presolve", "off")
        name, eta, lam = cold_ladder(h, Q.ravel(), SIMPLEX_TOLERANCES)
        if eta is None:
            return {}
        eta, lam = eta.reshape(k, p), lam.reshape(k, m)
        gaps = pre.checked_gaps(Q, eta, lam)
        return {Q[j].tobytes(): ("AlmostSolved", eta[j], lam[j], gaps[j]) for j in range(k)}


def _block_diagonal(A: sp.csc_matrix, k: int) -> sp.csc_matrix:
    """The block-diagonal CSC matrix of k copies of the CSC matrix A (scipy's ``block_diag``
    without its conversions)."""
    m, p = A.shape
    nnz = A.indptr[-1]
    indices = (A.indices[:nnz][None, :] + m * np.arange(k)[:, None]).ravel()
    indptr = np.concatenate([[0], (A.indptr[1:][None, :] + nnz * np.arange(k)[:, None]).ravel()])
    data = np.tile(A.data[:nnz], k)
    return sp.csc_matrix((data, indices, indptr), shape=(k * m, k * p))


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
    model = (batch.model(pre) if isinstance(batch, Batch) else
             cached_instance(pre, WARM_MODEL_KEY, lambda: WarmSimplex(pre.A, pre.b, pre.bounded)))
    checked = model.block_answer(pre, q, batch) if isinstance(batch, Batch) else None
    if checked is not None and checked[3] <= tol.ACCURATE_GAP_TOL:
        return checked
    answer = model.minimize(q, batch)  # not in the block, or not accurate there: the warm way
    gap = _gap_or_inf(pre, q, answer)
    if gap > tol.ACCURATE_GAP_TOL and model.answered_by_primal:
        again = model.minimize(q, batch, dual=True)
        again_gap = _gap_or_inf(pre, q, again)
        if again_gap < gap or np.isinf(gap):
            answer, gap = again, again_gap
    return (*answer, gap)


def _gap_or_inf(pre, q: np.ndarray, answer: tuple) -> float:
    """`Presolved.checked_gaps` of a simplex answer; inf when it is not an optimum or fails."""
    name, eta, z = answer
    if name != "AlmostSolved":
        return np.inf
    return float(pre.checked_gaps(q[None], eta[None], z[None])[0])
