"""The presolved factor set: the program {Âη = b̂, |η_B| ≤ 1} that `presolve.presolve` returns, with
the maps between its units and the original factors and the independent check of an answer.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .small_products import SmallProduct

__all__ = ["Presolved"]


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
    def free_columns(self) -> sp.csc_matrix:
        """Â_F, the free factors' columns, kept (`project_free` needs them per direction)."""
        return self.A[:, ~self.bounded]

    @cached_property
    def _free_rows(self) -> tuple[np.ndarray, sp.csr_matrix]:
        """The free factors' indices and their rows of Âᵀ."""
        free = np.flatnonzero(~self.bounded)
        return free, self.At[free]

    def free_residual(self, q: np.ndarray, z: np.ndarray) -> float:
        """max_j free |q_j + (Âᵀz)_j|: how far z is from cancelling the objective q on the free
        factors (0 without free factors)."""
        if not self.has_free:
            return 0.0
        free, AFt = self._free_rows
        return float(np.abs(q[free] + AFt @ z).max(initial=0.0))

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
        reduced = -Q - (self.products[1] @ lam.T).T
        free = self.has_free  # else the masks select every entry: the same sums, unmasked
        leak = np.abs(reduced[:, ~self.bounded]).max(axis=1, initial=0.0) if free else 0.0
        primal = -np.einsum("ij,ij->i", Q, eta)
        dual = lam @ self.b + np.abs(reduced[:, self.bounded] if free else reduced).sum(axis=1)
        scale = self.data_scale + np.abs(Q).sum(axis=1)
        residual = np.abs((self.products[0] @ eta.T).T - self.b).max(axis=1, initial=0.0)
        overshoot = (np.abs(eta[:, self.bounded] if free else eta) - 1.0).max(axis=1, initial=0.0)
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
