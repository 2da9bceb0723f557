"""The empty set of ℝⁿ: a value, not an error."""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .._validation import check_dim
from .base import ConvexSet
from .constrained_zonotope import empty_constrained_zonotope


class EmptySet(ConvexSet):
    """The empty subset of ℝⁿ.

    Supports are ``-inf``, ``is_empty()`` is True, and every operation with it is empty
    (an ill-posed filtering step returns it; the following steps stay empty).

    Parameters
    ----------
    n : int
        Dimension.
    """

    def __init__(self, n: int):
        self.dim = check_dim(n, "n")

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        # An infeasible constraint that still mentions x, so the problem keeps its variable.
        return [x[0] <= -1.0, x[0] >= 1.0]

    def _support(self, D: np.ndarray, certified: bool):
        return np.full(D.shape[0], -np.inf), np.full(D.shape, np.nan)

    def _is_empty(self) -> bool:
        return True

    def _contains(self, p: np.ndarray, margin: float) -> bool:
        return False

    def interval_hull(self, *, path: str = "auto", certified: bool = False) -> "EmptySet":
        if self._check_path(path) == "generic" and certified:
            return super().interval_hull(path=path, certified=certified)  # raises
        return self

    def center(self, method: str = "interval_hull", reference=None, norm=2) -> np.ndarray:
        if method not in ("interval_hull", "chebyshev", "closest"):
            return super().center(method)  # raises, naming the valid methods
        return np.full(self.dim, np.nan)

    def vertices_2d(self) -> np.ndarray:
        return np.zeros((0, 2))

    def sample(self, rng: np.random.Generator, size: int = 1, *, method: str = "auto") -> np.ndarray:
        raise ValueError("cannot sample from an empty set")

    def _as_constrained_zonotope(self):
        return empty_constrained_zonotope(self.dim)

    def _project(self, idx: np.ndarray) -> "EmptySet":
        return EmptySet(len(idx))

    def __eq__(self, other) -> bool:
        return isinstance(other, EmptySet) and other.dim == self.dim

    def __hash__(self) -> int:
        return hash(("EmptySet", self.dim))

    def __repr__(self) -> str:
        return f"EmptySet({self.dim})"
