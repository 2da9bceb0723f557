"""A nonlinear system with bounded noises: `NonlinearSystem` (smoothing paper (4)–(5))."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .._validation import as_vector, check_dim, given_instead_of_set
from ..sets.base import ConvexSet


class NonlinearSystem:
    """x_{k+1} = f(k, x_k, w_k),  y_k = g(k, x_k, v_k), with w_k ∈ W, v_k ∈ V.

    Parameters
    ----------
    f, g : callable
        Transition and measurement functions of (k, x, noise), acting on 1-D arrays.
    W, V : ConvexSet
        Noise ranges.
    n : int
        State dimension.

    Raises
    ------
    TypeError
        When f or g is not callable, W or V is not a `ConvexSet`, or n is not an integer.
    ValueError
        When n < 1. `step` and `measure` raise naming ``f(k, x, w)``/``g(k, x, v)`` when a value is
        complex (TypeError), NaN/inf or of the wrong length (ValueError).
    """

    def __init__(self, f: Callable, g: Callable, W: ConvexSet, V: ConvexSet, n: int):
        if not callable(f) or not callable(g):
            raise TypeError("f and g must be callables of (k, x, noise)")
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, {given_instead_of_set(S, name)}")
        self.f, self.g, self.W, self.V, self.n = f, g, W, V, check_dim(n, "n")

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} = f(k, x_k, w_k) for a realized process noise (smoothing paper (4))."""
        return as_vector(self.f(k, x, w), f"f({k}, x, w)", self.n)

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k = g(k, x_k, v_k) for a realized measurement noise (smoothing paper (5))."""
        return as_vector(self.g(k, x, v), f"g({k}, x, v)")
