"""The block-by-block scipy assembly the trajectory set used before `setsmooth.trajectories` built its
sparse matrix in one step from index arrays: kept as the reference of the bit-identity test
(``tests/test_trajectories.py``) and of the assembly timing in ``benchmarks/bench_smoothing.py``."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["block_assembly"]


def block_assembly(system, X0, ys):
    """(A, b) of the trajectory set for start = 0, assembled from one small scipy block per row group."""
    Z0 = X0.to_constrained_zonotope()
    Zw = system.W.to_constrained_zonotope()
    Zv = system.V.to_constrained_zonotope()
    n, T = system.n, ys.shape[0] - 1
    n_states = n * (T + 1)
    col_x0 = n_states
    col_w = col_x0 + Z0.ng
    col_v = col_w + T * Zw.ng
    n_factors = col_v + (T + 1) * Zv.ng
    dense = lambda M: M.toarray() if sp.issparse(M) else np.asarray(M)  # noqa: E731
    rows, rhs = [], []

    def block(r, pieces):
        mats = []
        for offset, M in pieces:
            M = sp.coo_matrix(M)
            mats.append(sp.coo_matrix((M.data, (M.row, M.col + offset)), shape=(r, n_factors)))
        return sum(mats[1:], mats[0]).tocsr()

    if Z0.nc:
        rows.append(block(Z0.nc, [(col_x0, Z0.A)]))
        rhs.append(Z0.b)
    for k in range(T):
        if Zw.nc:
            rows.append(block(Zw.nc, [(col_w + k * Zw.ng, Zw.A)]))
            rhs.append(Zw.b)
    for k in range(T + 1):
        if Zv.nc:
            rows.append(block(Zv.nc, [(col_v + k * Zv.ng, Zv.A)]))
            rhs.append(Zv.b)
    eye = sp.identity(n)
    rows.append(block(n, [(0, eye), (col_x0, -sp.csr_matrix(Z0.G))]))
    rhs.append(Z0.c)
    for k in range(T):
        Bk = system.E_at(k)
        rows.append(block(n, [((k + 1) * n, eye), (k * n, -system.A_at(k)),
                              (col_w + k * Zw.ng, -(Bk @ dense(Zw.G)))]))
        rhs.append(Bk @ Zw.c + system.input_term(k))
    for k in range(T + 1):
        Dk = system.F_at(k)
        rows.append(block(system.m, [(k * n, system.C_at(k)), (col_v + k * Zv.ng, Dk @ dense(Zv.G))]))
        rhs.append(ys[k] - Dk @ Zv.c)
    return sp.vstack(rows, format="csc"), np.concatenate(rhs)
