"""Lazy set operations: exact, represented by their operands, queried through CVXPY.

An operation whose operands have no common closed form stays lazy. Each lazy set flattens to a
constrained zonotope when all its operands do (and then uses the CZ fast path); otherwise its support
function uses the closed-form identities h_{MS}(d) = h_S(Mᵀd), h_{S⊕T} = h_S + h_T and
h_{S×T}(d₁, d₂) = h_S(d₁) + h_T(d₂), and intersections go through the generic CVXPY path.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .base import ConvexSet


def _sum_supports(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """h_S + h_T with the empty set absorbing: −∞ + ∞ is −∞ (the sum is empty)."""
    with np.errstate(invalid="ignore"):
        out = a + b
    out[np.isneginf(a) | np.isneginf(b)] = -np.inf
    return out


class LinearMap(ConvexSet):
    """{M s + offset : s ∈ S} for a matrix M of shape (m, S.dim)."""

    def __init__(self, M, S: ConvexSet, offset=None):
        self.M = M
        self.S = S
        self.dim = M.shape[0]
        self.offset = np.zeros(self.dim) if offset is None else np.asarray(offset, dtype=float)

    def constraints(self, x):
        s = cp.Variable(self.S.dim)
        return [x == self.M @ s + self.offset] + list(self.S.constraints(s))

    def _as_constrained_zonotope(self):
        cz = self.S._flat_cz
        return None if cz is None else cz._linear_map(self.M)._translate(self.offset)

    def _support(self, D, certified):
        if self._flat_cz is not None:
            return self._flat_cz._support(D, certified)
        values, points = self.S._support_points(np.asarray(D @ self.M), "auto", certified)
        return values + D @ self.offset, np.asarray((self.M @ points.T).T) + self.offset

    def _is_empty(self):
        return self.S._is_empty()


class MinkowskiSum(ConvexSet):
    """S ⊕ T."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        self.S, self.T, self.dim = S, T, S.dim

    def constraints(self, x):
        s, t = cp.Variable(self.dim), cp.Variable(self.dim)
        return [x == s + t] + list(self.S.constraints(s)) + list(self.T.constraints(t))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.T._flat_cz
        return None if a is None or b is None else a._minkowski_sum(b)

    def _support(self, D, certified):
        if self._flat_cz is not None:
            return self._flat_cz._support(D, certified)
        va, pa = self.S._support_points(D, "auto", certified)
        vb, pb = self.T._support_points(D, "auto", certified)
        return _sum_supports(va, vb), pa + pb

    def _is_empty(self):
        return self.S._is_empty() or self.T._is_empty()


class CartesianProduct(ConvexSet):
    """S × T ⊂ ℝ^{S.dim + T.dim}."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        self.S, self.T, self.dim = S, T, S.dim + T.dim

    def constraints(self, x):
        n = self.S.dim
        return list(self.S.constraints(x[:n])) + list(self.T.constraints(x[n:]))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.T._flat_cz
        return None if a is None or b is None else a._cartesian_product(b)

    def _support(self, D, certified):
        if self._flat_cz is not None:
            return self._flat_cz._support(D, certified)
        n = self.S.dim
        va, pa = self.S._support_points(D[:, :n], "auto", certified)
        vb, pb = self.T._support_points(D[:, n:], "auto", certified)
        return _sum_supports(va, vb), np.hstack([pa, pb])

    def _is_empty(self):
        return self.S._is_empty() or self.T._is_empty()


class Intersection(ConvexSet):
    """S ∩ T."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        self.S, self.T, self.dim = S, T, S.dim

    def constraints(self, x):
        return list(self.S.constraints(x)) + list(self.T.constraints(x))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.T._flat_cz
        return None if a is None or b is None else a._generalized_intersection(np.eye(self.dim), b)


class GeneralizedIntersection(ConvexSet):
    """{s ∈ S : R s ∈ Y} (smoothing paper (37) in any representation)."""

    def __init__(self, S: ConvexSet, R, Y: ConvexSet):
        self.S, self.R, self.Y, self.dim = S, R, Y, S.dim

    def constraints(self, x):
        return list(self.S.constraints(x)) + list(self.Y.constraints(self.R @ x))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.Y._flat_cz
        return None if a is None or b is None else a._generalized_intersection(self.R, b)
