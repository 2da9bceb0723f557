"""Products with a small sparse matrix, computed densely and bit for bit as scipy computes them.

A small program's checks and certificates multiply its rows by a few vectors per direction. scipy's
sparse product costs about fifteen Python calls (format, shape and dtype checks) around a few
hundred flops, and the construction of a transpose or of |M| costs more: on the interval hull of a
small constrained zonotope they took a large part of the time outside the solver. A BLAS product of
a dense copy would be cheaper but sums in its own order, so the last bits of every check and
certificate would change.

These products sum every entry as scipy's compiled kernels do (``csr_matvec(s)``, ``csc_matvec(s)``,
``csr_matmat``): sequentially, from +0, over the inner index in ascending order (the order of a
canonical matrix's stored entries). ``np.add.accumulate`` is sequential along its axis (``np.sum``
is pairwise). The dense copy also adds the structural zeros' products, ±0, which leave a sum
unchanged except for the sign of a zero sum; adding +0.0 at the end gives scipy's +0. The dense path
is taken only for a canonical matrix of at most ``SMALL_PRODUCT_MAX`` entries and finite operands
(0·∞ is NaN where scipy skips the entry); otherwise scipy computes the product.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["SMALL_PRODUCT_MAX", "GRAM_DENSE_MAX", "SmallProduct", "gram"]

#: Largest m·p of a matrix whose products are summed densely.
SMALL_PRODUCT_MAX = 5_000

#: Largest m²·p for which `gram` sums M Mᵀ densely (the (m, m, p) products are held at once).
GRAM_DENSE_MAX = 250_000




class SmallProduct:
    """``op(M) @ X`` for a sparse M (CSC or CSR), op(M) = M, Mᵀ, |M| or |M|ᵀ: bit for bit scipy's
    product of the same operator (the transpose as scipy's ``M.T``, |M| as ``abs(M)``).

    Parameters
    ----------
    M : csc_matrix or csr_matrix, shape (m, p)
    transpose, absolute : bool
        op(M) = Mᵀ, |M| (both: |M|ᵀ).
    """

    def __init__(self, M, *, transpose: bool = False, absolute: bool = False):
        self.M, self.transpose, self.absolute = M, transpose, absolute
        m, p = M.shape
        self.shape = (p, m) if transpose else (m, p)
        self.dense = None
        if 0 < m * p <= SMALL_PRODUCT_MAX and M.has_canonical_format:
            D = np.abs(M.toarray()) if absolute else M.toarray()
            self.dense = np.ascontiguousarray(D.T) if transpose else D
        self._sparse = None

    @property
    def sparse(self):
        """op(M) as scipy's sparse matrix (built on first use)."""
        if self._sparse is None:
            S = abs(self.M) if self.absolute else self.M
            self._sparse = S.T if self.transpose else S
        return self._sparse

    def __matmul__(self, X: np.ndarray) -> np.ndarray:
        D = self.dense
        if D is None or X.dtype != np.float64 or not np.isfinite(X).all():
            return self.sparse @ X
        # Σ over the inner index, term by term in ascending order; + 0.0: a zero sum is +0
        if X.ndim == 1:
            return np.add.accumulate(D * X, axis=1)[:, -1] + 0.0
        return np.add.accumulate(D[:, :, None] * X, axis=1)[:, -1] + 0.0


def gram(M: sp.csc_matrix) -> np.ndarray:
    """M Mᵀ as a dense array, bit for bit ``(M @ M.T).toarray()`` (each entry Σ_k M_ik M_jk in
    ascending k), summed densely when m²·p is at most ``GRAM_DENSE_MAX``."""
    m, p = M.shape
    if p == 0 or m * m * p > GRAM_DENSE_MAX or not M.has_canonical_format:
        return (M @ M.T).toarray()
    D = M.toarray()
    return np.add.accumulate(D[:, None, :] * D[None, :, :], axis=2)[:, :, -1] + 0.0
