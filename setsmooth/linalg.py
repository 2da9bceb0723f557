"""Rank decisions on linear equality constraints Aξ = b, shared by the LP presolve and order reduction.

Every decision here is relative: a row is zero, or dependent on others, when it is so up to
``RANK_TOL`` times the scale of the (row-normalized) data, so that scaling a row or the whole system
by 1e±12 does not change the verdict.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from . import tolerances as tol

__all__ = ["RowBasis", "independent_rows"]


@dataclass(frozen=True)
class RowBasis:
    """Which rows of Aξ = b carry information.

    Attributes
    ----------
    keep : ndarray of int
        Indices (increasing) of a maximal set of linearly independent rows.
    consistent : bool
        False when a dropped row contradicts the kept ones (a zero row with b ≠ 0, or a dependent row
        whose right-hand side is not the same combination of the kept ones): then {ξ : Aξ = b} is
        empty.
    """

    keep: np.ndarray
    consistent: bool


def independent_rows(A, b: np.ndarray, rtol: float = tol.RANK_TOL) -> RowBasis:
    """A maximal linearly independent subset of the rows of ``[A b]``'s left block, and consistency.

    Rows are normalized to unit 2-norm first (with b scaled alike), so the verdict does not depend on
    how each equation is scaled; only an exactly zero row is a zero row, and it is consistent when its
    b_i is within ``sqrt(rtol)`` of zero relative to the normalized right-hand sides. The basis is
    chosen by a QR factorization of Aᵀ with column pivoting (rank-revealing); a row whose pivot falls
    below ``rtol · max(shape) · largest pivot`` is dependent.
    A dependent row is consistent when its right-hand side equals, to ``rtol`` relative to the kept
    right-hand sides it combines, the combination of the kept rows that reproduces it.

    Parameters
    ----------
    A : ndarray or sparse matrix, shape (nc, ng)
    b : ndarray, shape (nc,)
    rtol : float
        Relative rank tolerance.

    Returns
    -------
    RowBasis

    Examples
    --------
    >>> import numpy as np
    >>> basis = independent_rows(np.array([[1.0, 1.0], [2.0, 2.0], [0.0, 0.0]]), np.array([1.0, 2.0, 0.0]))
    >>> basis.keep.tolist(), basis.consistent
    ([0], True)
    >>> independent_rows(np.array([[1.0, 1.0], [2.0, 2.0]]), np.array([1.0, 3.0])).consistent
    False
    """
    A = A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    nc = A.shape[0]
    if nc == 0:
        return RowBasis(np.zeros(0, dtype=int), True)
    norms = np.linalg.norm(A, axis=1)
    # Only an exactly zero row is zero: each row is normalized on its own, so a row scaled by 1e-12
    # keeps its full weight.
    zero = norms <= np.finfo(float).tiny
    rows = np.flatnonzero(~zero)
    An = A[rows] / norms[rows, None]
    bn = b[rows] / norms[rows]
    # A zero row reads 0 = b_i; b_i left over by cancellation is rounding, judged against the data.
    consistent = bool(np.all(np.abs(b[zero]) <= np.sqrt(rtol) * (1.0 + np.abs(bn).max(initial=0.0))))
    if rows.size == 0:
        return RowBasis(np.zeros(0, dtype=int), consistent)
    R, piv = sla.qr(An.T, mode="r", pivoting=True)  # Q is not needed: half the cost
    pivots = np.abs(np.diag(R))
    rank = int(np.count_nonzero(pivots > rtol * max(An.shape) * pivots[0]))
    kept, dropped = piv[:rank], piv[rank:]
    keep = rows[np.sort(kept)]
    if consistent and dropped.size:
        # Coefficients y with An[kept]ᵀ y = An[dropped]ᵀ in the least-squares sense: with
        # An[piv]ᵀ = Q R, that is R₁₁ y = R₁₂, a triangular solve (an SVD-based lstsq of the same
        # dominated the presolve of large factor sets).
        Y = sla.solve_triangular(R[:rank, :rank], R[:rank, rank:])
        predicted = Y.T @ bn[kept]
        scale = 1.0 + np.abs(Y.T) @ np.abs(bn[kept])
        consistent = bool(np.all(np.abs(predicted - bn[dropped]) <= np.sqrt(rtol) * scale))
    return RowBasis(keep, consistent)
