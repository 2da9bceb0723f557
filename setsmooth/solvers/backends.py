"""The backends of the factor-set programs behind one interface, with one status vocabulary.

A backend solves min qᵀη over a presolved factor set {Âη = b̂, |η_B| ≤ 1} (`presolved.Presolved`):
``BACKENDS[name](pre, q, batch) -> Answer``. The names:

* 'clarabel': this thread's kept Clarabel instance of the program, only its objective replaced;
* 'clarabel refined': a fresh Clarabel instance with iterative refinement;
* 'simplex': HiGHS's simplex method warm-started along the batch (`warm_simplex.simplex`);
* 'simplex cold': HiGHS's dual simplex method from scratch (`highs.simplex_cold`);
* 'interior': HiGHS's interior-point method without crossover (`highs.interior_point`).

A *sequence* backend keeps state along a sequence of programs that share their constraint matrix
and differ in b and the factor bounds (the OIT-CZ windows, `parametric.ParametricSupport`), min q_jᵀξ
over {Aξ = b, |ξ_i| ≤ h_i} for fixed objectives q_j: ``SEQUENCE_BACKENDS[name](A, Q, free)`` is made
once per sequence and its ``solve(j, b, h) -> Answer`` answers objective j of the current program,
in the same vocabulary, for the caller's certificate (or check) to judge; a backend made with
``block=(rows, cols)`` also takes new values of those entries of A (``set_block``) between programs:

* 'simplex along time': one HiGHS model per objective, re-solved by the dual simplex method from
  its last optimal basis (`highs.DirectionModels`).

`Answer.status` is one of `STATUSES`: 'solved' (Clarabel's own 'Solved': taken as it is),
'candidate' (a point and multipliers that only the caller's independent check may accept: Clarabel's
'AlmostSolved' and every HiGHS optimum), 'infeasible', 'unbounded', or 'unsettled' (no answer;
``detail`` keeps the backend's own status name for a `SolverError`). Which backends are asked, in
which order, is `policy.policy`'s decision, not the backends'.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import clarabel
import numpy as np
import scipy.sparse as sp

from . import clarabel_lp
from .clarabel_lp import _index_type, _zero_cost
from .highs import DirectionModels, interior_point, simplex_cold
from .instances import cached_instance
from .warm_simplex import checked_simplex

__all__ = ["Answer", "STATUSES", "BACKENDS", "SEQUENCE_BACKENDS", "Backend", "box_rows", "classify"]

STATUSES = ("solved", "candidate", "infeasible", "unbounded", "unsettled")

_INFEASIBLE = ("PrimalInfeasible", "AlmostPrimalInfeasible")
_UNBOUNDED = ("DualInfeasible", "AlmostDualInfeasible")


@dataclass(frozen=True)
class Answer:
    """A backend's answer to min qᵀη over a presolved program.

    Attributes
    ----------
    status : str
        One of `STATUSES`.
    eta : ndarray, shape (p,)
        The point (presolved factors); meaningful for 'solved' and 'candidate'.
    z : ndarray, shape (m,)
        Multipliers of the rows Âη = b̂ in Clarabel's convention (q + Âᵀz = 0 on free factors).
    detail : str
        The backend's own status name.
    checked : float or None
        The backend's own `Presolved.checked_gap` of this answer, when it computed one (inf: the
        check failed); None when the caller is to check it.
    """

    status: str
    eta: np.ndarray
    z: np.ndarray
    detail: str
    checked: float | None = None


Backend = Callable[..., Answer]


def classify(name: str, eta: np.ndarray, z: np.ndarray, m: int,
             checked: float | None = None) -> Answer:
    """The `Answer` of a status name in Clarabel's vocabulary (HiGHS's are mapped onto it);
    ``checked``, the backend's own gap check, is kept for a candidate only."""
    if name == "Solved":
        status = "solved"
    elif name == "AlmostSolved":
        status = "candidate"
    elif name in _INFEASIBLE:
        status = "infeasible"
    elif name in _UNBOUNDED:
        status = "unbounded"
    else:
        status = "unsettled"
    return Answer(status, np.asarray(eta), np.asarray(z)[:m], name,
                  checked if status == "candidate" else None)


def box_rows(pre) -> tuple[sp.csc_matrix, np.ndarray, list]:
    """Rows [Â; I_B; −I_B], right-hand sides [b̂; 1; 1] and Clarabel cones of the presolved program.

    Assembled from index arrays, column by column (Â[:, j], then +1 in row m + i and −1 in row
    m + nb + i when j is the i-th bounded factor): scipy's vstack costs more than a small solve."""
    m, p = pre.A.shape
    bcols = np.flatnonzero(pre.bounded)
    nb = bcols.size
    A = pre.A
    a_count = np.diff(A.indptr)
    col_nnz = a_count + 2 * pre.bounded
    indptr = np.zeros(p + 1, dtype=np.int64)
    np.cumsum(col_nnz, out=indptr[1:])
    a_dest = np.arange(A.nnz) + np.repeat(indptr[:-1] - A.indptr[:-1], a_count)
    upper = indptr[1:][bcols] - 2
    rows = np.empty(int(indptr[-1]), dtype=np.int64)
    data = np.empty(int(indptr[-1]))
    rows[a_dest], data[a_dest] = A.indices, A.data
    rows[upper], data[upper] = m + np.arange(nb), 1.0
    rows[upper + 1], data[upper + 1] = m + nb + np.arange(nb), -1.0
    itype = _index_type(max(int(indptr[-1]), m + 2 * nb))
    M = sp.csc_matrix((data, rows.astype(itype), indptr.astype(itype)), shape=(m + 2 * nb, p))
    rhs = np.concatenate([pre.b, np.ones(2 * nb)])
    cones = ([clarabel.ZeroConeT(m)] if m else []) + ([clarabel.NonnegativeConeT(2 * nb)]
                                                      if nb else [])
    return M, rhs, cones


