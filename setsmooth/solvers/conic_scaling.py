"""The equilibration of a compiled conic program (`conic.ConicForm`): starting column sizes from
the variables' bounds and definitions, then Ruiz scaling of the augmented matrix [A b].
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["groups", "bound_sizes", "defined_sizes", "ruiz", "RUIZ_PASSES"]

#: Ruiz equilibration passes: enough to bring rows and columns spread over 1e±12 to within a factor
#: of ~2 of each other.
RUIZ_PASSES = 25


def groups(n_zero: int, n_nonneg: int, soc: list[int], m: int) -> np.ndarray:
    """Start row of every block whose rows share one scaling factor (a cone keeps its shape
    only under a common factor; linear rows each form their own block)."""
    linear = n_zero + n_nonneg
    starts = list(range(linear))
    row = linear
    for k in soc:
        starts.append(row)
        row += k
    if row < m:
        starts.append(row)  # other cones: one common factor
    return np.array(starts, dtype=int)

def bound_sizes(A: sp.csc_matrix, b: np.ndarray, n_zero: int, n_nonneg: int) -> np.ndarray:
    """A starting column scaling from the variables' bounds: a linear row a·z_j ≤ b_i (or = b_i)
    says z_j has size ~|b_i/a|. Ruiz balances the matrix, not the variables: without this a
    variable bounded by 1e-8 next to one of size 1e12 stays at 1e-8 after scaling, below the
    solver's absolute accuracy."""
    c = np.ones(A.shape[1])
    lin = A[: n_zero + n_nonneg].tocsr()
    counts = np.diff(lin.indptr)
    rows = np.flatnonzero((counts == 1) & (b[: lin.shape[0]] != 0))
    if rows.size:
        cols = lin.indices[lin.indptr[rows]]
        size = np.abs(b[rows] / lin.data[lin.indptr[rows]])
        bound = np.zeros(A.shape[1])
        np.maximum.at(bound, cols, size)
        c = np.where(bound > 0, bound, 1.0)
    return defined_sizes(A, b, n_zero, c)

def defined_sizes(A: sp.csc_matrix, b: np.ndarray, n_zero: int, c: np.ndarray) -> np.ndarray:
    """Starting scales of the variables defined by one equality: a column whose only entry
    a_ij lies in a zero-cone row i is z_j = (b_i − Σ_k a_ik z_k)/a_ij, of the size
    max(|b_i|, max_k |a_ik| c_k)/|a_ij| of the row's other terms (k over the columns that are
    not themselves defined so).

    Ruiz cannot place such a column: its row and column factors only meet in their product, and
    the square-root splits it starts from leave, e.g., x = Gη + c of a set stated in coordinates
    of size 1e-12 (entry 4e12 on x, O(1) on η) at r = c_x = 5e-7 — the row's η terms at 1e-7
    and the objective xᵀd' below the solver's absolute accuracy (support values 7e-5 of the
    scale too low, yet within its tolerances)."""
    if n_zero == 0:
        return c
    nz = A.shape[1]
    A = A.tocsc()
    single = np.diff(A.indptr) == 1
    rows = np.full(nz, -1)
    rows[single] = A.indices[A.indptr[:-1][single]]
    entry = np.zeros(nz)
    entry[single] = np.abs(A.data[A.indptr[:-1][single]])
    # An explicit zero (a parameter set to 0, e.g. a dropped measurement) defines nothing.
    defined = single & (rows >= 0) & (rows < n_zero) & (entry > 0)
    if not defined.any():
        return c
    cols = np.flatnonzero(defined)
    coef = entry[cols]
    Z = abs(A[:n_zero]) @ sp.diags(np.where(defined, 0.0, c))
    others = np.maximum(np.asarray(Z.max(axis=1).todense()).ravel(),
                        np.abs(b[:n_zero]))[rows[cols]]
    c = c.copy()
    c[cols] = np.where(others > 0, others / coef, c[cols])
    return c

def ruiz(A: sp.csc_matrix, b: np.ndarray, starts: np.ndarray, c: np.ndarray
         ) -> tuple[np.ndarray, np.ndarray, float]:
    """Ruiz scaling of the augmented matrix [A b]: row factors r (common within a cone), column
    factors c and one factor β for b, so that the solution z' = β·z/c of the scaled program has
    entries of comparable size: a bound h_j = 1e12 next to h_k = 1e-8 would otherwise leave the
    small factors to the solver's absolute accuracy relative to the large ones."""
    m = A.shape[0]
    r, beta = np.ones(m), 1.0
    if m == 0:
        return r, c, beta
    sizes = np.diff(np.append(starts, m))
    absA, absb = abs(A), np.abs(b)
    for _ in range(RUIZ_PASSES):
        M = sp.diags(r) @ absA @ sp.diags(c)
        rb = r * absb * beta
        rows = np.maximum(np.asarray(M.max(axis=1).todense()).ravel(), rb)
        block = np.repeat(np.maximum.reduceat(rows, starts), sizes)
        cols = np.asarray(M.max(axis=0).todense()).ravel()
        bmax = rb.max(initial=0.0)
        sizes_now = np.concatenate([block, cols, [bmax]])
        sizes_now = sizes_now[sizes_now > 0]
        if sizes_now.size == 0 or np.abs(np.log2(sizes_now)).max() < 1:
            break
        r = r / np.sqrt(np.where(block > 0, block, 1.0))
        c = c / np.sqrt(np.where(cols > 0, cols, 1.0))
        if bmax > 0:
            beta = beta / np.sqrt(bmax)
    return r, c, beta
