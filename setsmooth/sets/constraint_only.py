"""Sets given only by their CVXPY constraints, the one required method of a `ConvexSet`.

What a user's own set looks like when it defines nothing else (no CZ form, no support function): every
query, filter and smoother then takes the generic (CVXPY) path. The trajectory-program tests and
``benchmarks/bench_long_horizon.py`` (its ``custom`` case) run on these two.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .base import ConvexSet

__all__ = ["L1Ball", "VertexHull"]


class L1Ball(ConvexSet):
    """{x : ‖x − c‖₁ ≤ r}, given only by its constraints."""

    def __init__(self, center, radius):
        self.c, self.r = np.asarray(center, dtype=float), float(radius)
        self.dim = self.c.size

    def constraints(self, x):
        return [cp.norm1(x - self.c) <= self.r]


class VertexHull(ConvexSet):
    """The convex hull of the rows of ``vertices``, given only by its constraints (unlike `VPolytope`,
    which has a CZ form)."""

    def __init__(self, vertices):
        self.vertices = np.asarray(vertices, dtype=float)
        self.dim = self.vertices.shape[1]

    def constraints(self, x):
        lam = cp.Variable(self.vertices.shape[0], nonneg=True)
        return [cp.sum(lam) == 1, x == self.vertices.T @ lam]
