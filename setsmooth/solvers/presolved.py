"""The presolved factor set: the program {Âη = b̂, |η_B| ≤ 1} that `presolve.presolve` returns, with
the maps between its units and the original factors and the independent check of an answer.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.sparse import _sparsetools

from .. import tolerances as tol
from .small_products import SmallProduct

__all__ = ["Presolved", "CompiledProduct", "compiled"]


class CompiledProduct:
    """``op(S) @ X`` for a CSR or CSC matrix S, op(S) = S, Sᵀ, |S| or |S|ᵀ, and arrays X of shape
    (n,) or (n, k), by the compiled kernel that scipy's product calls (``csr_matvec`` or
    ``csc_matvec`` for a vector or one column, else ``csr_matvecs`` or ``csc_matvecs``), called
    directly on S's arrays.

    It is scipy's product bit for bit: the same kernel on the same arrays, summed into zeros (Sᵀ is
    the other format on S's arrays, as scipy's ``S.T``; |S| takes |data| once S's duplicates are
    summed, as scipy's ``abs(S)``). It skips the Python dispatch around the kernel (~20 µs) and the
    construction of Sᵀ and |S|, which the checks and certificates of a chain of thousands of warm
    solves paid per product.

    Parameters
    ----------
    S : csr_matrix or csc_matrix
    transpose, absolute : bool
        op(S) = Sᵀ, |S| (both: |S|ᵀ).
    """

    def __init__(self, S, *, transpose: bool = False, absolute: bool = False):
        if absolute:
            S.sum_duplicates()  # in place, as scipy's abs(S) does before taking |data|
        fmt = S.format if not transpose else {"csr": "csc", "csc": "csr"}[S.format]
        self._vector = getattr(_sparsetools, fmt + "_matvec")
        self._vectors = getattr(_sparsetools, fmt + "_matvecs")
        self.shape = S.shape[::-1] if transpose else S.shape
        self._arrays = (S.indptr, S.indices, np.abs(S.data) if absolute else S.data)

    def __matmul__(self, X: np.ndarray) -> np.ndarray:
        M, N = self.shape
        if X.shape[0] != N or X.ndim > 2:
            raise ValueError(f"matmul: dimension mismatch, ({M}, {N}) @ {X.shape}")
        dtype = np.promote_types(self._arrays[2].dtype, X.dtype)
        if X.ndim == 1 or X.shape[1] == 1:
            out = np.zeros(M, dtype=dtype)
            self._vector(M, N, *self._arrays, X.ravel(), out)
            return out if X.ndim == 1 else out.reshape(M, 1)
        out = np.zeros((M, X.shape[1]), dtype=dtype)
        self._vectors(M, N, X.shape[1], *self._arrays, X.ravel(), out.ravel())
        return out


def compiled(P: SmallProduct) -> SmallProduct | CompiledProduct:
    """``P`` where it sums densely (a small matrix) or its matrix is not canonical (scipy's |M|
    reorders M's entries in place when first used), else its sparse operator as a
    `CompiledProduct`: bit for bit ``P @ X`` either way."""
    if P.dense is not None or not P.M.has_canonical_format:
        return P
    return CompiledProduct(P.M, transpose=P.transpose, absolute=P.absolute)


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
        return self.A.T  # CSR, sharing Â's arrays

    @cached_property
    def products(self) -> tuple[SmallProduct, SmallProduct]:
        """(Â, Âᵀ) for products with vectors, bit for bit scipy's and cheaper on small programs."""
        return SmallProduct(self.A), SmallProduct(self.A, transpose=True)

    @cached_property
    def _check_products(self) -> tuple:
        """(Â, Âᵀ) for the check's products: `products`, their sparse ones `compiled`."""
        return tuple(compiled(P) for P in self.products)

    @cached_property
    def _selections(self) -> tuple[np.ndarray, np.ndarray]:
        """The bounded and the free factors' indices (the check's selections, made once: the same
        entries in the same order as the masks ``bounded`` and ``~bounded`` select)."""
        return np.flatnonzero(self.bounded), np.flatnonzero(~self.bounded)

    @cached_property
    def free_columns(self) -> sp.csc_matrix:
        """Â_F, the free factors' columns, kept (`project_free` needs them per direction)."""
        return self.A[:, ~self.bounded]

    @cached_property
    def _free_rows(self) -> tuple[np.ndarray, sp.csr_matrix]:
        """The free factors' indices and their rows of Âᵀ."""
        free = self._selections[1]
        return free, self.At[free]

    @cached_property
    def _free_product(self) -> CompiledProduct:
        """The product with the free factors' rows of Âᵀ (`CompiledProduct`)."""
        return CompiledProduct(self._free_rows[1])

    def free_residual(self, q: np.ndarray, z: np.ndarray) -> float:
        """max_j free |q_j + (Âᵀz)_j|: how far z is from cancelling the objective q on the free
        factors (0 without free factors)."""
        if not self.has_free:
            return 0.0
        residual = self._free_product @ z
        residual += q[self._selections[1]]
        return float(np.abs(residual, out=residual).max(initial=0.0))

    def checked_gap(self, q: np.ndarray, eta: np.ndarray, z: np.ndarray) -> float | None:
        """`checked_gaps` of one answer: the relative gap, or None when the check fails."""
        gap = float(self.checked_gaps(q[None], eta[None], z[None])[0])
        return None if np.isinf(gap) else gap

    def checked_gaps(self, Q: np.ndarray, eta: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Independent check of reduced-accuracy answers (η, ẑ) to min qᵀη (rows of ``Q``, ``eta``
        and ``z``), in the presolved units: primal residual, bound overshoot and gap to the
        weak-duality bound b̂ᵀλ + Σ_B |ĝ − Âᵀλ|_j must be within ``SOLVER_CHECK_TOL`` of the scale
        (rows and objective have unit ∞-norm, bounds are 1). Returns the relative gaps, inf where
        the check fails."""
        lam = z  # Clarabel's stationarity q + Âᵀz = 0 on the free factors: λ̂ = z
        product, product_t = self._check_products
        # |ĝ − Âᵀλ| = |−q − Âᵀλ| = |q + Âᵀλ| bit for bit (negation is exact), formed in place, as
        # are the residual and the overshoot (each sum over the same layout as before)
        abs_reduced = np.add(Q, (product_t @ lam.T).T)
        np.abs(abs_reduced, out=abs_reduced)
        free = self.has_free  # else the selections take every entry: the same sums, unselected
        bounded, unbounded = self._selections
        leak = abs_reduced[:, unbounded].max(axis=1, initial=0.0) if free else 0.0
        primal = -np.einsum("ij,ij->i", Q, eta)
        dual = lam @ self.b + (abs_reduced[:, bounded] if free else abs_reduced).sum(axis=1)
        scale = self.data_scale + np.abs(Q).sum(axis=1)
        residual = (product @ eta.T).T
        np.subtract(residual, self.b, out=residual)
        residual = np.abs(residual, out=residual).max(axis=1, initial=0.0)
        overshoot = np.abs(eta[:, bounded] if free else eta)
        overshoot = np.subtract(overshoot, 1.0, out=overshoot).max(axis=1, initial=0.0)
        worst = np.maximum(np.maximum(np.abs(dual - primal), residual), overshoot) / scale
        failed = (worst > tol.SOLVER_CHECK_TOL) | (leak > tol.REDUCED_COST_TOL)
        return np.where(failed, np.inf, worst)

    def objective(self, g: np.ndarray) -> np.ndarray:
        """ĝ = S g[cols] for objectives ``g`` of the original factors (rows of a (k, ng) array)."""
        return g[:, self.cols] * self.col_scale

    def minimized(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The minimized objectives q = −ĝ/σ for maximizing the rows of ``g`` (original factors,
        shape (k, ng)) and their scales σ = ‖ĝ‖∞ (1 for a zero objective), row by row."""
        ghat = self.objective(g)
        sigma = np.abs(ghat).max(axis=1, initial=0.0)
        sigma[sigma == 0.0] = 1.0
        return -ghat / sigma[:, None], sigma

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
