"""What the OIT filters need from the observability analysis, read from `setsmooth.analysis`.

`Structure` collects, for one time-invariant (A, C), the pieces Algorithms 2 and 3 use: the orthogonal
P of the observability decomposition (17) (x̃ = Px = [x_o; x_ō]), n_o, the blocks Ã_o, Ã_21, Ã_ō,
μ_o, the index n_λ0 of the eigenvalue 0 of Ã_o (Lemma 1's k_* = max{μ_o − 1 + n_λ0, 1}) and Υ∞
(Algorithm 3 Line 1). The decomposition and Υ∞ come from `setsmooth.analysis`; the index of the
zero eigenvalue is computed here (a rank sequence).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tolerances as tol

__all__ = ["Structure", "structure"]


@dataclass(frozen=True)
class Structure:
    P: np.ndarray
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
        decomposition = _decompose(A, C)
    dec = decomposition
    n_o = int(dec.n_o)
    P = np.asarray(dec.P, dtype=float)
    A_o = np.asarray(dec.A_o, dtype=float).reshape(n_o, n_o)
    C_o = np.asarray(dec.C_o, dtype=float).reshape(C.shape[0], n_o)
    A_21 = np.asarray(dec.A_21, dtype=float).reshape(A.shape[0] - n_o, n_o)
    A_obar = np.asarray(dec.A_obar, dtype=float).reshape(A.shape[0] - n_o, A.shape[0] - n_o)
    mu_o = observability_index(A_o, C_o) if n_o else 0
    return Structure(P, n_o, A_o, A_21, A_obar, C_o, mu_o, zero_eigenvalue_index(A_o))


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


def _decompose(A: np.ndarray, C: np.ndarray):
    try:
        from ..analysis import observability_decomposition
    except ImportError:  # pragma: no cover  (before the analysis package is merged)
        return _svd_decomposition(A, C)
    return observability_decomposition(A, C)


def observability_index(A: np.ndarray, C: np.ndarray) -> int:
    """μ: the smallest j with rank [C; CA; …; CA^{j−1}] = n (observable (A, C))."""
    n = A.shape[0]
    rows, block = [], np.asarray(C, dtype=float)
    for j in range(1, n + 1):
        rows.append(block)
        O = np.vstack(rows)
        if np.linalg.matrix_rank(O, tol=tol.RANK_TOL * max(1.0, np.abs(O).max()) * O.shape[0]) == n:
            return j
        block = block @ A
    raise ValueError("(A_o, C_o) is not observable")


@dataclass(frozen=True)
class _Decomposition:
    P: np.ndarray
    n_o: int
    A_o: np.ndarray
    A_21: np.ndarray
    A_obar: np.ndarray
    C_o: np.ndarray


def _svd_decomposition(A: np.ndarray, C: np.ndarray) -> _Decomposition:
    """Observability decomposition (17) from the SVD of the observability matrix (fallback)."""
    n = A.shape[0]
    blocks, block = [], np.asarray(C, dtype=float)
    for _ in range(n):
        blocks.append(block)
        block = block @ A
    O = np.vstack(blocks)
    _, s, Vt = np.linalg.svd(O)
    n_o = int(np.sum(s > tol.RANK_TOL * max(1.0, s[0] if s.size else 0.0) * O.shape[0]))
    P = Vt  # rows: observable directions first, then the kernel of O
    At = P @ A @ P.T
    return _Decomposition(P, n_o, At[:n_o, :n_o], At[n_o:, :n_o], At[n_o:, n_o:], (C @ P.T)[:, :n_o])


def upsilon_inf(A_obar: np.ndarray) -> float:
    """Υ∞ of Algorithm 3 Line 1, from `setsmooth.analysis.upsilon_inf` (a grid search over γ here
    until that is merged: γ = ρ + jh, h = (1 − ρ)/1001, max over k ≤ 1000 of ‖(A_ō/γ)^k‖∞)."""
    try:
        from ..analysis import upsilon_inf as analysis_upsilon
    except ImportError:  # pragma: no cover
        return _grid_upsilon(A_obar)
    return float(analysis_upsilon(A_obar))


def _grid_upsilon(A_obar: np.ndarray) -> float:
    n = A_obar.shape[0]
    if n == 0:
        return 0.0
    rho = float(max(abs(np.linalg.eigvals(A_obar))))
    if rho >= 1:
        raise ValueError(f"A_obar is not Schur stable (spectral radius {rho:.6g}): (A, C) is not detectable")
    h = (1 - rho) / 1001
    best = np.inf
    for gamma in rho + h * np.arange(1, 1001):
        M, power, worst = A_obar / gamma, np.eye(n), 1.0
        for _ in range(1000):
            power = power @ M
            norm = np.abs(power).sum(axis=1).max()
            worst = max(worst, norm)
            if norm < 1e-12:
                break
        best = min(best, worst / (1 - gamma))
    return float(best)