def _clarabel(solver) -> tuple[str, np.ndarray, np.ndarray]:
    sol = solver.solve()
    return str(sol.status).split(".")[-1], np.asarray(sol.x), np.asarray(sol.z)


def clarabel_kept(pre, q: np.ndarray, batch: object = None) -> Answer:
    """'clarabel': this thread's kept instance of the program, its objective replaced."""
    def build():
        M, rhs, cones = box_rows(pre)
        p = pre.A.shape[1]
        return clarabel.DefaultSolver(_zero_cost(p), np.zeros(p), M, rhs, cones,
                                      clarabel_lp.settings())

    solver = cached_instance(pre, "clarabel", build)
    solver.update(q=q)
    return classify(*_clarabel(solver), pre.A.shape[0])


def clarabel_refined(pre, q: np.ndarray, batch: object = None) -> Answer:
    """'clarabel refined': a fresh instance (no state of the kept one) with iterative refinement."""
    M, rhs, cones = box_rows(pre)
    solver = clarabel.DefaultSolver(_zero_cost(q.size), q, M, rhs, cones,
                                    clarabel_lp.settings(refine=True))
    return classify(*_clarabel(solver), pre.A.shape[0])


def highs_simplex(pre, q: np.ndarray, batch: object = None) -> Answer:
    """'simplex': HiGHS's simplex method warm-started along ``batch`` (its answer already checked)."""
    name, eta, z, gap = checked_simplex(pre, q, batch)
    return classify(name, eta, z, pre.A.shape[0], gap)


def highs_simplex_cold(pre, q: np.ndarray, batch: object = None) -> Answer:
    """'simplex cold': HiGHS's dual simplex method from scratch."""
    return classify(*simplex_cold(pre, q), pre.A.shape[0])


def highs_interior(pre, q: np.ndarray, batch: object = None) -> Answer:
    """'interior': HiGHS's interior-point method without crossover, from scratch."""
    return classify(*interior_point(pre, q), pre.A.shape[0])


#: The backends by name (see the module docstring).
BACKENDS: dict[str, Backend] = {
    "clarabel": clarabel_kept,
    "clarabel refined": clarabel_refined,
    "simplex": highs_simplex,
    "simplex cold": highs_simplex_cold,
    "interior": highs_interior,
}


class SimplexAlongTime:
    """'simplex along time': `highs.DirectionModels`, its answers in `Answer`'s vocabulary.

    ``block``: (rows, cols) of entries of A that change along the sequence too (`set_block`); A must
    hold them as stored entries (nonzero placeholders), so every model has them to change."""

    def __init__(self, A: sp.csc_matrix, Q: np.ndarray, free: np.ndarray,
                 block: tuple[np.ndarray, np.ndarray] | None = None):
        self.models = DirectionModels(A if block is None else A.copy(), Q, free)
        self.m = A.shape[0]
        self.block = block
        self._values: np.ndarray | None = None      # the block's current values
        self._synced: dict[int, np.ndarray] = {}    # the values each direction's model holds

    def set_block(self, values: np.ndarray) -> None:
        """The block's entries for the next programs (in the order of ``block``)."""
        self._values = np.asarray(values, dtype=float)

    def solve(self, j: int, b: np.ndarray, h: np.ndarray) -> Answer:
        """Objective j over {Aξ = b, |ξ| ≤ h} from its model's last basis: 'candidate' at an optimum
        (for the caller's certificate), else the ladder's verdict."""
        if self._values is not None:
            self._sync(j)
        return classify(*self.models.solve(j, b, h), self.m)

    def _sync(self, j: int) -> None:
        """Direction j's model to the block's current values (changed entries only)."""
        rows, cols = self.block
        if self.models.models is None:  # the models are built from A: give it the values first
            A = self.models.A
            for r, c, v in zip(rows, cols, self._values):
                A[r, c] = v
            self._synced = {i: self._values for i in range(len(self.models.Q))}
            return
        held = self._synced.get(j)
        model = self.models.models[j]
        changed = np.arange(rows.size) if held is None else np.flatnonzero(held != self._values)
        for e in changed:
            model.changeCoeff(int(rows[e]), int(cols[e]), float(self._values[e]))
        self._synced[j] = self._values


#: The sequence backends by name (see the module docstring).
SEQUENCE_BACKENDS: dict[str, Callable] = {
    "simplex along time": SimplexAlongTime,
}
