"""Presolve of the factor set {ξ : Aξ = b, |ξ| ≤ h} before it reaches Clarabel.

One set can be written many ways: a constraint row multiplied by 1e-12, a factor ξ_j replaced by
s·ξ_j (its column of G and A divided by s, its bound multiplied by s), coordinates rescaled. An
interior-point method is not invariant under these changes (Clarabel's own equilibration is clipped
to [1e-4, 1e4]), so a badly scaled representation can lose a constraint row or stall. The presolve
maps every representation of one set to (nearly) the same well-scaled program:

* factors with ``h_j = 0`` are fixed at zero and dropped;
* finite bounds are scaled out, ``ξ_j = h_j η_j`` with ``|η_j| ≤ 1`` (this makes the program
  invariant under rescaling a bounded factor);
* rows are scaled to unit ∞-norm over their bounded entries, and the columns of free factors to
  unit ∞-norm over those rows (alternating sweeps with the rows that hold free factors only, for
  free factors seen by no other row), so a row or a free factor
  scaled by 1e±12 is the same row or factor, and free factors take values in the units of the
  bounded ones;
* zero rows are dropped (an inconsistent one, 0 = b_i ≠ 0, means the set is empty), and, when
  asked (small or dense programs, or after a failed solve), linearly dependent rows too, through the
  scale-invariant rank decision of `setsmooth.linalg.independent_rows`.

The presolved program is

    maximize ĝᵀη   subject to   Âη = b̂,  |η_j| ≤ 1 (j bounded),   with  Â = R A S,  b̂ = R b,
    ĝ = S g,  ξ = S η,

where R (rows) and S (columns) are positive diagonal scalings. A multiplier ẑ of the presolved
program for the objective ĝ/σ maps back to λ = σ R ẑ for the original one (zero on dropped rows).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg

from .. import tolerances as tol
from ..linalg import independent_rows

__all__ = ["Presolved", "presolve", "simplex", "simplex_cold", "simplex_inequalities",
           "simplex_timed_out", "simplex_box_equalities", "project_free", "RUIZ_SWEEPS",
           "INDEPENDENT_RCOND"]

#: Equilibration sweeps with free factors (each scales the free columns, then the rows holding only
#: free factors, to unit ∞-norm); without free factors one row normalization is exact.
RUIZ_SWEEPS = 3


#: Rows whose smallest singular value is at least this fraction of the largest are independent
#: beyond doubt (far above the rank tolerance of `independent_rows`), and the QR is skipped.
INDEPENDENT_RCOND = 1e-6


#: Largest kept-rows × columns count for which dependent rows are looked for (the dense Gram matrix
#: or QR of the rows: 3e7 entries, 240 MB). Beyond it the fallback goes to the simplex method, whose
#: own presolve handles dependent rows; the recursion smoother's CZs reach it at T ≈ 40.
DEPENDENT_DENSE_MAX = 30_000_000

#: HiGHS's feasibility tolerances for the simplex fallback, on the presolved program (unit rows,
#: |η| ≤ 1), tried in turn (None: HiGHS's defaults, 1e-7). The defaults alone left duality gaps of
#: ~1e-7 of the objective's scale, which a certified bound built on the multipliers keeps: 1.1e-6 of
#: w + σ on the recursion smoother's hulls of an unstable system at noise 1e-6 (reliability case
#: 001). But on the recursion smoother's degenerate, ill-conditioned sets (σ_min(Â) ≈ 6e-8) the
#: tight tolerance alone cycles: 100,000 – 530,000 iterations, 3 – 22 s, often ending in
#: 'numerical difficulties', where the defaults need ~250 iterations. Each rung is therefore
#: capped (`_rung_iterations`); what it does not settle the next, looser one solves. Every answer
#: is checked independently by the caller and certified bounds hold for any multipliers, so a
#: looser rung costs tightness, never soundness.
SIMPLEX_TOLERANCES = (1e-10, 1e-9, None)

#: The ladder of the programs whose optimal value decides something (the elastic phase-one program:
#: empty iff its optimum exceeds ``EMPTINESS_TOL`` = 1e-8; the recession program: unbounded iff its
#: gain exceeds ``REDUCED_COST_TOL``). A feasible point of them is not a proof, so they stop at
#: 1e-9, an order below those thresholds, and never use HiGHS's defaults.
DECISION_TOLERANCES = (1e-10, 1e-9)


def _rung_iterations(size: int, last: bool) -> int:
    """Iteration cap of a rung for a program of ``size`` = rows + columns: size + 200 for the tight
    rungs (their successful solves need about size/2: reliability case 000 at T = 20, 196 fallback
    programs), 20·size + 1000 for the last (a guard against cycling, never reached there)."""
    return 20 * size + 1000 if last else size + 200


#: A rung's time limit is ``RUNG_SECONDS_FLOOR`` + ``RUNG_SECONDS_PER_ITERATION`` × the tight rungs'
#: iteration cap (`rung_seconds`; the last rung's cap, 20× larger, is a guard against cycling
#: that legitimate solves never reach). It guards against HiGHS's dual simplex method looping in
#: its primal clean-up without counting iterations, where no cap stops it: on the recursion
#: smoother's set k = 17 of reliability case 184 at noise 1e3 (1,864 rows, 2,454 factors, 103 k
#: nonzeros) the cold dual rung reached its 2,025th iteration in 0.2 s and then ran for hours at
#: any cap. The densest programs seen take 1.5 ms per iteration (case 039, k = 20: 199 k
#: nonzeros), so a rung that settles stays far below the limit; one that reaches it has failed.
RUNG_SECONDS_FLOOR = 10.0
RUNG_SECONDS_PER_ITERATION = 5e-3


def rung_seconds(size: int) -> float:
    """The time limit of every simplex rung on a program of ``size`` = rows + columns."""
    return RUNG_SECONDS_FLOOR + RUNG_SECONDS_PER_ITERATION * _rung_iterations(size, False)


def _rung_caps(size: int, rungs: int) -> list[int]:
    """The iteration caps of a ladder of ``rungs`` rungs (`_rung_iterations`)."""
    return [_rung_iterations(size, rung == rungs - 1) for rung in range(rungs)]


def _refused(res) -> bool:
    """SciPy's status 2 also carries HiGHS's refusal of the data, told apart by its message."""
    return res.status == 2 and "infeasible" not in res.message.lower()


def _highs_ladder(q: np.ndarray, size: int, tolerances: tuple = SIMPLEX_TOLERANCES, **program):
    """``scipy.optimize.linprog(q, method='highs', **program)`` through ``tolerances``: the first
    rung's result that is not an iteration or time limit (status 1; `rung_seconds`) or a
    numerical failure (status 4, or status 2 without 'infeasible' in the message: HiGHS refusing
    the data). An infeasible or unbounded verdict ends the ladder: it is the caller's to judge."""
    from scipy.optimize import linprog

    res = None
    for tolerance, cap in zip(tolerances, _rung_caps(size, len(tolerances))):
        options = {"maxiter": cap, "time_limit": rung_seconds(size)}
        if tolerance is not None:
            options.update(primal_feasibility_tolerance=tolerance,
                           dual_feasibility_tolerance=tolerance)
        res = linprog(q, method="highs", options=options, **program)
        if res.status not in (1, 4) and not _refused(res):
            return res
    return res


