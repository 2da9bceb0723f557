"""Constants of the stability paper: the OIT diameter bound (16) and Υ∞ of Algorithm 3, Line 1.

Both are upper bounds used by the filters and drawn in the figures; each is computed so that the
returned number is an attained value of the expression being minimized (a valid bound), never an
extrapolated limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_matrix, real_number
from ..tolerances import RANK_TOL, UPSILON_GAMMA_TOL
from .observability import observability_decomposition, spectral_radius

__all__ = ["oit_diameter_bound", "OITBound", "minimize_oit_diameter_bound", "Upsilon", "upsilon_inf",
           "upsilon_search", "noise_diameter"]


def noise_diameter(S: Any, name: str) -> float:
    """2-norm diameter used for d_w, d_v in (16): a number as given, or that of a set's interval hull.

    The interval hull's diagonal ‖hi − lo‖₂ is the exact 2-norm diameter of a box (d = 2√p for
    [−1, 1]^p) and an upper bound for any other set, so (16) stays a valid bound.
    """
    from ..sets import ConvexSet
    if isinstance(S, ConvexSet):
        hull = S.interval_hull()
        if hull.is_empty():
            raise ValueError(f"{name} is empty")
        return float(np.linalg.norm(hull.hi - hull.lo))
    d = real_number(S, name)
    if not (d >= 0 and math.isfinite(d)):
        raise ValueError(f"{name} must be a ConvexSet or a finite non-negative diameter, got {d}")
    return d


def _check_abc(A: Any, B: Any, C: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    A = as_matrix(A, "A")
    n = A.shape[0]
    if A.shape != (n, n):
        raise ValueError(f"A must be square, got shape {A.shape}")
    return A, as_matrix(B, "B", rows=n), as_matrix(C, "C", cols=n)


def _bound(A: np.ndarray, B: np.ndarray, C: np.ndarray, d_w: float, d_v: float, delta: int,
           A_inv: np.ndarray) -> float:
    # O_δ = [C A^{−δ}; …; C A^{−1}; C] and the terms ‖C A^{−l} B‖ of (16), l = 1..δ.
    powers = [np.eye(A.shape[0])]
    for _ in range(delta):
        powers.append(powers[-1] @ A_inv)
    O = np.vstack([C @ powers[delta - j] for j in range(delta + 1)])
    s_min = np.linalg.svd(O, compute_uv=False)[-1] if O.shape[0] >= O.shape[1] else 0.0
    if s_min <= RANK_TOL * max(1.0, np.linalg.norm(O, 2)):
        return math.inf
    gains = [np.linalg.norm(C @ powers[l] @ B, 2) for l in range(delta + 1)]
    terms = [d_v + d_w * sum(gains[1:delta - j + 1]) for j in range(delta + 1)]
    return float(math.sqrt(sum(t * t for t in terms)) / s_min)


def oit_diameter_bound(A: Any, B: Any, C: Any, W: Any, V: Any, delta: int) -> float:
    """d̄_δ(A, B, C) of stability paper (16): an upper bound on the 2-norm diameter of the OIT.

    d(∩_{i=k−δ}^{k} O_{k,i}) ≤ sqrt(Σ_{j=0}^{δ} [d_v + Σ_{l=1}^{δ−j} ‖C A^{−l} B‖ d_w]²) / σ_min(O_δ),
    O_δ = [C A^{−δ}; …; C A^{−1}; C], for every k ≥ δ ≥ μ − 1 (Theorem 1).

    Parameters
    ----------
    A, B, C : array_like
        n×n (nonsingular), n×p, m×n with (A, C) observable.
    W, V : ConvexSet or float
        The noise ranges or their 2-norm diameters d_w, d_v (see `noise_diameter`).
    delta : int
        δ ≥ μ − 1.

    Returns
    -------
    float
        d̄_δ; ``inf`` when O_δ is rank deficient (δ < μ − 1 cannot happen: it raises).

    Raises
    ------
    ValueError
        When A is singular, (A, C) is not observable, or δ < μ − 1.

    Examples
    --------
    >>> from setsmooth import analysis
    >>> round(analysis.oit_diameter_bound([[1, 1], [0, 1]], [[0.5], [1]], [[1, 0]], 2.0, 2.0, 1), 4)
    5.8339
    """
    A, B, C = _check_abc(A, B, C)
    if isinstance(delta, bool) or not isinstance(delta, (int, np.integer)) or delta < 0:
        raise ValueError(f"delta must be a non-negative integer, got {delta!r}")
    dec = observability_decomposition(A, C)
    if not dec.is_observable:
        raise ValueError("(A, C) must be observable for the OIT bound (16) (Theorem 1)")
    if delta < dec.mu_o - 1:
        raise ValueError(f"delta must be at least mu - 1 = {dec.mu_o - 1}, got {delta}")
    s = np.linalg.svd(A, compute_uv=False)
    if s[-1] <= RANK_TOL * s[0] * A.shape[0]:
        raise ValueError("A must be nonsingular for the OIT bound (16) (Theorem 1)")
    d_w, d_v = noise_diameter(W, "W"), noise_diameter(V, "V")
    return _bound(A, B, C, d_w, d_v, int(delta), np.linalg.inv(A))


@dataclass(frozen=True)
class OITBound:
    """The best d̄_δ of (16) over δ ∈ [μ − 1, delta_max]: ``value`` attained at ``delta``."""

    delta: int
    value: float
    values: tuple[float, ...]   # d̄_δ for δ = μ − 1, …, delta_max


def minimize_oit_diameter_bound(A: Any, B: Any, C: Any, W: Any, V: Any, *,
                                delta_max: int | None = None) -> OITBound:
    """min_δ d̄_δ(A, B, C) of (16) over δ = μ − 1, …, ``delta_max`` (the horizontal line of Fig. 2).

    The minimum over all δ ≥ μ − 1 need not be attained (for a stable A both numerator and σ_min(O_δ)
    grow like ‖A^{−δ}‖), so the search is over a finite range; every returned value is a valid bound.

    Parameters
    ----------
    A, B, C, W, V
        As `oit_diameter_bound`.
    delta_max : int, optional
        Largest δ tried; default μ − 1 + 2n.

    Returns
    -------
    OITBound

    Examples
    --------
    >>> from setsmooth import analysis
    >>> best = analysis.minimize_oit_diameter_bound([[1, 1], [0, 1]], [[0.5], [1]], [[1, 0]], 2.0, 2.0)
    >>> best.delta, round(best.value, 4)
    (1, 5.8339)
    """
    A, B, C = _check_abc(A, B, C)
    dec = observability_decomposition(A, C)
    lo = max(dec.mu_o - 1, 0)
    hi = lo + 2 * A.shape[0] if delta_max is None else int(delta_max)
    if hi < lo:
        raise ValueError(f"delta_max must be at least mu - 1 = {lo}, got {hi}")
    first = oit_diameter_bound(A, B, C, W, V, lo)          # validates everything once
    d_w, d_v = noise_diameter(W, "W"), noise_diameter(V, "V")
    A_inv = np.linalg.inv(A)
    values = [first] + [_bound(A, B, C, d_w, d_v, d, A_inv) for d in range(lo + 1, hi + 1)]
    best = int(np.argmin(values))
    return OITBound(delta=lo + best, value=float(values[best]), values=tuple(float(v) for v in values))


# -- Υ∞ ---------------------------------------------------------------------------------------------

#: Powers tried for one γ before that γ is declared too close to ρ(Ã_ō) (its β_γ is then +inf).
_MAX_POWERS = 100_000


def _beta(M: np.ndarray) -> tuple[float, int]:
    """β = max_{k ≥ 0} ‖M^k‖∞ for ρ(M) < 1, exactly, and the k where the search could stop.

    Once ‖M^K‖∞ ≤ 1 for some K ≥ 1, every later power M^{qK+r} = (M^K)^q M^r has norm ≤ ‖M^r‖∞ with
    r < K, so the maximum over k < K is the maximum over all k (footnote 17: finitely many steps).
    """
    P = np.eye(M.shape[0])
    best = 1.0
    for K in range(1, _MAX_POWERS + 1):
        P = P @ M
        norm = float(np.abs(P).sum(axis=1).max())
        if norm <= 1.0:
            return best, K
        best = max(best, norm)
    return math.inf, _MAX_POWERS


@dataclass(frozen=True)
class Upsilon:
    """Υ∞ = β_γ/(1 − γ) at the γ found, with β_γ = max_k γ^{−k}‖Ã_ō^k‖∞ attained up to ``k_stop``."""

    value: float
    gamma: float
    beta: float
    k_stop: int


def upsilon_search(A_obar: Any) -> Upsilon:
    """Υ∞ of Algorithm 3, Line 1: inf over γ ∈ (ρ(Ã_ō), 1) of max_k γ^{−k}‖Ã_ō^k‖∞ / (1 − γ).

    Each g_k(γ) = γ^{−k}‖Ã_ō^k‖∞/(1 − γ) is log-convex in γ (−k log γ and −log(1 − γ) are convex),
    so their maximum f(γ) is log-convex, hence unimodal on (ρ, 1): a golden-section search on log f
    finds the infimum; β_γ is computed exactly for each γ tried (see `_beta`). The returned value is
    f at the γ found — an attained value, so Σ_{j ≥ 0}‖Ã_ō^j‖∞ ≤ Υ∞ holds for it (Lemma 4); when the
    infimum is a limit at γ → ρ (e.g. Ã_ō = 0.5 gives the limit 2) the value lies just above it.

    Parameters
    ----------
    A_obar : array_like, shape (n_ō, n_ō)
        Ã_ō with ρ(Ã_ō) < 1 (a detectable system). An empty matrix gives Υ∞ = 0.

    Returns
    -------
    Upsilon

    Raises
    ------
    ValueError
        When ρ(Ã_ō) ≥ 1.

    Examples
    --------
    >>> from setsmooth import analysis
    >>> round(analysis.upsilon_inf([[0.5]]), 4)    # the authors' grid gives 2.002
    2.0
    """
    M = as_matrix(A_obar, "A_obar") if np.size(A_obar) else np.zeros((0, 0))
    if M.shape[0] != M.shape[1]:
        raise ValueError(f"A_obar must be square, got shape {M.shape}")
    if M.size == 0:
        return Upsilon(value=0.0, gamma=0.0, beta=0.0, k_stop=0)
    rho = spectral_radius(M)
    if rho >= 1.0:
        raise ValueError(f"A_obar must have spectral radius < 1 (a detectable system), got {rho}")

    def log_f(gamma: float) -> tuple[float, float, int]:
        beta, k = _beta(M / gamma)
        return math.log(beta) - math.log1p(-gamma), beta, k

    # Golden section on (ρ, 1); the ends are never evaluated (β blows up at ρ for a defective or
    # non-normal Ã_ō, and 1/(1 − γ) at 1).
    a, b = rho, 1.0
    r = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = b - r * (b - a), a + r * (b - a)
    f1, f2 = log_f(x1)[0], log_f(x2)[0]
    while b - a > UPSILON_GAMMA_TOL * max(1.0 - rho, 1e-300):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - r * (b - a)
            f1 = log_f(x1)[0]
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + r * (b - a)
            f2 = log_f(x2)[0]
    gamma = x1 if f1 <= f2 else x2
    _, beta, k = log_f(gamma)
    return Upsilon(value=beta / (1.0 - gamma), gamma=gamma, beta=beta, k_stop=k)


def upsilon_inf(A_obar: Any) -> float:
    """Υ∞ of Algorithm 3, Line 1 (see `upsilon_search`, which also returns the γ attaining it)."""
    return upsilon_search(A_obar).value
