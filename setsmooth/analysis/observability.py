"""The observability decomposition (stability paper (17)) and the spectral tests built on it.

x̃ = P x = [x̃_o; x̃_ō] splits the state into an observable part, driven by itself and seen by the
output, and an unobservable part driven by both:

    x̃^o_{k+1} = Ã_o x̃^o_k + B̃_o w_k,   x̃^ō_{k+1} = Ã_21 x̃^o_k + Ã_ō x̃^ō_k + B̃_ō w_k,   y_k = C̃_o x̃^o_k + v_k.

It is computed by the orthogonal staircase algorithm (the dual of the controllability staircase of
Rosenbrock / Van Dooren): each step takes the SVD of the part of the output map not yet accounted for,
so P is orthogonal and no power of A is ever formed. Forming the observability matrix
[C; CA; …; CA^{n−1}] instead loses the rank decision as soon as A has eigenvalues far from 1 (A^{n−1}
swamps the small singular values); the staircase keeps every rank decision at the scale of ‖[A; C]‖.
The number of staircase steps is the observability index μ_o of (Ã_o, C̃_o).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validation import as_matrix
from ..tolerances import RANK_TOL, SPECTRAL_CLUSTER_TOL, SPECTRAL_TOL

__all__ = ["ObservabilityDecomposition", "observability_decomposition", "observability_index",
           "is_observable", "is_detectable", "is_marginally_stable", "spectral_radius"]


def _frozen(M: np.ndarray) -> np.ndarray:
    M = np.array(M, dtype=float)
    M.setflags(write=False)
    return M


@dataclass(frozen=True, eq=False)   # arrays: identity equality, hashable
class ObservabilityDecomposition:
    """x̃ = P x = [x̃_o; x̃_ō] with the blocks of stability paper (17).

    Build it with `observability_decomposition` (from (A, C), or from a given P). ``P`` is orthogonal
    when computed here; a user-given P need only be nonsingular, and ``U`` = P⁻¹ is then its inverse.

    Attributes
    ----------
    A, C : ndarray
        The system's matrices (n×n, m×n).
    P : ndarray, shape (n, n)
        The equivalence transformation; rows ``P_o`` = P[:n_o] span the observable coordinates.
    U : ndarray, shape (n, n)
        P⁻¹ = [U_o U_ō].
    n_o : int
        Dimension of the observable subsystem.
    mu_o : int
        Observability index of (Ã_o, C̃_o): the least μ with rank [C̃_o; …; C̃_o Ã_o^{μ−1}] = n_o
        (0 when n_o = 0).
    B : ndarray or None
        The noise matrix, when given; then ``B_o``, ``B_obar`` are its blocks.
    """

    A: np.ndarray
    C: np.ndarray
    P: np.ndarray
    n_o: int
    mu_o: int
    B: np.ndarray | None = None
    U: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("A", "C", "P"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        if self.B is not None:
            object.__setattr__(self, "B", _frozen(self.B))
        object.__setattr__(self, "U", _frozen(np.linalg.inv(self.P)))

    # -- dimensions and the row/column blocks of P and U (footnote 12) ------------------------------
    @property
    def n(self) -> int:
        """State dimension n."""
        return self.A.shape[0]

    @property
    def n_obar(self) -> int:
        """Dimension n_ō = n − n_o of the unobservable subsystem."""
        return self.n - self.n_o

    @property
    def P_o(self) -> np.ndarray:
        """P_o (n_o×n): x̃^o = P_o x."""
        return self.P[: self.n_o]

    @property
    def P_obar(self) -> np.ndarray:
        """P_ō (n_ō×n): x̃^ō = P_ō x."""
        return self.P[self.n_o:]

    @property
    def U_o(self) -> np.ndarray:
        """U_o (n×n_o), the first block column of P⁻¹."""
        return self.U[:, : self.n_o]

    @property
    def U_obar(self) -> np.ndarray:
        """U_ō (n×n_ō), whose columns span the unobservable subspace."""
        return self.U[:, self.n_o:]

    # -- the blocks of (17) ---------------------------------------------------------------------
    @property
    def A_tilde(self) -> np.ndarray:
        """P A P⁻¹, block lower triangular [[Ã_o, 0], [Ã_21, Ã_ō]] up to rounding."""
        return self.P @ self.A @ self.U

    @property
    def A_o(self) -> np.ndarray:
        """Ã_o = P_o A U_o."""
        return self.P_o @ self.A @ self.U_o

    @property
    def A_21(self) -> np.ndarray:
        """Ã_21 = P_ō A U_o."""
        return self.P_obar @ self.A @ self.U_o

    @property
    def A_obar(self) -> np.ndarray:
        """Ã_ō = P_ō A U_ō; its eigenvalues depend on (A, C) only, not on P."""
        return self.P_obar @ self.A @ self.U_obar

    @property
    def C_o(self) -> np.ndarray:
        """C̃_o = C U_o."""
        return self.C @ self.U_o

    @property
    def B_o(self) -> np.ndarray | None:
        """B̃_o = P_o B (None when the decomposition was built without B)."""
        return None if self.B is None else self.P_o @ self.B

    @property
    def B_obar(self) -> np.ndarray | None:
        """B̃_ō = P_ō B (None when the decomposition was built without B)."""
        return None if self.B is None else self.P_obar @ self.B

    def split_input(self, B: Any) -> tuple[np.ndarray, np.ndarray]:
        """Return (B̃_o, B̃_ō) = (P_o B, P_ō B) for any matrix B with n rows (noise or known input).

        Raises
        ------
        ValueError
            When ``B`` does not have n rows.
        """
        B = as_matrix(B, "B", rows=self.n)
        return self.P_o @ B, self.P_obar @ B

    # -- verdicts -------------------------------------------------------------------------------
    @property
    def is_observable(self) -> bool:
        """(A, C) observable: n_o = n."""
        return self.n_o == self.n

    @property
    def is_detectable(self) -> bool:
        """(A, C) detectable: ρ(Ã_ō) < 1 (stability paper, below (17))."""
        return self.n_obar == 0 or spectral_radius(self.A_obar) < 1.0 - SPECTRAL_TOL

    def to_tilde(self, x: Any) -> np.ndarray:
        """x̃ = P x (x may be a vector or a matrix of column vectors)."""
        return self.P @ np.asarray(x, dtype=float)

    def from_tilde(self, x_tilde: Any) -> np.ndarray:
        """x = P⁻¹ x̃."""
        return self.U @ np.asarray(x_tilde, dtype=float)


def _rank_tol(*Ms: np.ndarray) -> float:
    scale = max([1.0] + [float(np.linalg.norm(M, 2)) for M in Ms if M.size])
    return RANK_TOL * scale * max(M.shape[0] + M.shape[1] for M in Ms)


def _staircase(A: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, int, int]:
    """Orthogonal Q (n×n) whose first n_o columns span the observable subspace (row space of the
    observability matrix), with n_o and the number of staircase steps μ_o.

    The controllability staircase of (Aᵀ, Cᵀ): at each step the SVD of the block that the previous
    step's coordinates feed into splits the remaining coordinates into newly reached and not yet
    reached ones; the reached subspace after all steps is the controllable subspace of (Aᵀ, Cᵀ).
    """
    n = A.shape[0]
    tol = _rank_tol(A, C)
    At = A.T.copy()
    Q = np.eye(n)
    feed = C.T.copy()           # n_rest × m: what the reached coordinates drive in the rest
    start, steps = 0, 0
    while start < n and feed.size:
        U, s, _ = np.linalg.svd(feed, full_matrices=True)
        r = int(np.sum(s > tol))
        if r == 0:
            break
        # Rotate the remaining coordinates start: by U, then read off the next feed block.
        T = np.eye(n)
        T[start:, start:] = U
        At = T.T @ At @ T
        Q = Q @ T
        feed = At[start + r:, start:start + r]
        start += r
        steps += 1
    return Q, start, steps


def observability_decomposition(A: Any, C: Any, *, B: Any = None, P: Any = None,
                                n_o: int | None = None) -> ObservabilityDecomposition:
    """The observability decomposition x̃ = P x of stability paper (17).

    Parameters
    ----------
    A : array_like, shape (n, n)
    C : array_like, shape (m, n)
    B : array_like, shape (n, p), optional
        The noise matrix; when given, the result carries B̃_o and B̃_ō.
    P : array_like, shape (n, n), optional
        A given nonsingular transformation whose first ``n_o`` rows span the observable coordinates
        (for example MATLAB's ``obsvf`` reordered). When omitted, an orthogonal P is computed by the
        staircase algorithm.
    n_o : int, optional
        Observable dimension belonging to a given ``P`` (default: the computed one).

    Returns
    -------
    ObservabilityDecomposition

    Raises
    ------
    ValueError
        When shapes disagree, a given ``P`` is singular, or it is not an observability decomposition
        of (A, C): Ã_12 = P_o A U_ō and C U_ō must vanish and n_o must equal rank of the
        observability matrix.

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth import analysis
    >>> dec = analysis.observability_decomposition([[0.5, 1.0], [0.0, 1.0]], [[0.0, 1.0]])
    >>> dec.n_o, dec.mu_o, np.round(np.abs(dec.A_obar), 12).tolist()
    (1, 1, [[0.5]])
    """
    A = as_matrix(A, "A")
    n = A.shape[0]
    if A.shape != (n, n):
        raise ValueError(f"A must be square, got shape {A.shape}")
    C = as_matrix(C, "C", cols=n)
    Bm = None if B is None else as_matrix(B, "B", rows=n)
    Q, n_found, mu_o = _staircase(A, C)
    if P is None:
        if n_o is not None:
            raise ValueError("n_o is only meaningful with a given P; it is computed otherwise")
        return ObservabilityDecomposition(A=A, C=C, P=Q.T, n_o=n_found, mu_o=mu_o, B=Bm)
    P = as_matrix(P, "P", rows=n, cols=n)
    n_o = n_found if n_o is None else int(n_o)
    if n_o != n_found:
        raise ValueError(f"n_o = {n_o} disagrees with the rank {n_found} of the observability matrix "
                         "of (A, C)")
    sv = np.linalg.svd(P, compute_uv=False)
    if sv[-1] <= RANK_TOL * sv[0] * n:
        raise ValueError("P must be nonsingular (its condition number exceeds 1/RANK_TOL)")
    dec = ObservabilityDecomposition(A=A, C=C, P=P, n_o=n_o, mu_o=mu_o, B=Bm)
    A12 = dec.P_o @ A @ dec.U_obar
    C_obar = C @ dec.U_obar
    tol = _rank_tol(A, C) * float(np.linalg.cond(P))
    if (A12.size and np.abs(A12).max() > tol) or (C_obar.size and np.abs(C_obar).max() > tol):
        raise ValueError("P is not an observability decomposition of (A, C): P_o A U_ō and C U_ō "
                         "must vanish (the last n − n_o columns of P⁻¹ must span the unobservable "
                         "subspace)")
    return dec


def observability_index(A: Any, C: Any) -> int:
    """Observability index μ_o of the observable part of (A, C) (μ when (A, C) is observable).

    The least μ such that [C; CA; …; CA^{μ−1}] has the rank of the full observability matrix
    (stability paper, Theorem 1 and (17); Chen, Linear System Theory and Design, §6.3.1).

    Examples
    --------
    >>> from setsmooth import analysis
    >>> analysis.observability_index([[1.0, 1.0], [0.0, 1.0]], [[1.0, 0.0]])
    2
    """
    A = as_matrix(A, "A")
    C = as_matrix(C, "C", cols=A.shape[1])
    if A.shape[0] != A.shape[1]:
        raise ValueError(f"A must be square, got shape {A.shape}")
    return _staircase(A, C)[2]


def is_observable(A: Any, C: Any) -> bool:
    """Whether (A, C) is observable (rank of the observability matrix = n, by the staircase)."""
    return observability_decomposition(A, C).is_observable


def is_detectable(A: Any, C: Any) -> bool:
    """Whether (A, C) is detectable: ρ(Ã_ō) < 1 for the decomposition (17).

    Examples
    --------
    >>> from setsmooth import analysis
    >>> analysis.is_detectable([[0.5, 1.0], [0.0, 1.0]], [[0.0, 1.0]])
    True
    >>> analysis.is_detectable([[1.0, 0.0], [0.0, 0.5]], [[0.0, 1.0]])
    False
    """
    return observability_decomposition(A, C).is_detectable


def spectral_radius(M: Any) -> float:
    """ρ(M), the largest eigenvalue modulus (0 for an empty matrix)."""
    M = np.asarray(M, dtype=float)
    return float(np.max(np.abs(np.linalg.eigvals(M)))) if M.size else 0.0


def is_marginally_stable(M: Any) -> bool:
    """Whether x_{k+1} = M x_k is marginally stable: every |λ| ≤ 1, those with |λ| = 1 non-defective.

    Footnote 13 of the stability paper. Equivalently sup_k ‖M^k‖ < ∞. An eigenvalue counts as on the
    unit circle within ``SPECTRAL_CLUSTER_TOL``; such a cluster of r eigenvalues (a defective
    eigenvalue of multiplicity r splits by about eps^{1/r} in floating point) is non-defective when
    dim ker(M − λI) = r, with λ the cluster's mean. Distinct eigenvalues closer than the cluster
    tolerance on the unit circle are therefore judged as one, conservatively.

    Examples
    --------
    >>> from setsmooth import analysis
    >>> analysis.is_marginally_stable([[1.0, 0.0], [0.0, -1.0]])
    True
    >>> analysis.is_marginally_stable([[1.0, 1.0], [0.0, 1.0]])
    False
    """
    M = as_matrix(M, "M")
    if M.shape[0] != M.shape[1]:
        raise ValueError(f"M must be square, got shape {M.shape}")
    if M.size == 0:
        return True
    lam = np.linalg.eigvals(M)
    mod = np.abs(lam)
    if np.any(mod > 1.0 + SPECTRAL_CLUSTER_TOL):
        return False
    on_circle = list(lam[mod > 1.0 - SPECTRAL_CLUSTER_TOL])
    n = M.shape[0]
    tol = _rank_tol(M)
    while on_circle:
        ref = on_circle[0]
        cluster = [z for z in on_circle if abs(z - ref) <= SPECTRAL_CLUSTER_TOL]
        on_circle = [z for z in on_circle if abs(z - ref) > SPECTRAL_CLUSTER_TOL]
        lam0 = np.mean(cluster)
        N = M.astype(complex) - lam0 * np.eye(n)
        # Non-defective: the geometric multiplicity (dim ker(M − λI)) equals the algebraic one.
        geo = int(np.sum(np.linalg.svd(N, compute_uv=False) <= tol))
        if geo < len(cluster):
            return False
    return True