@dataclass(frozen=True)
class Presolved:
    """The presolved factor set (see the module docstring).

    Attributes
    ----------
    A : csc_matrix, shape (m, p)
        Â = R A[rows][:, cols] S.
    b : ndarray, shape (m,)
        b̂ = R b[rows] − Â η⁰ (η⁰ = ``shift``, zero when None).
    rows : ndarray of int
        The original rows kept.
    cols : ndarray of int
        The original factors kept (those with h > 0).
    row_scale : ndarray, shape (m,)
        The diagonal of R.
    col_scale : ndarray, shape (p,)
        The diagonal of S (h_j for bounded factors).
    bounded : ndarray of bool, shape (p,)
        Which kept factors have |η_j| ≤ 1 (the others are free).
    empty : bool
        True when a dropped row is inconsistent: the factor set is empty.
    dependent_checked : bool
        Whether linearly dependent rows were looked for.
    shift : ndarray, shape (p,) or None
        Deviation coordinates of the free factors: the program's η is the deviation from a nominal
        point η⁰ (zero on bounded factors; `nominal_free_point`), so b̂ above is R b[rows] − Â η⁰ and
        a factor of the set is S(η + η⁰). None: no shift.
    b_scale : float
        1 + ‖R b[rows]‖∞, the magnitude of the unshifted right-hand sides: the scale of the data's
        own rounding, against which emptiness and accuracy are judged.
    """

    A: sp.csc_matrix
    b: np.ndarray
    rows: np.ndarray
    cols: np.ndarray
    row_scale: np.ndarray
    col_scale: np.ndarray
    bounded: np.ndarray
    empty: bool
    dependent_checked: bool
    shift: np.ndarray | None = None
    b_scale: float | None = None

    @property
    def data_scale(self) -> float:
        """``b_scale``, or 1 + ‖b̂‖∞ for a program built without one."""
        return self.b_scale if self.b_scale is not None else 1.0 + np.abs(self.b).max(initial=0.0)

    @cached_property
    def has_free(self) -> bool:
        """Whether some kept factor is free (h = ∞)."""
        return not bool(self.bounded.all())

    @cached_property
    def At(self) -> sp.csr_matrix:
        """Âᵀ, kept: a transpose per solve costs more than its product on small programs."""
        return sp.csr_matrix(self.A.T)

    @cached_property
    def free_columns(self) -> sp.csc_matrix:
        """Â_F, the free factors' columns, kept (`project_free` needs them per direction)."""
        return sp.csc_matrix(self.A[:, ~self.bounded])

    @cached_property
    def _free_rows(self) -> tuple[np.ndarray, sp.csr_matrix]:
        """The free factors' indices and their rows of Âᵀ."""
        free = np.flatnonzero(~self.bounded)
        return free, sp.csr_matrix(self.At[free])

    def free_residual(self, q: np.ndarray, z: np.ndarray) -> float:
        """max_j free |q_j + (Âᵀz)_j|: how far z is from cancelling the objective q on the free
        factors (0 without free factors)."""
        if not self.has_free:
            return 0.0
        free, AFt = self._free_rows
        return float(np.abs(q[free] + AFt @ z).max(initial=0.0))

    def checked_gap(self, q: np.ndarray, eta: np.ndarray, z: np.ndarray) -> float | None:
        """Independent check of a reduced-accuracy answer (η, ẑ) to min qᵀη, in the presolved
        units: primal residual, bound overshoot and gap to the weak-duality bound
        b̂ᵀλ + Σ_B |ĝ − Âᵀλ|_j must be within ``SOLVER_CHECK_TOL`` of the scale (rows and objective
        have unit ∞-norm, bounds are 1). Returns the relative gap, or None when the check fails."""
        lam = z  # Clarabel's stationarity q + Âᵀz = 0 on the free factors: λ̂ = z
        reduced = -q - self.At @ lam
        if np.abs(reduced[~self.bounded]).max(initial=0.0) > tol.REDUCED_COST_TOL:
            return None
        primal = float(-q @ eta)
        dual = float(lam @ self.b + np.abs(reduced[self.bounded]).sum())
        scale = self.data_scale + np.abs(q).sum()
        residual = np.abs(self.A @ eta - self.b).max(initial=0.0)
        overshoot = np.max(np.abs(eta[self.bounded]) - 1.0, initial=0.0)
        worst = max(abs(dual - primal), residual, overshoot) / scale
        return worst if worst <= tol.SOLVER_CHECK_TOL else None

    def objective(self, g: np.ndarray) -> np.ndarray:
        """ĝ = S g[cols] for objectives ``g`` of the original factors (rows of a (k, ng) array)."""
        return g[:, self.cols] * self.col_scale

    def factors(self, eta: np.ndarray, ng: int) -> np.ndarray:
        """ξ = S (η + η⁰) on the kept factors, 0 on the dropped ones (rows of a (k, p) array)."""
        xi = np.zeros((eta.shape[0], ng))
        xi[:, self.cols] = (eta if self.shift is None else eta + self.shift) * self.col_scale
        return xi

    def multipliers(self, z: np.ndarray, sigma: np.ndarray, nc: int) -> np.ndarray:
        """λ = σ R ẑ on the kept rows, 0 on the dropped ones (``z`` of shape (k, m))."""
        lam = np.zeros((z.shape[0], nc))
        lam[:, self.rows] = z * self.row_scale * sigma[:, None]
        return lam


