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
  free factors seen by no other row), so a row or a free factor scaled by 1e±12 is the same row
  or factor, and free factors take values in the units of the bounded ones;
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

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dpotrf

from .. import tolerances as tol
from ..linalg import independent_rows
from .free_factors import nominal_free_point
from .presolved import Presolved
from .small_products import gram

__all__ = ["Presolved", "presolve", "RUIZ_SWEEPS", "INDEPENDENT_RCOND"]

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
    # Scaled in place on the CSC arrays: scipy's sparse products cost more than Clarabel's whole
    # solve of a small CZ.
    M = sp.csc_matrix(A[:, cols]) if cols.size < ng else A.copy()
    M.sum_duplicates()
    col_of = np.repeat(np.arange(M.shape[1]), np.diff(M.indptr))
    col_scale = np.where(bounded, hk, 1.0)
    M.data = M.data * col_scale[col_of]
    row_scale, col_scale = _equilibrate(M, col_of, bounded, col_scale)
    bs = b * row_scale
    rows, empty, dependent = _kept_rows(M, b, bs, dependent)
    Mr = sp.csc_matrix(M[rows]) if rows.size < nc else M
    b_kept = bs[rows]
    b_scale = 1.0 + float(np.abs(b_kept).max(initial=0.0))
    shift = nominal_free_point(Mr, b_kept, bounded) if (~bounded).any() and not empty else None
    if shift is not None:
        b_kept = b_kept - Mr @ shift
    return Presolved(Mr, b_kept, rows, cols, row_scale[rows], col_scale, bounded, empty, dependent,
                     shift, b_scale)


def _equilibrate(M: sp.csc_matrix, col_of: np.ndarray, bounded: np.ndarray,
                 col_scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Scale the rows and free columns of M in place (module docstring): (row_scale, col_scale).

    Rows are measured by their bounded entries, which are in the units of the factors' bounds
    (|η| ≤ 1): a row reads in those units whatever the scale of the free factors it also holds.
    Free columns are then scaled to unit ∞-norm, which puts the free factors' values in the same
    units (a trajectory set of noise scale 1e-6 has states of size 1e-6: unscaled they would sit
    below the solver's absolute tolerances). Rows without bounded entries are measured by all of
    them, which the free-column scaling changes: hence a few alternating sweeps."""
    free = ~bounded
    has_free = bool(free.any())
    bounded_norm = _row_abs_max(M, bounded[col_of]) if has_free else _row_abs_max(M)
    row_scale = _inverse(bounded_norm)
    M.data *= row_scale[M.indices]
    if not has_free:
        return row_scale, col_scale
    only_free = bounded_norm == 0
    # A free factor seen by a row with bounded entries takes its units from those rows: scaled to
    # unit ∞-norm over them, its values are of the bounded factors' size (a state of the trajectory
    # set at noise scale 1e3 becomes O(1), not 1e3: measured by all rows, the free-only rows (a
    # dynamics row without noise) would pin it at its raw scale and leave the interior-point
    # method a dual residual of ~1e-7 on it, and a wrong support value).
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
    return row_scale, col_scale


def _kept_rows(M: sp.csc_matrix, b: np.ndarray, bs: np.ndarray, dependent: bool
               ) -> tuple[np.ndarray, bool, bool]:
    """(the rows kept, whether the set is empty, whether dependent rows were looked for): zero rows
    dropped, and linearly dependent ones when ``dependent`` and the dense QR fits in memory."""
    nonzero = _row_abs_max(M) > 0
    # A zero row reads 0 = b_i; b_i left over by cancellation is rounding, judged against the other
    # rows' normalized right-hand sides, as `independent_rows` judges one.
    scale_b = 1.0 + np.abs(bs[nonzero]).max(initial=0.0)
    empty = bool(np.any(np.abs(b[~nonzero]) > np.sqrt(tol.RANK_TOL) * scale_b))
    rows = np.flatnonzero(nonzero)
    if dependent and rows.size * M.shape[1] > DEPENDENT_DENSE_MAX:
        dependent = False  # not looked for: memory stays bounded (see DEPENDENT_DENSE_MAX)
    if dependent and rows.size > 1 and not empty and not _well_conditioned(M, rows):
        basis = independent_rows(M[rows] if rows.size < M.shape[0] else M, bs[rows])
        empty = not basis.consistent
        rows = rows[basis.keep]
    return rows, empty, dependent


def _neighbour_units(M: sp.csc_matrix, col_of: np.ndarray, floating: np.ndarray) -> np.ndarray:
    """Column scales that put each floating free factor in the units of its scaled neighbours.

    A floating factor ξ_j (a state seen only by dynamics rows without noise, such as a state
    component that neither B·W nor the measurement reaches) is fixed by a row
    a_j ξ_j + Σ_i a_i ξ_i = b with ξ_i already in unit scale, so |ξ_j| ≈ max_i |a_i| / |a_j|: the
    scale s_j = min over its rows of that ratio makes the entry a_j s_j no larger than its row's
    other entries. Without it the alternating equilibration settles with the floating column at its
    raw scale (the row's largest entry, so unit row and column norms): at noise scale 1e-6 such a
    state is 1e-7 in the solver's units, below Clarabel's and HiGHS's absolute tolerances, and
    hulls come out off by 1e-3 of their width (evidence: docs/numerical_core.md).
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
    G = gram(M[rows] if m < M.shape[0] else M)
    bound = float(np.abs(G).sum(axis=1).max(initial=0.0))
    if not bound > 0 or not np.isfinite(bound):
        return False
    G[np.diag_indices(m)] -= (INDEPENDENT_RCOND ** 2 + 4 * m * np.finfo(float).eps) * bound
    # LAPACK's potrf as `scipy.linalg.cholesky` calls it (the same routine and arguments), without
    # its wrapper's checks, which cost more than the factorization of a small program's rows.
    _, info = dpotrf(G, lower=True, overwrite_a=True)
    if info < 0:
        raise ValueError(f"LAPACK reported an illegal value in argument {-info} of POTRF")
    return info == 0


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
