"""V-polytopes: the convex hull of finitely many points, exactly a constrained zonotope.

With simplex weights λ = (𝟙 + ξ)/2 ∈ [0, 1]^k, Σλ = 1, the hull of the rows v_1..v_k of V is

    conv{v_i} = { Vᵀλ } = Z(G = Vᵀ/2, c = Vᵀ𝟙/2, A = 𝟙ᵀ, b = 2 − k, ξ ∈ [−1, 1]^k)

(built from the points relative to their mean, the same set with generators of the polytope's size),

so every query and estimator takes the CZ fast path, and the closed forms are cheap: the support
function is a maximum over the points, the interval hull their coordinate-wise extremes, a linear
map or translation maps the points.
"""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .._validation import as_matrix
from . import _matrices as mx
from . import rounding
from .base import ConvexSet
from .box import Box
from .constrained_zonotope import ConstrainedZonotope


class VPolytope(ConvexSet):
    """The convex hull of the rows of ``points``.

    Parameters
    ----------
    points : array_like, shape (k, n)
        k ≥ 1 points of ℝⁿ, one per row (redundant interior points are allowed).

    Raises
    ------
    ValueError
        Without points, with NaN or infinite entries, or when ``points`` is not 2-D: ``[0, 1, 2]``
        could be one point of ℝ³ (``[[0, 1, 2]]``) or three of ℝ (``[[0], [1], [2]]``).

    Examples
    --------
    >>> import setsmooth as ss
    >>> P = ss.VPolytope([[0, 0], [2, 0], [0, 1]])
    >>> P.support([1, 1]), round(P.area(), 9), P.contains([0.5, 0.25])
    (2.0, 1.0, True)
    """

    def __init__(self, points: Any):
        V = as_matrix(points, "points", layout="(k, n), one point per row")
        if V.shape[0] == 0:
            raise ValueError("points must hold at least one point (use EmptySet(n) for the empty set)")
        self._init(V)

    def _init(self, V: np.ndarray) -> None:
        self.points = mx.readonly(V)
        self.dim = V.shape[1]

    @classmethod
    def _trusted(cls, V: np.ndarray) -> "VPolytope":
        obj = cls.__new__(cls)
        obj._init(np.ascontiguousarray(V, dtype=float))
        return obj

    def __repr__(self) -> str:
        return f"VPolytope(dim={self.dim}, points={self.points.shape[0]})"

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        # Relative to the mean m of the points, so that the data have the polytope's size (the
        # generic path's accuracy is relative to the data, not to the position).
        lam = cp.Variable(self.points.shape[0], nonneg=True)
        m = self.points.mean(axis=0)
        return [cp.sum(lam) == 1, x - m == (self.points - m).T @ lam]

    def _as_constrained_zonotope(self):
        # Points relative to their mean m: x = m + V₀ᵀλ with V₀ = V − m, so the generators have the
        # size of the polytope rather than of its position (the fast path's accuracy is relative
        # to them). Σλ = 1 makes m + V₀ᵀλ = Vᵀλ; c = m + V₀ᵀ𝟙/2 = m since Σ_i V₀_i = 0 up to rounding.
        V, k = self.points, self.points.shape[0]
        m = V.mean(axis=0)
        V0 = V - m
        return ConstrainedZonotope._trusted(V0.T / 2, m + V0.sum(axis=0) / 2, np.ones((1, k)),
                                            np.array([2.0 - k]), np.ones(k))

    # -- closed forms ------------------------------------------------------------------------------
    def _support(self, D: np.ndarray, certified: bool):
        """h(d) = max_i dᵀv_i, attained at the maximizing point (exact in floating point up to the
        rounding of one dot product per point)."""
        scores = D @ self.points.T
        best = np.argmax(scores, axis=1)
        values = scores[np.arange(D.shape[0]), best]
        if certified:  # every point's dot product bounded above, then the largest
            values = rounding.upper_bound(scores, np.abs(D) @ np.abs(self.points).T,
                                          self.dim).max(axis=1)
        return values, self.points[best].copy()

    def interval_hull(self, *, path: str = "auto", certified: bool | None = None):
        if self._check_path(path) == "generic":
            return super().interval_hull(path=path, certified=certified)
        return Box._trusted(self.points.min(axis=0), self.points.max(axis=0))

    def _is_empty(self) -> bool:
        return False

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_linear_map(self, M) -> "VPolytope":
        M = M.toarray() if sp.issparse(M) else M
        return VPolytope._trusted(self.points @ M.T)

    def _closed_translate(self, v: np.ndarray) -> "VPolytope":
        return VPolytope._trusted(self.points + v)

    def _project(self, idx: np.ndarray) -> "VPolytope":
        return VPolytope._trusted(self.points[:, idx])

    def _closed_sum(self, other):
        """conv V ⊕ conv W = conv{v + w}: closed form while the k·l pairwise sums stay small."""
        if isinstance(other, VPolytope) and self.points.shape[0] * other.points.shape[0] <= 4096:
            return VPolytope._trusted((self.points[:, None, :] + other.points[None, :, :])
                                      .reshape(-1, self.dim))
        return NotImplemented