#: The free factors' nominal point (`nominal_free_point`) is a dense least-squares solve up to this
#: many entries of Â_F, and LSQR (a fixed iteration limit: deterministic) beyond.
NOMINAL_DENSE_MAX = 250_000


def presolve(A: sp.csc_matrix, b: np.ndarray, h: np.ndarray, *, dependent: bool) -> Presolved:
    """Presolve {ξ : Aξ = b, |ξ| ≤ h} (module docstring).

    Parameters
    ----------
    A : csc_matrix, shape (nc, ng)
    b : ndarray, shape (nc,)
    h : ndarray, shape (ng,)
        Bounds in [0, ∞].
    dependent : bool
        Also drop linearly dependent rows (dense QR: for small programs or as a fallback).

    Returns
    -------
    Presolved
    """
    nc, ng = A.shape
    cols = np.flatnonzero(h > 0)
    hk = h[cols]
    bounded = np.isfinite(hk)
    col_scale = np.where(bounded, hk, 1.0)
    # Scaled in place on the CSC arrays: scipy's sparse products cost more than Clarabel's whole
    # solve of a small CZ.
    M = sp.csc_matrix(A[:, cols]) if cols.size < ng else A.copy()
    M.sum_duplicates()
    col_of = np.repeat(np.arange(M.shape[1]), np.diff(M.indptr))
    M.data = M.data * col_scale[col_of]
    row_scale = np.ones(nc)
    free = ~bounded
    # Rows are measured by their bounded entries, which are in the units of the factors' bounds
    # (|η| ≤ 1): a row reads in those units whatever the scale of the free factors it also holds.
    # Free columns are then scaled to unit ∞-norm, which puts the free factors' values in the same
    # units (a trajectory set of noise scale 1e-6 has states of size 1e-6: unscaled they would sit
    # below the solver's absolute tolerances). Rows without bounded entries are measured by all of
    # them, which the free-column scaling changes: hence a few alternating sweeps.
    has_free = bool(free.any())
    bounded_norm = _row_abs_max(M, bounded[col_of]) if has_free else _row_abs_max(M)
    r = _inverse(bounded_norm)
    M.data *= r[M.indices]
    row_scale *= r
    only_free = bounded_norm == 0
    if has_free:
        # A free factor seen by a row with bounded entries takes its units from those rows: scaled
        # to unit ∞-norm over them, its values are of the bounded factors' size (a state of the
        # trajectory set at noise scale 1e3 becomes O(1), not 1e3: measured by all rows, the
        # free-only rows (a dynamics row without noise) would pin it at its raw scale and leave
        # the interior-point method a dual residual of ~1e-7 on it, and a wrong support value).
        anchored_entry = ~only_free[M.indices]
        anchor = np.zeros(M.shape[1])
        np.maximum.at(anchor, col_of[anchored_entry], np.abs(M.data[anchored_entry]))
        anchored = free & (anchor > 0)
        s = np.where(anchored, _inverse(anchor), 1.0)
        M.data *= s[col_of]
        col_scale = col_scale * s
        floating = free & ~anchored  # free factors seen by free-only rows only
        for _ in range(RUIZ_SWEEPS):
            if not floating.any():
                break
            s = _neighbour_units(M, col_of, floating)
            floating &= ~(s > 0)
            s = np.where(s > 0, s, 1.0)
            M.data *= s[col_of]
            col_scale = col_scale * s
        for sweep in range(RUIZ_SWEEPS + 1 if only_free.any() else 0):
            r = np.where(only_free, _inverse(_row_abs_max(M)), 1.0)
            M.data *= r[M.indices]
            row_scale *= r
            if sweep == RUIZ_SWEEPS or not floating.any():
                break  # rows last: every kept row has unit ∞-norm
            s = np.where(floating, _inverse(_col_abs_max(M)), 1.0)
            M.data *= s[col_of]
            col_scale = col_scale * s
    nonzero = _row_abs_max(M) > 0
    bs = b * row_scale
    # A zero row reads 0 = b_i; b_i left over by cancellation is rounding, judged against the other
    # rows' normalized right-hand sides, as `independent_rows` judges one.
    scale_b = 1.0 + np.abs(bs[nonzero]).max(initial=0.0)
    empty = bool(np.any(np.abs(b[~nonzero]) > np.sqrt(tol.RANK_TOL) * scale_b))
    rows = np.flatnonzero(nonzero)
    if dependent and rows.size * M.shape[1] > DEPENDENT_DENSE_MAX:
        dependent = False  # not looked for: memory stays bounded (see DEPENDENT_DENSE_MAX)
    if dependent and rows.size > 1 and not empty and not _well_conditioned(M, rows):
        basis = independent_rows(M[rows] if rows.size < nc else M, bs[rows])
        empty = not basis.consistent
        rows = rows[basis.keep]
    Mr = sp.csc_matrix(M[rows]) if rows.size < nc else M
    b_kept = bs[rows]
    b_scale = 1.0 + float(np.abs(b_kept).max(initial=0.0))
    shift = nominal_free_point(Mr, b_kept, bounded) if has_free and not empty else None
    if shift is not None:
        b_kept = b_kept - Mr @ shift
    return Presolved(Mr, b_kept, rows, cols, row_scale[rows], col_scale, bounded, empty, dependent,
                     shift, b_scale)


