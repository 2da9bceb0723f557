"""Reproducible random linear systems for the stability experiments (stability paper, Section 7).

python-control's ``drss`` draws from NumPy's global generator, so a run cannot be replayed from a
seed; MATLAB's ``drss`` (the authors') cannot be replayed in Python at all. These generators draw
everything from one explicit `numpy.random.Generator`:

- `random_observable_system`: a ``drss``-like stable system (poles in the closed unit disk, with an
  occasional integrator at z = 1 as ``drss`` produces), redrawn until (A, C) is observable (Fig. 4
  top, Table 1);
- `random_detectable_system`: the authors' construction of a detectable system with a chosen n_o
  (Fig. 4 bottom): (Ã_o, B̃_o, C̃_o) observable as above, Ã_ō = R/ρ(R)·s with R uniform on [0, 1]
  entries and s uniform on [0, s_max], Ã_21 and B̃_ō uniform on [0, 1] entries, and P the orthogonal
  factor of a QR of a uniform random matrix; A = P⁻¹[[Ã_o, 0], [Ã_21, Ã_ō]]P, B = P⁻¹[B̃_o; B̃_ō],
  C = [C̃_o 0]P.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import check_dim, check_rng, real_number
from .observability import ObservabilityDecomposition, observability_decomposition

__all__ = ["RandomSystem", "random_observable_system", "random_detectable_system", "random_stable_matrix"]

#: Probability that a drawn pole is an integrator at z = 1 (``drss`` places some poles there).
_UNIT_POLE_PROBABILITY = 0.05
#: Probability that a pole is the first of a complex-conjugate pair (when two slots remain).
_COMPLEX_PAIR_PROBABILITY = 0.4
#: Probability that an entry of B or C is kept (``drss`` masks some entries to zero).
_KEEP_ENTRY_PROBABILITY = 0.8
#: Redraws allowed before giving up on an observable draw (observability fails with probability ~0).
_MAX_TRIES = 1000


@dataclass(frozen=True, eq=False)   # arrays: identity equality, hashable
class RandomSystem:
    """A drawn system (A, B, C) with its observability decomposition (17).

    Attributes
    ----------
    A, B, C : ndarray
        n×n, n×p, m×n.
    decomposition : ObservabilityDecomposition
        For `random_detectable_system` the P it was built with; for `random_observable_system` the
        computed (orthogonal) one.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    decomposition: ObservabilityDecomposition

    def linear_system(self, W: Any = None, V: Any = None):
        """The `LinearSystem` x⁺ = Ax + Bw, y = Cx + v, with W = [−1, 1]^p, V = [−1, 1]^m by default."""
        from ..sets import Box
        from ..models.linear_system import LinearSystem
        p, m = self.B.shape[1], self.C.shape[0]
        W = Box(-np.ones(p), np.ones(p)) if W is None else W
        V = Box(-np.ones(m), np.ones(m)) if V is None else V
        return LinearSystem(self.A, None, self.C, E=self.B, W=W, V=V)


def _probability(value: Any, name: str) -> float:
    x = real_number(value, name)
    if not 0.0 <= x <= 1.0:
        raise ValueError(f"{name} must lie in [0, 1], got {x}")
    return x


def random_stable_matrix(rng: np.random.Generator, n: int, *,
                         unit_pole_probability: float = _UNIT_POLE_PROBABILITY) -> np.ndarray:
    """A random real n×n matrix with poles in the closed unit disk, ``drss``-style.

    Poles are drawn one slot at a time: an integrator at z = 1 with probability
    ``unit_pole_probability``; otherwise, while two slots remain, a complex pair r·e^{±iθ}
    (r ~ U[0, 1), θ ~ U(0, π)) with probability 0.4, else a real pole ~ U(−1, 1). The real block
    diagonal form is then mapped by a random similarity S = Q₁ diag(e^{u}) Q₂ (Q orthogonal,
    u ~ U[−1, 1]), so the matrix is not normal but cond(S) ≤ e².

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
    unit_pole_probability : float, default 0.05

    Returns
    -------
    ndarray, shape (n, n)
    """
    check_rng(rng)
    n = check_dim(n, "n")
    p_unit = _probability(unit_pole_probability, "unit_pole_probability")
    D = np.zeros((n, n))
    i = 0
    while i < n:
        if rng.random() < p_unit:
            D[i, i] = 1.0
            i += 1
        elif i + 1 < n and rng.random() < _COMPLEX_PAIR_PROBABILITY:
            r, theta = rng.random(), np.pi * rng.random()
            a, b = r * np.cos(theta), r * np.sin(theta)
            D[i:i + 2, i:i + 2] = [[a, b], [-b, a]]
            i += 2
        else:
            D[i, i] = rng.uniform(-1.0, 1.0)
            i += 1
    Q1 = np.linalg.qr(rng.standard_normal((n, n)))[0]
    Q2 = np.linalg.qr(rng.standard_normal((n, n)))[0]
    S = Q1 @ np.diag(np.exp(rng.uniform(-1.0, 1.0, n))) @ Q2
    return S @ D @ np.linalg.inv(S)


