"""Zonotopes Z(G, c) = {Gξ + c : ‖ξ‖∞ ≤ 1}: support function and interval hull in closed form."""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.linalg
import scipy.sparse as sp

from .._validation import as_matrix, as_vector
from . import _matrices as mx
from .base import ConvexSet


class Zonotope(ConvexSet):
    """The zonotope {Gξ + c : ξ ∈ [−1, 1]^ng}.

    Parameters
    ----------
    G : array_like, shape (n, ng)
        Generators, one per column.
    c : array_like, shape (n,)
        Centre.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope([[1.0, 1.0], [0.0, 1.0]], [0.0, 0.0])
    >>> Z.interval_hull().hi.tolist()
    [2.0, 1.0]
    """

    def __init__(self, G: Any, c: Any):
        G = as_matrix(G, "G")
        c = as_vector(c, "c", G.shape[0])
        self._init(G, c)

    def _init(self, G: np.ndarray, c: np.ndarray) -> None:
        self.G = mx.readonly(G)
        self.c = mx.readonly(c)
        self.dim = self.G.shape[0]

    @classmethod
    def _trusted(cls, G: np.ndarray, c: np.ndarray) -> "Zonotope":
        obj = cls.__new__(cls)
        obj._init(G, c)
        return obj

    @property
    def ng(self) -> int:
        """Number of generators."""
        return self.G.shape[1]

    def __repr__(self) -> str:
        return f"Zonotope(dim={self.dim}, ng={self.ng})"

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        xi = cp.Variable(self.ng)
        return [x == self.G @ xi + self.c, cp.norm(xi, "inf") <= 1]

    # -- closed forms ------------------------------------------------------------------------------
    def _support(self, D: np.ndarray, certified: bool):
        """h_Z(d) = dᵀc + ‖Gᵀd‖₁, attained at c + G sign(Gᵀd)."""
        g = D @ self.G
        values = D @ self.c + np.abs(g).sum(axis=1)
        points = np.sign(g) @ self.G.T + self.c
        return values, points

    def interval_hull(self, *, path: str = "auto", certified: bool = False):
        """[c − r, c + r] with r = Σ_j |G_{:,j}| (no program)."""
        if self._check_path(path) == "generic":
            return super().interval_hull(path=path, certified=certified)
        from .box import Box

        r = np.abs(self.G).sum(axis=1)
        return Box._trusted(self.c - r, self.c + r)

    def _is_empty(self) -> bool:
        return False

    def _as_constrained_zonotope(self):
        from .constrained_zonotope import ConstrainedZonotope

        return ConstrainedZonotope._trusted(self.G, self.c, np.zeros((0, self.ng)), np.zeros(0),
                                            np.ones(self.ng))

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_linear_map(self, M) -> "Zonotope":
        M = M.toarray() if sp.issparse(M) else M
        return Zonotope._trusted(M @ self.G, M @ self.c)

    def _closed_translate(self, v: np.ndarray) -> "Zonotope":
        return Zonotope._trusted(self.G, self.c + v)

    def _project(self, idx: np.ndarray) -> "Zonotope":
        return Zonotope._trusted(self.G[idx], self.c[idx])

    def _closed_sum(self, other):
        other = _as_zonotope(other)
        if other is None:
            return NotImplemented
        return Zonotope._trusted(np.hstack([self.G, other.G]), self.c + other.c)

    def _closed_product(self, other):
        other = _as_zonotope(other)
        if other is None:
            return NotImplemented
        # Dense like every G here (mx.block_diag would turn a large product sparse).
        return Zonotope._trusted(scipy.linalg.block_diag(self.G, other.G),
                                 np.concatenate([self.c, other.c]))


def _as_zonotope(S):
    from .box import Box

    if isinstance(S, Zonotope):
        return S
    if isinstance(S, Box) and S.is_bounded:
        return S.to_zonotope()
    return None