def nominal_free_point(M: sp.csc_matrix, b: np.ndarray, bounded: np.ndarray) -> np.ndarray | None:
    """η⁰: the free factors' least-squares solution of Â_F η_F = b̂ (bounded factors at 0), the
    point around which the presolved program is posed; None when it does not shrink b̂.

    A free factor that a thin measurement pins (noise 1e-6 beside states of size 5) makes the
    equilibrated right-hand sides ~5e7 while the bounded factors move them by O(1): an
    interior-point method then resolves the rows only to ~1e-8 of 5e7, and its elastic phase-one
    program found t* = 2.4 on a set that holds the true state (a filter posterior called empty at
    k = 2 and non-empty at k = 3). Around η⁰ the right-hand sides are what the bounded factors
    must produce, O(1) on a non-empty set, and the same program gives t* = 9e-11. The shift is a
    change of coordinates: certificates are computed on the original data (`certify`).
    """
    free = np.flatnonzero(~bounded)
    if free.size == 0 or M.shape[0] == 0:
        return None
    AF = M[:, free]
    if AF.shape[0] * AF.shape[1] <= NOMINAL_DENSE_MAX:
        x = scipy.linalg.lstsq(AF.toarray(), b, lapack_driver="gelsy")[0]  # 2x gelsd's speed
    else:
        x = scipy.sparse.linalg.lsqr(AF, b, atol=1e-14, btol=1e-14, iter_lim=4 * AF.shape[1])[0]
    if not np.all(np.isfinite(x)):
        return None
    shift = np.zeros(M.shape[1])
    shift[free] = x
    if np.abs(b - M @ shift).max(initial=0.0) >= np.abs(b).max(initial=0.0):
        return None
    return shift


