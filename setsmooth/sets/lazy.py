"""Lazy set operations: exact, represented by their operands, queried through CVXPY.

An operation whose operands have no common closed form stays lazy. Each lazy set flattens to a
constrained zonotope when all its operands do (and then uses the CZ fast path); otherwise its support
function uses the closed-form identities h_{MS}(d) = h_S(Mᵀd), h_{S⊕T} = h_S + h_T and
h_{S×T}(d₁, d₂) = h_S(d₁) + h_T(d₂), and intersections go through the generic CVXPY path.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .._validation import as_matrix, as_vector
from . import _matrices as mx
from .base import ConvexSet, _same_dim
from .rounding import sum_up


def _operand(S, name: str) -> ConvexSet:
    if not isinstance(S, ConvexSet):
        raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
    return S


def _frozen_matrix(M, name: str, rows: int | None, cols: int):
    """A validated private copy of M (sets are immutable): read-only when dense."""
    M = as_matrix(M, name, rows=rows, cols=cols, allow_sparse=True)  # copies a sparse M
    return M if sp.issparse(M) else mx.readonly(M)


def _sum_supports(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """h_S + h_T rounded up (so that certified values stay upper bounds), with the empty set
    absorbing: −∞ + ∞ is −∞ (the sum is empty)."""
    with np.errstate(invalid="ignore"):
        out = sum_up(a, b)
    out[np.isneginf(a) | np.isneginf(b)] = -np.inf
    return out


class LinearMap(ConvexSet):
    """{M s + offset : s ∈ S} for a matrix M of shape (m, S.dim)."""

    def __init__(self, M, S: ConvexSet, offset=None):
        self.S = _operand(S, "S")
        self.M = _frozen_matrix(M, "M", None, S.dim)
        self.dim = self.M.shape[0]
        self.offset = mx.readonly(np.zeros(self.dim) if offset is None
                                  else as_vector(offset, "offset", self.dim))

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

    def _support_values(self, D, path, certified):
        # Values only (no maximizers) through the operand: a user's closed-form support function
        # (`ConvexSet.support_function`) then serves h_{MS}(d) = h_S(Mᵀd) without a program.
        if path != "auto" or self._flat_cz is not None:
            return super()._support_values(D, path, certified)
        return self.S._support_values(np.asarray(D @ self.M), "auto", certified) + D @ self.offset

    def _is_empty(self):
        return self.S._is_empty()


class MinkowskiSum(ConvexSet):
    """S ⊕ T."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        _same_dim(_operand(S, "S"), _operand(T, "T"), "Minkowski sum")
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

    def _support_values(self, D, path, certified):
        if path != "auto" or self._flat_cz is not None:
            return super()._support_values(D, path, certified)
        return _sum_supports(self.S._support_values(D, "auto", certified),
                             self.T._support_values(D, "auto", certified))

    def _is_empty(self):
        return self.S._is_empty() or self.T._is_empty()


class CartesianProduct(ConvexSet):
    """S × T ⊂ ℝ^{S.dim + T.dim}."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        self.S, self.T = _operand(S, "S"), _operand(T, "T")
        self.dim = S.dim + T.dim

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
        values, points = _sum_supports(va, vb), np.hstack([pa, pb])
        points[~np.isfinite(values)] = np.nan  # no maximizer, not even in one factor
        return values, points

    def _support_values(self, D, path, certified):
        if path != "auto" or self._flat_cz is not None:
            return super()._support_values(D, path, certified)
        n = self.S.dim
        return _sum_supports(self.S._support_values(D[:, :n], "auto", certified),
                             self.T._support_values(D[:, n:], "auto", certified))

    def _is_empty(self):
        return self.S._is_empty() or self.T._is_empty()


class Intersection(ConvexSet):
    """S ∩ T."""

    def __init__(self, S: ConvexSet, T: ConvexSet):
        _same_dim(_operand(S, "S"), _operand(T, "T"), "intersection")
        self.S, self.T, self.dim = S, T, S.dim

    def constraints(self, x):
        return list(self.S.constraints(x)) + list(self.T.constraints(x))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.T._flat_cz
        return None if a is None or b is None else a._generalized_intersection(np.eye(self.dim), b)


class GeneralizedIntersection(ConvexSet):
    """{s ∈ S : R s ∈ Y} (smoothing paper (37) in any representation)."""

    def __init__(self, S: ConvexSet, R, Y: ConvexSet):
        self.S, self.Y = _operand(S, "S"), _operand(Y, "Y")
        self.R = _frozen_matrix(R, "R", Y.dim, S.dim)
        self.dim = S.dim

    def constraints(self, x):
        return list(self.S.constraints(x)) + list(self.Y.constraints(self.R @ x))

    def _as_constrained_zonotope(self):
        a, b = self.S._flat_cz, self.Y._flat_cz
        return None if a is None or b is None else a._generalized_intersection(self.R, b)
