"""The bound on the free factors that certifies support values of trajectory sets, in O(length).

A certified support value (`solvers.certify`) of a constrained zonotope with free factors charges the
rounding residual of the multipliers against β ≥ ‖ξ_F‖∞, which needs a rigorous lower bound on
λ_min(A_FᵀA_F). The general path computes it densely (an eigenvalue problem of the nF × nF Gram matrix:
O(nF³), and not at all beyond `certify.FREE_BOUND_DENSE_MAX` free factors). In a trajectory set the free
factors are the states, written in time order, and every row couples neighbouring times only, so the
Gram matrix is **banded** (half-bandwidth < 2n). There the bound costs O(nF):

* a proof that M − μI is positive definite, for μ found by halving from min a_ii (≥ λ_min) and a few
  bisections, each by a floating-point banded Cholesky
  factorization of M − (μ + c)I running to completion, with Rump's shift c ≥ γ_{N+1}/(1 − γ_{N+1})·tr(M)
  for the rounding errors of the factorization (S. M. Rump, "Verification of positive definiteness",
  BIT 46 (2006), Lemma 2.1: a successful floating-point Cholesky factorization of a matrix shifted by
  this much proves the unshifted one positive definite) and the shifted diagonal rounded downward;
* λ_min of the exact Gram matrix ≥ μ − ‖M − A_FᵀA_F‖₂, the computed Gram matrix's rounding error bounded
  as in `certify.free_factor_bound` (γ_{nc+2}‖|A_F|ᵀ|A_F|‖_F).
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sp
from scipy.linalg import LinAlgError, cholesky_banded

from ..floating import gamma
from ..solvers.certify import free_factor_bound

__all__ = ["banded_free_factor_bound", "gram_lower_bound", "BANDED_MAX_BANDWIDTH"]

#: Gram matrices with a larger half-bandwidth are left to the dense bound (not a trajectory layout).
BANDED_MAX_BANDWIDTH = 64

#: Halvings of the shift from min a_ii before giving up (λ_min below 2⁻⁶⁰ of the diagonal: singular to
#: working accuracy), and bisections of the last factor of 2 (the bound is then within 2^(1/2⁴)).
_HALVINGS = 60
_BISECTIONS = 4

#: Smallest positive normal number: covers the underflow terms of Rump's shift (2N + tr) · η.
_TINY = float(np.finfo(float).tiny)


def gram_lower_bound(AF: sp.spmatrix) -> float | None:
    """A rigorous lower bound on λ_min(A_FᵀA_F) of the exact data when the Gram matrix is banded.

    Parameters
    ----------
    AF : sparse matrix, shape (nc, nF)
        The free factors' columns, in an order that makes A_FᵀA_F banded.

    Returns
    -------
    float or None
        A positive lower bound, or None when the Gram matrix is not banded (half-bandwidth above
        `BANDED_MAX_BANDWIDTH`), not positive definite to working accuracy, or not proven so.
    """
    AF = sp.csc_matrix(AF, copy=True)
    AF.sum_duplicates()
    # Memoized on the matrix itself (exactly: its canonical CSC arrays): the windows of one length
    # along time share their states' columns, outer and inner bracket alike, so the bound is computed
    # once per window shape.
    key = (AF.shape, AF.indptr.astype(np.int64).tobytes(), AF.indices.astype(np.int64).tobytes(),
           AF.data.tobytes())
    return _gram_lower_bound(*key)


@functools.lru_cache(maxsize=16)
def _gram_lower_bound(shape: tuple[int, int], indptr: bytes, indices: bytes, data: bytes
                      ) -> float | None:
    AF = sp.csc_matrix((np.frombuffer(data, dtype=float), np.frombuffer(indices, dtype=np.int64),
                        np.frombuffer(indptr, dtype=np.int64)), shape=shape)
    N = AF.shape[1]
    if N == 0:
        return None
    gram = sp.coo_matrix(AF.T @ AF)
    low = gram.row >= gram.col
    offset = gram.row[low] - gram.col[low]
    width = int(offset.max(initial=0))
    if width > BANDED_MAX_BANDWIDTH:
        return None
    band = np.zeros((width + 1, N))  # LAPACK's lower band storage: band[i − j, j] = M[i, j]
    np.add.at(band, (offset, gram.col[low]), gram.data[low])
    if not np.all(np.isfinite(band)):
        return None
    absAF = abs(AF)
    abs_gram = sp.csr_matrix(absAF.T @ absAF)
    gram_err = float(gamma(AF.shape[0] + 2)) * float(np.sqrt((abs_gram.data ** 2).sum())) * (
        1.0 + float(gamma(abs_gram.nnz + 2)))
    trace = float(band[0].sum())
    # Rump's shift, doubled for margin, plus the trace's own rounding and the underflow terms.
    c = 2.0 * float(gamma(N + 2)) * trace * (1.0 + float(gamma(N))) + (2 * N + 2) * _TINY

    def proven(mu: float) -> bool:
        """Whether M − μI is proven positive definite (a Cholesky factorization of M − (μ + c)I)."""
        shift = np.nextafter(mu + c, np.inf)
        shifted = band.copy()
        # Two steps down: the computed diagonal is at most the exact a_ii − shift.
        shifted[0] = np.nextafter(np.nextafter(band[0] - shift, -np.inf), -np.inf)
        try:
            cholesky_banded(shifted, lower=True, check_finite=False)
        except LinAlgError:
            return False
        return True

    # λ_min ≤ min a_ii: halve from there until proven (each try is one O(N) factorization, far
    # cheaper than LAPACK's banded eigensolver), then bisect the last factor of 2 a few times.
    hi = float(band[0].min())
    mu = 0.5 * hi
    for _ in range(_HALVINGS):
        if not mu > gram_err:
            return None
        if proven(mu):
            break
        hi, mu = mu, 0.5 * mu
    else:
        return None
    for _ in range(_BISECTIONS):
        mid = 0.5 * (mu + hi)
        if proven(mid):
            mu = mid
        else:
            hi = mid
    bound = np.nextafter(mu - gram_err, -np.inf)  # ≤ λ_min(M) − ‖M − A_FᵀA_F‖₂
    return float(bound) if bound > 0 else None


def banded_free_factor_bound(A: sp.spmatrix, b: np.ndarray, h: np.ndarray,
                             slack: np.ndarray | None = None,
                             slack_free: np.ndarray | None = None) -> float | None:
    """β ≥ max ‖ξ_F‖∞ over {ξ : Aξ = b, |ξ| ≤ h} (`certify.free_factor_bound`) from the banded
    λ_min bound, or None when the free factors' Gram matrix is not banded or not proven definite.

    Parameters
    ----------
    A : sparse matrix, shape (nc, ng)
    b : ndarray, shape (nc,)
    h : ndarray, shape (ng,)
        Factor bounds; the free factors (h = ∞) in an order that makes A_FᵀA_F banded.
    slack, slack_free : ndarray, shape (nc,), optional
        The rows' rounding charges: the bound holds on the relaxed set (`certify.free_factor_bound`).

    Returns
    -------
    float or None
    """
    free = np.flatnonzero(~np.isfinite(h))
    if free.size == 0:
        return 0.0
    A = sp.csc_matrix(A)
    AF = sp.csc_matrix(A[:, free])
    lam_min = gram_lower_bound(AF)
    if lam_min is None:
        return None
    return free_factor_bound(A, b, h, lam_min=lam_min, AF=AF, slack=slack, slack_free=slack_free)