def _neighbour_units(M: sp.csc_matrix, col_of: np.ndarray, floating: np.ndarray) -> np.ndarray:
    """Column scales that put each floating free factor in the units of its scaled neighbours.

    A floating factor ξ_j (a state seen only by dynamics rows without noise, such as a state
    component that neither B·W nor the measurement reaches) is fixed by a row
    a_j ξ_j + Σ_i a_i ξ_i = b with ξ_i already in unit scale, so |ξ_j| ≈ max_i |a_i| / |a_j|: the
    scale s_j = min over its rows of that ratio makes the entry a_j s_j no larger than its row's
    other entries. Without it the alternating equilibration settles with the floating column at its
    raw scale (the row's largest entry, so unit row and column norms): at noise scale 1e-6 such a
    state is 1e-7 in the solver's units, below Clarabel's and HiGHS's absolute tolerances
    (reliability case 015: filtered hulls 3.8e-3 of the width off, certified ones 9e-3 loose).
    Returns 0 for a column none of whose rows has a non-floating entry (left to the sweeps).
    """
    values = np.abs(M.data)
    rows = M.indices
    neighbour = np.zeros(M.shape[0])
    settled = ~floating[col_of]
    np.maximum.at(neighbour, rows[settled], values[settled])
    ratio = np.full(M.shape[1], np.inf)
    mine = floating[col_of] & (neighbour[rows] > 0) & (values > 0)
    np.minimum.at(ratio, col_of[mine], neighbour[rows[mine]] / values[mine])
    return np.where(np.isfinite(ratio), ratio, 0.0)


