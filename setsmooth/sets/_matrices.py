"""Block assembly that keeps a matrix sparse when any of its parts is sparse, dense otherwise."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def any_sparse(*mats) -> bool:
    return any(sp.issparse(m) for m in mats)


def hstack(mats):
    return sp.hstack(mats, format="csc") if any_sparse(*mats) else np.hstack(mats)


def vstack(mats):
    return sp.vstack(mats, format="csc") if any_sparse(*mats) else np.vstack(mats)


#: A block-diagonal result with more entries than this is stored sparse: CZ constraint matrices built
#: by repeated intersections (filters, smoothers) are mostly zero blocks.
SPARSE_ABOVE = 4096


def block_diag(*mats):
    rows = sum(m.shape[0] for m in mats)
    cols = sum(m.shape[1] for m in mats)
    if any_sparse(*mats) or rows * cols > SPARSE_ABOVE:
        return sp.block_diag([sp.csc_matrix(m) for m in mats], format="csc")
    out = np.zeros((rows, cols))
    r = c = 0
    for m in mats:
        out[r:r + m.shape[0], c:c + m.shape[1]] = m
        r += m.shape[0]
        c += m.shape[1]
    return out


def zeros_like_kind(rows: int, cols: int, sparse: bool):
    return sp.csc_matrix((rows, cols)) if sparse else np.zeros((rows, cols))


def matmul(M, X):
    """M @ X, returning a dense array when both are dense and a CSC matrix otherwise."""
    out = M @ X  # ndarray @ sparse is an ndarray: the operands decide, not the product's type
    return sp.csc_matrix(out) if any_sparse(M, X) else np.asarray(out)


def abs_row_sums(G) -> np.ndarray:
    """Σ_j |G_ij| for each row i."""
    if sp.issparse(G):
        return np.asarray(abs(G).sum(axis=1)).reshape(-1)
    return np.abs(G).sum(axis=1)


def readonly(arr: np.ndarray) -> np.ndarray:
    arr = np.array(arr, dtype=float, copy=True)
    arr.flags.writeable = False
    return arr
