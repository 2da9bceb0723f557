"""Shared systems and checks for the estimator tests."""

from __future__ import annotations

import numpy as np

import setsmooth as ss
from setsmooth.papers.smoothing_examples import smoothing_example_31

example_31 = smoothing_example_31  # the one definition of (31), under the name the tests use


def singular_system() -> ss.LinearSystem:
    """Φ of rank 1: x2 is forgotten at every step, so ker(Φ) matters in the smoother (16)."""
    return ss.LinearSystem([[0.9, 0.5], [0.0, 0.0]], None, [[1.0, 1.0]], E=[[1.0], [0.5]],
                           W=ss.Box([-0.5], [0.5]), V=ss.Box([-1.0], [1.0]))


def time_varying_system() -> ss.LinearSystem:
    """Time-varying A_k, E_k, C_k (Φ_k, Γ_k, Ξ_k) given as callables, with a known input and a zonotopic W."""
    def A(k):
        a = 0.3 * np.sin(0.7 * k)
        return np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]]) * 0.95

    def C(k):
        return np.array([[1.0, 0.2 * np.cos(k)]])

    return ss.LinearSystem(A, np.eye(2), C, E=lambda k: np.eye(2) * (1.0 + 0.1 * (k % 2)), F=[[0.5]],
                           W=ss.Zonotope([[0.3, 0.1], [0.0, 0.2]], [0.05, 0.0]),
                           V=ss.Box([-1.0], [1.0]),
                           u=lambda k: np.array([0.1 * k, -0.05]))


DIRECTIONS_2D = np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 24, endpoint=False) + 0.1),
                                 np.sin(np.linspace(0, 2 * np.pi, 24, endpoint=False) + 0.1)])


def contains_by_support(S: ss.ConvexSet, x: np.ndarray, directions: np.ndarray, margin: float = 1e-7) -> bool:
    """x ∈ S tested as dᵀx ≤ h_S(d) + margin along every direction (certified supports)."""
    values = S.support_many(directions, certified=True)
    return bool(np.all(directions @ x <= values + margin * (1 + np.abs(x).max())))