def _well_conditioned(M: sp.csc_matrix, rows: np.ndarray) -> bool:
    """Whether the kept rows are certainly independent: σ_min ≥ `INDEPENDENT_RCOND`·σ_max of the
    (row-normalized) rows, a cheap test that spares the rank-revealing QR on the common case.

    Decided by a Cholesky factorization of the Gram matrix shifted down, G − τI with G = M_r M_rᵀ and
    τ = (rcond² + 4 m ε)·‖G‖_∞: it exists only if λ_min(G) > τ up to the factorization's rounding
    (the 4 m ε term), and ‖G‖_∞ ≥ λ_max(G), so success means σ_min² > rcond²·σ_max². That is one
    m³/3 factorization of an m × m matrix instead of an SVD of the m × p rows: on the recursion
    smoother's CZs (m = 3125, p = 5667) 1.3 s instead of 37 s of CPU, the whole of a certified hull.
    """
    m = rows.size
    if m > M.shape[1]:
        return False
    Mr = M[rows] if m < M.shape[0] else M
    G = (Mr @ Mr.T).toarray()
    bound = float(np.abs(G).sum(axis=1).max(initial=0.0))
    if not bound > 0 or not np.isfinite(bound):
        return False
    G[np.diag_indices(m)] -= (INDEPENDENT_RCOND ** 2 + 4 * m * np.finfo(float).eps) * bound
    try:
        scipy.linalg.cholesky(G, lower=True, overwrite_a=True, check_finite=False)
    except np.linalg.LinAlgError:
        return False
    return True


def _inverse(norms: np.ndarray) -> np.ndarray:
    """1/norm, and 1 for zero norms (a zero row or column is left alone)."""
    out = np.ones_like(norms)
    pos = norms > 0
    out[pos] = 1.0 / norms[pos]
    return out


def _row_abs_max(M: sp.csc_matrix, entries: np.ndarray | None = None) -> np.ndarray:
    """∞-norm of every row (over the stored entries selected by the mask ``entries``)."""
    out = np.zeros(M.shape[0])
    if entries is None:
        np.maximum.at(out, M.indices, np.abs(M.data))
    else:
        np.maximum.at(out, M.indices[entries], np.abs(M.data[entries]))
    return out


def _col_abs_max(M: sp.csc_matrix) -> np.ndarray:
    out = np.zeros(M.shape[1])
    counts = np.diff(M.indptr)
    nonempty = counts > 0
    if M.nnz:
        out[nonempty] = np.maximum.reduceat(np.abs(M.data), M.indptr[:-1][nonempty])
    return out


#: The key of a program's warm model (`warm_simplex.WarmSimplex`) in the per-thread instance cache.
WARM_MODEL_KEY = "warm simplex"


