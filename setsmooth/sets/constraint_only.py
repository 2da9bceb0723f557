"""Sets given only by their CVXPY constraints, as the README invites users to write them.

Shared by the trajectory-program tests and `benchmarks/bench_long_horizon.py` (issue 8's custom-set
noises).
"""

import cvxpy as cp
import numpy as np

import setsmooth as ss


class L1Ball(ss.ConvexSet):
    """{x : ‖x − c‖₁ ≤ r}, given only by its constraints."""

    def __init__(self, center, radius):
        self.c, self.r = np.asarray(center, dtype=float), float(radius)
        self.dim = self.c.size

    def constraints(self, x):
        return [cp.norm1(x - self.c) <= self.r]


class VPolytope(ss.ConvexSet):
    """The convex hull of the rows of ``vertices``, given only by its constraints."""

    def __init__(self, vertices):
        self.vertices = np.asarray(vertices, dtype=float)
        self.dim = self.vertices.shape[1]

    def constraints(self, x):
        lam = cp.Variable(self.vertices.shape[0], nonneg=True)
        return [cp.sum(lam) == 1, x == self.vertices.T @ lam]
