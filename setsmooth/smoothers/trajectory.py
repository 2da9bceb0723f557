"""The set of all state trajectories consistent with the measurements, as one sparse extended CZ.

    ⟦x_{0:T} | y_{0:T}⟧ = { (x_0, …, x_T) : x_0 ∈ X0,  x_{k+1} = A_k x_k + B_k w_k + u_k,
                                              y_k = C_k x_k + D_k v_k,  w_k ∈ W,  v_k ∈ V }

Its projection on x_k is the optimal smoothed range ⟦x_k | y_{0:T}⟧ (smoothing paper Theorem 1: the
smoothed range is the set of x_k over all consistent trajectories), and its projection on x_T is the
last posterior. The states themselves are free factors (h = ∞) of the extended CZ (stability paper
Definition 7), so every constraint couples only neighbouring time steps: O(T) factors, O(T) sparse
rows, instead of the dense O(T²) blocks that eliminating the states would create.

Factors, in order: s_0..s_T (the states, h = ∞), ξ_0 (X0), ξ_{w,0..T−1} (W), ξ_{v,0..T} (V).
Rows: A0ξ_0 = b0, A_wξ_{w,k} = b_w, A_vξ_{v,k} = b_v, then
    s_0 − G0ξ_0                       = c0
    s_{k+1} − A_k s_k − B_k G_w ξ_{w,k} = B_k c_w + u_k
    C_k s_k + D_k G_v ξ_{v,k}           = y_k − D_k c_v
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from .._validation import as_measurements
from ..sets.base import ConvexSet
from ..sets.constrained_zonotope import ConstrainedZonotope


def trajectory_set(system, X0: ConvexSet, ys: Any) -> ConstrainedZonotope:
    """The set of trajectories (x_0, …, x_T) ∈ ℝ^{n(T+1)} consistent with y_{0:T}.

    Parameters
    ----------
    system : LinearSystem
        Its W and V (and ``X0``) must flatten to constrained zonotopes (Box, Zonotope, CZ).
    X0 : ConvexSet
        Initial prior range.
    ys : array_like, shape (T+1, m)

    Returns
    -------
    ConstrainedZonotope
        Sparse, of dimension n(T+1); coordinates k·n .. (k+1)·n − 1 hold x_k.

    Raises
    ------
    TypeError
        If X0, W or V has no exact constrained-zonotope form.
    """
    ys = as_measurements(ys, system.m)
    if not isinstance(X0, ConvexSet) or X0.dim != system.n:
        raise ValueError(f"X0 must be a ConvexSet of dimension n = {system.n}")
    Z0 = X0.to_constrained_zonotope()
    Zw = system.W.to_constrained_zonotope()
    Zv = system.V.to_constrained_zonotope()
    n, T = system.n, ys.shape[0] - 1

    # Column offsets of each factor group.
    n_states = n * (T + 1)
    col_x0 = n_states
    col_w = col_x0 + Z0.ng
    col_v = col_w + T * Zw.ng
    n_factors = col_v + (T + 1) * Zv.ng

    rows: list[sp.spmatrix] = []
    rhs: list[np.ndarray] = []

    def block(r: int, pieces: list[tuple[int, Any]]) -> sp.csr_matrix:
        """A row block of height r with the given (column offset, matrix) pieces."""
        mats = []
        for offset, M in pieces:
            M = sp.coo_matrix(M)
            mats.append(sp.coo_matrix((M.data, (M.row, M.col + offset)), shape=(r, n_factors)))
        return sum(mats[1:], mats[0]).tocsr()

    # Constraints of the noise and initial factor sets.
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
    # x_0 ∈ X0
    rows.append(block(n, [(0, eye), (col_x0, -sp.csr_matrix(Z0.G))]))
    rhs.append(Z0.c)
    # dynamics
    for k in range(T):
        Bk = system.B(k)
        rows.append(block(n, [((k + 1) * n, eye), (k * n, -system.A(k)),
                              (col_w + k * Zw.ng, -(Bk @ _dense(Zw.G)))]))
        rhs.append(Bk @ Zw.c + system.input_term(k))
    # measurements
    for k in range(T + 1):
        Dk = system.D(k)
        rows.append(block(system.m, [(k * n, system.C(k)), (col_v + k * Zv.ng, Dk @ _dense(Zv.G))]))
        rhs.append(ys[k] - Dk @ Zv.c)

    A = sp.vstack(rows, format="csc")
    b = np.concatenate(rhs)
    G = sp.csc_matrix((np.ones(n_states), (np.arange(n_states), np.arange(n_states))),
                      shape=(n_states, n_factors))
    h = np.concatenate([np.full(n_states, np.inf), Z0.h, np.tile(Zw.h, T), np.tile(Zv.h, T + 1)])
    trajectories = ConstrainedZonotope._trusted(G, np.zeros(n_states), A, b, h)
    trajectories.factors  # created now, so that every projection shares one factor set
    return trajectories


def _dense(M) -> np.ndarray:
    return M.toarray() if sp.issparse(M) else np.asarray(M)
