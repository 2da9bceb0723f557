"""Zonotopes Z(G, c) = {Gξ + c : ‖ξ‖∞ ≤ 1}: support function and interval hull in closed form."""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.linalg
import scipy.sparse as sp

from .._validation import as_matrix, as_vector
from . import _matrices as mx
from . import rounding
from .base import ConvexSet
from .box import Box
from .constrained_zonotope import ConstrainedZonotope


class Zonotope(ConvexSet):
    """The zonotope {Gξ + c : ξ ∈ [−1, 1]^ng}.

    Parameters
    ----------
    G : array_like, shape (n, ng)
        Generators, one per column.
    c : array_like, shape (n,)
        Centre.

    Raises
    ------
    ValueError
        If ``G`` is not 2-D (a 1-D ``G`` could be one generator or n of them: it is refused), ``c``
        is not a vector of length n, or an entry is NaN or infinite.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope([[1.0, 1.0], [0.0, 1.0]], [0.0, 0.0])
    >>> Z.interval_hull().hi.tolist()
    [2.0, 1.0]
    """

    def __init__(self, G: Any, c: Any):
        G = as_matrix(G, "G", layout="(n, ng), one generator per column")
        c = as_vector(c, "c", G.shape[0])
        self._init(G, c)

    def _init(self, G: np.ndarray, c: np.ndarray, pad: np.ndarray | None = None,
              pad_generators: np.ndarray | None = None) -> None:
        self.G = mx.readonly(G)
        self.c = mx.readonly(c)
        self.dim = self.G.shape[0]
        # The algebra's rounding (`setsmooth.sets.rounding`): every point of the exact set is within
        # box(pad) ⊕ Z(pad_generators) of a point of Z(G, c); linear maps carry the generators exactly.
        self._pad_box = None if pad is None else mx.readonly(pad)
        self._pad_generators = None if pad_generators is None else mx.readonly(pad_generators)
        hull = rounding.pad_hull(pad, pad_generators)
        #: The box hull of the rounding charges (componentwise); None when nothing was rounded.
        self.pad = None if hull is None else mx.readonly(hull)

    @classmethod
    def _trusted(cls, G: np.ndarray, c: np.ndarray, pad: np.ndarray | None = None,
                 pad_generators: np.ndarray | None = None) -> "Zonotope":
        obj = cls.__new__(cls)
        obj._init(G, c, pad, pad_generators)
        return obj

    def materialized(self) -> "Zonotope":
        """The same enclosure with the pad written as generators (one per padded coordinate)."""
        if self.pad is None:
            return self
        rows = np.flatnonzero(self.pad)
        P = np.zeros((self.dim, rows.size))
        P[rows, np.arange(rows.size)] = self.pad[rows]
        return Zonotope._trusted(np.hstack([self.G, P]), self.c)

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
        """h_Z(d) = dᵀc + ‖Gᵀd‖₁, attained at c + G sign(Gᵀd); ``certified``: plus the bound on its
        rounding (γ over the n + ng products and sums) and |d|ᵀpad."""
        g = D @ self.G
        values = D @ self.c + np.abs(g).sum(axis=1)
        points = np.sign(g) @ self.G.T + self.c
        if certified:
            magnitude = np.abs(D) @ np.abs(self.c) + np.abs(D) @ np.abs(self.G).sum(axis=1)
            values = rounding.upper_bound(values, magnitude, self.dim + self.ng + 1,
                                          absolute=self.dim * self.ng)
            if self.pad is not None:
                values = np.nextafter(values + rounding.rounded_up(rounding.abs_matvec(D, self.pad),
                                                                   self.dim), np.inf)
        return values, points

    def interval_hull(self, *, path: str = "auto", certified: bool = False):
        """[c − r, c + r] with r = Σ_j |G_{:,j}| (no program); ``certified`` (or a padded
        zonotope): r and the pad rounded up and the bounds rounded outward."""
        if self._check_path(path) == "generic":
            return super().interval_hull(path=path, certified=certified)
        r = np.abs(self.G).sum(axis=1)
        if not certified and self.pad is None:
            return Box._trusted(self.c - r, self.c + r)
        r = rounding.rounded_up(r, self.ng)
        if self.pad is not None:
            r = rounding.add(r, self.pad)
        return Box._trusted(rounding.sum_down(self.c, -r), rounding.sum_up(self.c, r))

    def _is_empty(self) -> bool:
        return False

    def _as_constrained_zonotope(self):
        return ConstrainedZonotope._trusted(self.G, self.c, np.zeros((0, self.ng)), np.zeros(0),
                                            np.ones(self.ng), pad=self._pad_box,
                                            pad_generators=self._pad_generators)

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_linear_map(self, M) -> "Zonotope":
        M = M.toarray() if sp.issparse(M) else M
        fresh, _ = rounding.linear_image(M, self.G, self.c, np.ones(self.ng), None)
        generators, carried = rounding.mapped_pad(M, self._pad_box, self._pad_generators)
        return Zonotope._trusted(M @ self.G, M @ self.c, rounding.add(fresh, carried), generators)

    def _closed_translate(self, v: np.ndarray) -> "Zonotope":
        c, err = rounding.sum_with_error(self.c, v)
        return Zonotope._trusted(self.G, c, rounding.add(self._pad_box, err if err.any() else None),
                                 self._pad_generators)

    def _project(self, idx: np.ndarray) -> "Zonotope":
        return Zonotope._trusted(self.G[idx], self.c[idx],
                                 None if self._pad_box is None else self._pad_box[idx],
                                 None if self._pad_generators is None else self._pad_generators[idx])

    def _closed_sum(self, other):
        other = _as_zonotope(other)
        if other is None:
            return NotImplemented
        c, err = rounding.sum_with_error(self.c, other.c)
        generators = [P for P in (self._pad_generators, other._pad_generators) if P is not None]
        return Zonotope._trusted(np.hstack([self.G, other.G]), c,
                                 rounding.add(self._pad_box, other._pad_box, err if err.any() else None),
                                 np.hstack(generators) if generators else None)

    def _closed_product(self, other):
        other = _as_zonotope(other)
        if other is None:
            return NotImplemented
        # Dense like every G here (mx.block_diag would turn a large product sparse).
        pad = None
        if self.pad is not None or other.pad is not None:
            pad = np.concatenate([np.zeros(self.dim) if self.pad is None else self.pad,
                                  np.zeros(other.dim) if other.pad is None else other.pad])
        return Zonotope._trusted(scipy.linalg.block_diag(self.G, other.G),
                                 np.concatenate([self.c, other.c]), pad)


def _as_zonotope(S):
    if isinstance(S, Zonotope):
        return S
    if isinstance(S, Box) and S.is_bounded:
        return S.to_zonotope()
    return None
