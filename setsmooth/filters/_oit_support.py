"""What the OIT filters need from the observability analysis, read from `setsmooth.analysis`.

`Structure` collects, for one time-invariant (A, C), the pieces Algorithms 2 and 3 use: the orthogonal
P of the observability decomposition (17) and U = P⁻¹ (x̃ = Px = [x_o; x_ō]), n_o, the blocks Ã_o, Ã_21, Ã_ō,
μ_o, the index n_λ0 of the eigenvalue 0 of Ã_o (Lemma 1's k_* = max{μ_o − 1 + n_λ0, 1}) and Υ∞
(Algorithm 3 Line 1). The decomposition and Υ∞ come from `setsmooth.analysis`; the index of the zero
eigenvalue is computed here (a rank sequence).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tolerances as tol
from ..analysis import (ObservabilityDecomposition, observability_decomposition,
                        upsilon_inf as analysis_upsilon)

__all__ = ["Structure", "structure"]


@dataclass(frozen=True)
class Structure:
    P: np.ndarray
    U: np.ndarray
    n_o: int
    A_o: np.ndarray
    A_21: np.ndarray
    A_obar: np.ndarray
    C_o: np.ndarray
    mu_o: int
    n_lambda0: int

    @property
    def observable(self) -> bool:
        return self.n_o == self.P.shape[0]

    @property
    def P_o(self) -> np.ndarray:
        return self.P[:self.n_o]

    @property
    def P_obar(self) -> np.ndarray:
        return self.P[self.n_o:]

    @property
    def k_star(self) -> int:
        """k_* = max{μ_o − 1 + n_λ0, 1} of Lemma 1."""
        return max(self.mu_o - 1 + self.n_lambda0, 1)


def structure(A: np.ndarray, C: np.ndarray, decomposition=None) -> Structure:
    """The `Structure` of (A, C), from ``decomposition`` when given (an `analysis` decomposition)."""
    if decomposition is None:
        decomposition = observability_decomposition(A, C)
    elif not isinstance(decomposition, ObservabilityDecomposition):
        raise TypeError("decomposition must be an ObservabilityDecomposition "
                        f"(setsmooth.analysis.observability_decomposition), got {type(decomposition).__name__}")
    elif not (np.array_equal(decomposition.A, A) and np.array_equal(decomposition.C, C)):
        raise ValueError("decomposition belongs to another (A, C) than the system's")
    dec = decomposition
    A_o = np.asarray(dec.A_o, dtype=float)
    return Structure(np.asarray(dec.P, dtype=float), np.asarray(dec.U, dtype=float), int(dec.n_o), A_o,
                     np.asarray(dec.A_21, dtype=float), np.asarray(dec.A_obar, dtype=float),
                     np.asarray(dec.C_o, dtype=float), int(dec.mu_o), zero_eigenvalue_index(A_o))


def zero_eigenvalue_index(M: np.ndarray) -> int:
    """The index of the eigenvalue 0 of M (size of its largest Jordan block; 0 if M is invertible):
    the smallest j with rank(M^j) = rank(M^{j+1})."""
    n = M.shape[0]
    if n == 0:
        return 0
    scale = max(1.0, float(np.abs(M).max()))
    power, rank = np.eye(n), n
    for j in range(n + 1):
        nxt = M @ power
        r = int(np.linalg.matrix_rank(nxt, tol=tol.RANK_TOL * scale ** (j + 1) * n))
        if r == rank:
            return j
        power, rank = nxt, r
    return n


def upsilon_inf(A_obar: np.ndarray) -> float:
    """Υ∞ of Algorithm 3 Line 1 (`setsmooth.analysis.upsilon_inf`)."""
    return float(analysis_upsilon(A_obar))
