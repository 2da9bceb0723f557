"""Ellipsoids {c + Lu : ‖u‖₂ ≤ 1} with shape matrix Q = LLᵀ (possibly singular)."""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .._validation import as_matrix, as_vector, check_count, check_rng
from . import _matrices as mx
from .base import ConvexSet
from .box import Box


class Ellipsoid(ConvexSet):
    """The ellipsoid E(c, Q) = {c + Q^{1/2} u : ‖u‖₂ ≤ 1}.

    With Q positive definite this is {x : (x − c)ᵀ Q⁻¹ (x − c) ≤ 1}; a singular Q gives a degenerate
    (flat) ellipsoid, which linear maps produce.

    Parameters
    ----------
    c : array_like, shape (n,)
        Centre.
    Q : array_like, shape (n, n)
        Symmetric positive semidefinite shape matrix.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> E = ss.Ellipsoid([0.0, 0.0], np.diag([4.0, 1.0]))
    >>> E.support([1.0, 0.0])
    2.0
    """

    def __init__(self, c: Any, Q: Any):
        c = as_vector(c, "c")
        Q = as_matrix(Q, "Q", rows=c.shape[0], cols=c.shape[0])
        scale = max(1.0, np.abs(Q).max(initial=0.0))
        if np.abs(Q - Q.T).max(initial=0.0) > tol.RANK_TOL * 1e3 * scale:
            raise ValueError("Q must be symmetric")
        if np.linalg.eigvalsh((Q + Q.T) / 2).min() < -tol.RANK_TOL * 1e3 * scale:
            raise ValueError("Q must be positive semidefinite")
        self._init(c, (Q + Q.T) / 2)

    def _init(self, c: np.ndarray, Q: np.ndarray) -> None:
        self.c = mx.readonly(c)
        self.Q = mx.readonly(Q)
        self.dim = self.c.shape[0]

    @classmethod
    def _trusted(cls, c: np.ndarray, Q: np.ndarray) -> "Ellipsoid":
        obj = cls.__new__(cls)
        obj._init(c, (Q + Q.T) / 2)
        return obj

    def __repr__(self) -> str:
        return f"Ellipsoid(dim={self.dim})"

    @property
    def root(self) -> np.ndarray:
        """A square root L with LLᵀ = Q (symmetric, from the eigendecomposition)."""
        w, V = np.linalg.eigh(self.Q)
        return (V * np.sqrt(np.clip(w, 0.0, None))) @ V.T

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        # x = c + Lu, ‖u‖ ≤ 1 with a thin factor L (one column per eigenvalue above the rounding
        # noise of Q): a u moving along the null space of a square root would leave x unchanged, a
        # degeneracy on which the interior-point method stalls for flat ellipsoids.
        # The eigenvalues are judged in coordinates scaled by √Q_ii (Jacobi scaling), so that an
        # ellipsoid with axes of 1e3 and 1e-6 keeps both (unscaled, 1e-12 of the largest eigenvalue
        # fell below the rounding threshold and the set came out flat).
        d = np.sqrt(np.clip(np.diag(self.Q), 0.0, None))
        d = np.where(d > 0, d, 1.0)
        w, V = np.linalg.eigh(self.Q / np.outer(d, d))
        keep = w > 10 * self.dim * np.finfo(float).eps * max(w.max(initial=0.0), 0.0)
        if not keep.any():
            return [x == self.c]
        u = cp.Variable(int(keep.sum()))
        return [x == (d[:, None] * V[:, keep] * np.sqrt(w[keep])) @ u + self.c, cp.norm(u, 2) <= 1]

    def _support(self, D: np.ndarray, certified: bool):
        """h_E(d) = dᵀc + √(dᵀQd), attained at c + Qd/√(dᵀQd)."""
        if certified:
            # Not a CZ: no weak-duality certificate, as for every other non-flattenable set.
            return super()._support(D, certified)
        QD = D @ self.Q
        s = np.sqrt(np.clip(np.einsum("ij,ij->i", QD, D), 0.0, None))
        values = D @ self.c + s
        safe = np.where(s > 0, s, 1.0)
        points = self.c + np.where(s[:, None] > 0, QD / safe[:, None], 0.0)
        return values, points

    def interval_hull(self, *, path: str = "auto", certified: bool = False):
        if self._check_path(path) == "generic" or certified:
            return super().interval_hull(path=path, certified=certified)
        r = np.sqrt(np.clip(np.diag(self.Q), 0.0, None))
        return Box._trusted(self.c - r, self.c + r)

    def _is_empty(self) -> bool:
        return False

    def _chebyshev_center(self) -> np.ndarray:
        return np.array(self.c)

    def sample(self, rng: np.random.Generator, size: int = 1, *, method: str = "auto") -> np.ndarray:
        """Uniform samples: a uniform point of the unit ball mapped by Q^{1/2} (exact for every ``method``)."""
        check_rng(rng)
        size = check_count(size)
        u = rng.standard_normal((size, self.dim))
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        u *= rng.uniform(size=(size, 1)) ** (1.0 / self.dim)
        return u @ self.root.T + self.c

    def _closed_linear_map(self, M) -> "Ellipsoid":
        """M E(c, Q) = E(Mc, MQMᵀ)."""
        M = M.toarray() if sp.issparse(M) else M
        return Ellipsoid._trusted(M @ self.c, M @ self.Q @ M.T)

    def _closed_translate(self, v: np.ndarray) -> "Ellipsoid":
        return Ellipsoid._trusted(self.c + v, self.Q)

    def _project(self, idx: np.ndarray) -> "Ellipsoid":
        return Ellipsoid._trusted(self.c[idx], self.Q[np.ix_(idx, idx)])