def simplex(pre: Presolved, q: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀη over the presolved program by HiGHS's simplex method: (status name, η, λ̂ in
    Clarabel's sign convention q + Âᵀλ̂ = 0 on the free factors).

    One HiGHS model per presolved program and thread, warm-started from the last objective's basis
    (`warm_simplex.WarmSimplex`), through the ladder ``SIMPLEX_TOLERANCES``: the primal method
    from that basis, and the dual method from the batch's start when the primal method's answer
    fails `Presolved.checked_gap` at ``ACCURATE_GAP_TOL`` (on ill-conditioned programs the primal
    method's duals can be loose: gaps of 2.7e-7 to 8e-7, or failing the check, on 4 of 8 objectives
    of the test suite's cycling program, where the dual method's are below 3e-9). `simplex_cold`
    is the same ladder by SciPy's ``linprog`` from scratch, the reference it is tested against."""
    from .instances import cached_instance
    from .warm_simplex import WarmSimplex

    model = cached_instance(pre, WARM_MODEL_KEY, lambda: WarmSimplex(pre.A, pre.b, pre.bounded))
    caps = _rung_caps(sum(pre.A.shape), len(SIMPLEX_TOLERANCES))
    answer = model.minimize(q, SIMPLEX_TOLERANCES, caps)
    gap = _gap_or_inf(pre, q, answer)
    if gap > tol.ACCURATE_GAP_TOL and model.answered_by_primal:
        again = model.minimize(q, SIMPLEX_TOLERANCES, caps, dual=True)
        if _gap_or_inf(pre, q, again) < gap or np.isinf(gap):
            answer = again
    return answer


def simplex_timed_out(pre: Presolved) -> bool:
    """Whether `simplex` ran out of time (`rung_seconds`) on ``pre`` in this thread's current batch
    of queries (`warm_simplex.new_batch`); False when it has not been asked in this thread."""
    from .instances import kept_instance

    model = kept_instance(pre, WARM_MODEL_KEY)
    return model is not None and model.timed_out_in_batch()


def _gap_or_inf(pre: Presolved, q: np.ndarray, answer: tuple) -> float:
    """`Presolved.checked_gap` of a simplex answer; inf when it is not an optimum or fails."""
    name, eta, z = answer
    gap = pre.checked_gap(q, eta, z) if name == "AlmostSolved" else None
    return np.inf if gap is None else gap


def simplex_cold(pre: Presolved, q: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """`simplex` by SciPy's ``linprog``, every objective from scratch (the reference)."""
    m, p = pre.A.shape
    bounds = np.where(pre.bounded[:, None], [[-1.0, 1.0]], [[-np.inf, np.inf]])
    res = _highs_ladder(q, m + p, A_eq=pre.A if m else None, b_eq=pre.b if m else None,
                        bounds=bounds)
    names = {0: "AlmostSolved", 1: "MaxIterations", 2: "PrimalInfeasible", 3: "DualInfeasible"}
    name = "NumericalError" if _refused(res) else names.get(res.status, "NumericalError")
    if res.status != 0:
        return name, np.full(p, np.nan), np.full(m, np.nan)
    # HiGHS's marginals are ∂(min)/∂b_eq, i.e. q = Âᵀy + (bound duals): λ̂ = −y.
    return name, np.asarray(res.x), -np.asarray(res.eqlin.marginals)


def simplex_inequalities(q: np.ndarray, rows: sp.csc_matrix, r: np.ndarray
                         ) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀx subject to rows·x ≤ r (x free) by HiGHS (SciPy), in Clarabel's convention for the
    multipliers (z ≥ 0, q + rowsᵀz = 0): ('optimal', x, z), or (HiGHS's status, NaNs, NaNs). The
    fallback of the always-feasible programs (phase one, the relaxed support program)."""
    n, k = rows.shape[1], rows.shape[0]
    res = _highs_ladder(q, n + k, DECISION_TOLERANCES, A_ub=rows, b_ub=r,
                        bounds=[(None, None)] * n)
    if res.status != 0:
        return f"status {res.status}", np.full(n, np.nan), np.full(k, np.nan)
    # HiGHS's marginals are ∂(min)/∂b_ub ≤ 0: q = −rowsᵀy, so z = −y.
    return "optimal", np.asarray(res.x), -np.asarray(res.ineqlin.marginals)


def simplex_box_equalities(q: np.ndarray, A: sp.csc_matrix) -> tuple[str, np.ndarray]:
    """min qᵀη subject to Aη = 0, |η| ≤ 1 by HiGHS (SciPy): ('optimal', η) or (its status, NaNs).
    The fallback of the recession program (feasible at η = 0, bounded)."""
    m, n = A.shape
    res = _highs_ladder(q, m + n, DECISION_TOLERANCES, A_eq=A if m else None,
                        b_eq=np.zeros(m) if m else None, bounds=(-1.0, 1.0))
    if res.status != 0:
        return f"status {res.status}", np.full(n, np.nan)
    return "optimal", np.asarray(res.x)


def project_free(pre: Presolved, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q + Âᵀλ₀ with its free entries set to zero, λ₀), λ₀ the least-squares solution of
    Â_Fᵀλ₀ = −q_F: the same objective on {Âη = b̂} up to the constant and the residual on the free
    factors, which the recession program found to be within tolerance.

    λ₀ is the least-norm solution through the normal equations of Â_F (one sparse LU per presolved
    program and thread, refined), or by lsqr when Â_F is rank deficient: `certify.correct_multipliers`
    from λ = 0. (lsqr on every direction cost 25 ms each on a trajectory set of n = 5, T = 27,
    reliability case 150: 95 % of its smoother's time.)
    """
    from .certify import correct_multipliers, normal_solver
    from .instances import cached_instance

    free = ~pre.bounded
    AF = pre.free_columns
    solve_normal = cached_instance(pre, "normal equations of the free factors",
                                   lambda: normal_solver(AF))
    lam0 = correct_multipliers(AF, -q[free][None, :], np.zeros((1, pre.A.shape[0])),
                               solve_normal, pre._free_rows[1])[0]
    shifted = q + pre.At @ lam0
    shifted[free] = 0.0
    return shifted, lam0

