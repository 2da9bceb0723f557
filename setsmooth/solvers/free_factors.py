"""The free factors of a presolved program: the point the program is posed around, and the
projection of an objective off them.

Free factors (h = ∞: the states of trajectory sets and posterior views) have no bound of their own;
only the rows tie them to the bounded factors. `nominal_free_point` is the least-squares point η⁰ of
the rows in the free factors alone: the presolved program's free factors are deviations from it, so
its right-hand side is what the bounded factors must produce, O(1) on a non-empty set whatever the
data's precision or the states' distance from the origin. `project_free` moves the part of an
objective that lies on the free factors into the multipliers.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg

from .certify import correct_multipliers, normal_solver
from .instances import cached_instance

__all__ = ["nominal_free_point", "project_free", "NOMINAL_DENSE_MAX"]

#: The free factors' nominal point (`nominal_free_point`) is a dense least-squares solve up to this
#: many entries of Â_F, and LSQR (a fixed iteration limit: deterministic) beyond.
NOMINAL_DENSE_MAX = 250_000


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


def project_free(pre, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q + Âᵀλ₀ with its free entries set to zero, λ₀), λ₀ the least-squares solution of
    Â_Fᵀλ₀ = −q_F: the same objective on {Âη = b̂} up to the constant and the residual on the free
    factors, which the recession program found to be within tolerance.

    λ₀ is the least-norm solution through the normal equations of Â_F (one sparse LU per presolved
    program and thread, refined), or by lsqr when Â_F is rank deficient: `certify.correct_multipliers`
    from λ = 0; one factorization serves every direction, where lsqr per direction dominated a
    smoother's time (docs/numerical_core.md).
    """
    free = ~pre.bounded
    AF = pre.free_columns
    solve_normal = cached_instance(pre, "normal equations of the free factors",
                                   lambda: normal_solver(AF))
    lam0 = correct_multipliers(AF, -q[free][None, :], np.zeros((1, pre.A.shape[0])),
                               solve_normal, pre._free_rows[1])[0]
    shifted = q + pre.At @ lam0
    shifted[free] = 0.0
    return shifted, lam0