def _masked_gaussian(rng: np.random.Generator, shape: tuple[int, int]) -> np.ndarray:
    M = rng.standard_normal(shape) * (rng.random(shape) < _KEEP_ENTRY_PROBABILITY)
    return M


def random_observable_system(rng: np.random.Generator, n: int, p: int, m: int, *,
                             unit_pole_probability: float = _UNIT_POLE_PROBABILITY) -> RandomSystem:
    """A random stable (A, B, C) with (A, C) observable, redrawn until it is (stability Fig. 4, Table 1).

    Parameters
    ----------
    rng : numpy.random.Generator
        The only source of randomness.
    n : int
        State dimension.
    p : int
        Process-noise dimension (B is n×p).
    m : int
        Measurement dimension (C is m×n).
    unit_pole_probability : float, default 0.05
        See `random_stable_matrix`.

    Returns
    -------
    RandomSystem

    Raises
    ------
    TypeError
        When ``rng`` is not a Generator or a dimension not an integer.
    RuntimeError
        When 1000 draws in a row are unobservable (C masked to almost nothing; not seen in practice).

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth import analysis
    >>> sys1 = analysis.random_observable_system(np.random.default_rng(1), 4, 2, 1)
    >>> sys2 = analysis.random_observable_system(np.random.default_rng(1), 4, 2, 1)
    >>> bool(np.array_equal(sys1.A, sys2.A)), sys1.decomposition.n_o
    (True, 4)
    """
    check_rng(rng)
    n, p, m = check_dim(n, "n"), check_dim(p, "p"), check_dim(m, "m")
    for _ in range(_MAX_TRIES):
        A = random_stable_matrix(rng, n, unit_pole_probability=unit_pole_probability)
        B = _masked_gaussian(rng, (n, p))
        C = _masked_gaussian(rng, (m, n))
        dec = observability_decomposition(A, C, B=B)
        if dec.is_observable:
            return RandomSystem(A=dec.A, B=dec.B, C=dec.C, decomposition=dec)
    raise RuntimeError(f"no observable draw in {_MAX_TRIES} tries (n = {n}, m = {m})")


def random_detectable_system(rng: np.random.Generator, n: int, n_o: int, p: int, m: int, *,
                             s_max: float = 0.5,
                             unit_pole_probability: float = _UNIT_POLE_PROBABILITY) -> RandomSystem:
    """A random detectable, unobservable (A, B, C) with observable dimension ``n_o`` (stability Fig. 4).

    The authors' construction (see the module docstring): ρ(Ã_ō) = s ~ U[0, s_max] < 1, so (A, C) is
    detectable, and (Ã_o, C̃_o) is observable, so the observable dimension is exactly n_o.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        State dimension.
    n_o : int
        Observable dimension, 1 ≤ n_o < n.
    p, m : int
        Noise and measurement dimensions.
    s_max : float, default 0.5
        Largest spectral radius of Ã_ō; must lie in [0, 1).
    unit_pole_probability : float, default 0.05
        For the observable block, see `random_stable_matrix`.

    Returns
    -------
    RandomSystem
        Its ``decomposition`` is built from the P used, and validated against (A, C).

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth import analysis
    >>> s = analysis.random_detectable_system(np.random.default_rng(0), 5, 3, 3, 3)
    >>> s.decomposition.n_o, s.decomposition.is_detectable, analysis.observability_decomposition(s.A, s.C).n_o
    (3, True, 3)
    """
    check_rng(rng)
    n, n_o, p, m = check_dim(n, "n"), check_dim(n_o, "n_o"), check_dim(p, "p"), check_dim(m, "m")
    if n_o >= n:
        raise ValueError(f"n_o must be smaller than n = {n} (use random_observable_system), got {n_o}")
    s_max = real_number(s_max, "s_max")
    if not 0.0 <= s_max < 1.0:
        raise ValueError(f"s_max must lie in [0, 1) for a detectable system, got {s_max}")
    observable = random_observable_system(rng, n_o, p, m, unit_pole_probability=unit_pole_probability)
    A_o, B_o, C_o = observable.A, observable.B, observable.C
    n_obar = n - n_o
    R = rng.random((n_obar, n_obar))
    rho = float(np.max(np.abs(np.linalg.eigvals(R))))
    A_obar = R / rho * rng.uniform(0.0, s_max) if rho > 0 else np.zeros_like(R)
    A_21 = rng.random((n_obar, n_o))
    B_obar = rng.random((n_obar, p))
    P = np.linalg.qr(rng.random((n, n)))[0]
    A_tilde = np.block([[A_o, np.zeros((n_o, n_obar))], [A_21, A_obar]])
    # P is orthogonal, so P⁻¹ = Pᵀ exactly in exact arithmetic; use it to avoid an inverse.
    A = P.T @ A_tilde @ P
    B = P.T @ np.vstack([B_o, B_obar])
    C = np.hstack([C_o, np.zeros((m, n_obar))]) @ P
    dec = observability_decomposition(A, C, B=B, P=P, n_o=n_o)
    return RandomSystem(A=A, B=B, C=C, decomposition=dec)
