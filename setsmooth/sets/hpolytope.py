"""H-polytopes {x : Hx ≤ k}: intersections, preimages and translations in closed form."""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.linalg
import scipy.sparse as sp

from .._validation import as_matrix, as_vector
from ..solvers import chebyshev_ball
from . import _matrices as mx
from .base import ConvexSet
from .box import Box
from .reals import Reals


class HPolytope(ConvexSet):
    """The polyhedron {x : Hx ≤ k} (possibly unbounded or empty).

    Parameters
    ----------
    H : array_like, shape (m, n)
        Normals, one inequality per row.
    k : array_like, shape (m,)
        Offsets.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> P = ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [1.0, 0.0, 0.0])
    >>> round(P.area(), 6)
    0.5
    """

    def __init__(self, H: Any, k: Any):
        H = as_matrix(H, "H")
        k = as_vector(k, "k", H.shape[0])
        self._init(H, k, H.shape[1])

    def _init(self, H: np.ndarray, k: np.ndarray, dim: int) -> None:
        self.H = mx.readonly(H)
        self.k = mx.readonly(k)
        self.dim = dim

    @classmethod
    def _trusted(cls, H: np.ndarray, k: np.ndarray, dim: int) -> "HPolytope":
        obj = cls.__new__(cls)
        obj._init(H.reshape(-1, dim), k.reshape(-1), dim)
        return obj

    def __repr__(self) -> str:
        return f"HPolytope(dim={self.dim}, m={self.H.shape[0]})"

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        if self.H.shape[0] == 0:
            return []
        return [self.H @ x <= self.k]

    #: `_contains` is a closed form (no solver accuracy): `membership.settled_without_hull` may use it.
    _exact_membership_form = True

    def _contains(self, p: np.ndarray, margin) -> bool:
        # An ∞-norm margin m around the point (a float or one per coordinate) relaxes row i by
        # Σ_j |H_ij| m_j.
        m = np.broadcast_to(np.asarray(margin, dtype=float), (self.dim,))
        return bool(np.all(self.H @ p <= self.k + np.abs(self.H) @ m))

    def _chebyshev_center(self) -> np.ndarray:
        center, _ = chebyshev_ball(self.H, self.k)
        return center

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_translate(self, v: np.ndarray) -> "HPolytope":
        return HPolytope._trusted(self.H, self.k + self.H @ v, self.dim)

    def _closed_intersection(self, other):
        other = _as_hpolytope(other)
        if other is None:
            return NotImplemented
        return HPolytope._trusted(np.vstack([self.H, other.H]), np.concatenate([self.k, other.k]),
                                  self.dim)

    def _closed_generalized_intersection(self, R, Y):
        """{x ∈ P : Rx ∈ Y} = {x : Hx ≤ k, H_Y R x ≤ k_Y} for a polyhedral Y."""
        Y = _as_hpolytope(Y)
        if Y is None:
            return NotImplemented
        R = R.toarray() if sp.issparse(R) else R
        return HPolytope._trusted(np.vstack([self.H, Y.H @ R]), np.concatenate([self.k, Y.k]), self.dim)

    def _closed_reflected_generalized_intersection(self, S, R):
        """{s ∈ S : Rs ∈ P} for an S with an H-form (a Box): the same closed form as S ∩_R P."""
        S = _as_hpolytope(S)
        if S is None:
            return NotImplemented
        return S._closed_generalized_intersection(R, self)

    def _closed_product(self, other):
        other = _as_hpolytope(other)
        if other is None:
            return NotImplemented
        # Dense like every H here (mx.block_diag would turn a large product sparse).
        return HPolytope._trusted(scipy.linalg.block_diag(self.H, other.H),
                                  np.concatenate([self.k, other.k]), self.dim + other.dim)

    def _closed_reflected_product(self, S):
        """S × P for an S with an H-form (a Box, ℝⁿ)."""
        S = _as_hpolytope(S)
        if S is None:
            return NotImplemented
        return S._closed_product(self)


def _as_hpolytope(S):
    """An H-form of a Box, of ℝⁿ (no rows) or of an HPolytope; None for other representations."""
    if isinstance(S, HPolytope):
        return S
    if isinstance(S, Box):
        return S.to_hpolytope()
    if isinstance(S, Reals):
        return HPolytope._trusted(np.zeros((0, S.dim)), np.zeros(0), S.dim)
    return None
