"""Axis-aligned boxes (intervals in 1-D): every query in closed form."""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np

from .._validation import as_vector, check_count, check_rng
from . import _matrices as mx
from . import rounding
from .base import ConvexSet
from .constrained_zonotope import ConstrainedZonotope
from .empty import EmptySet


class Box(ConvexSet):
    """The box {x : lo ≤ x ≤ hi}; bounds may be infinite.

    Parameters
    ----------
    lo, hi : array_like, shape (n,)
        Lower and upper corners with ``lo <= hi`` (use `EmptySet` for an empty box).

    Raises
    ------
    TypeError
        If a bound is not numeric (booleans included).
    ValueError
        If a bound is not a 1-D vector (a row ``[[0, 0]]`` is refused, not flattened), has no entry,
        the lengths differ, an entry is NaN, or ``lo > hi`` somewhere.

    Examples
    --------
    >>> import setsmooth as ss
    >>> ss.Box([-1, 0], [1, 2]).support([1, 1])
    3.0
    """

    def __init__(self, lo: Any, hi: Any):
        lo = as_vector(lo, "lo", allow_inf=True)
        if lo.shape[0] == 0:
            raise ValueError("lo and hi must have at least one entry (a box of ℝⁿ, n ≥ 1), got empty bounds")
        hi = as_vector(hi, "hi", lo.shape[0], allow_inf=True)
        bad = np.flatnonzero(lo > hi)
        if bad.size:
            raise ValueError(f"lo must not exceed hi; lo > hi at indices {bad.tolist()} "
                             "(an empty box is EmptySet(n))")
        if np.isposinf(lo).any() or np.isneginf(hi).any():
            raise ValueError("lo cannot be +inf and hi cannot be -inf")
        self._init(lo, hi)

    def _init(self, lo: np.ndarray, hi: np.ndarray) -> None:
        self.lo = mx.readonly(lo)
        self.hi = mx.readonly(hi)
        self.dim = self.lo.shape[0]

    @classmethod
    def _trusted(cls, lo: np.ndarray, hi: np.ndarray) -> "Box":
        obj = cls.__new__(cls)
        obj._init(lo, hi)
        return obj

    def __repr__(self) -> str:
        return f"Box(lo={self.lo.tolist()}, hi={self.hi.tolist()})"

    def midpoint(self) -> np.ndarray:
        """Centre (lo + hi)/2 (NaN on unbounded coordinates)."""
        with np.errstate(invalid="ignore"):
            mid = (self.lo + self.hi) / 2
        mid[~(np.isfinite(self.lo) & np.isfinite(self.hi))] = np.nan
        return mid

    def widths(self) -> np.ndarray:
        """Edge lengths hi − lo."""
        return self.hi - self.lo

    @property
    def is_bounded(self) -> bool:
        return bool(np.isfinite(self.lo).all() and np.isfinite(self.hi).all())

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        cons = []
        lo_idx = np.flatnonzero(np.isfinite(self.lo))
        hi_idx = np.flatnonzero(np.isfinite(self.hi))
        if lo_idx.size:
            cons.append(x[lo_idx] >= self.lo[lo_idx])
        if hi_idx.size:
            cons.append(x[hi_idx] <= self.hi[hi_idx])
        return cons

    # -- closed forms ------------------------------------------------------------------------------
    def _support(self, D: np.ndarray, certified: bool):
        corner = np.where(D > 0, self.hi, np.where(D < 0, self.lo, 0.0))
        # 0·∞ = 0: a coordinate the direction does not see contributes nothing.
        with np.errstate(invalid="ignore"):
            terms = np.where(D == 0, 0.0, D * corner)
        values = terms.sum(axis=1)
        if certified:  # the sum's rounding (and underflowed products), charged unless exact:
            # one nonzero term per direction (a coordinate axis), its product exact
            exact = (np.count_nonzero(terms, axis=1) <= 1) & np.all(
                rounding.products_exact(np.where(D == 0, 0.0, D), np.where(D == 0, 0.0, corner)),
                axis=1)
            values = np.where(exact, values,
                              rounding.upper_bound(values, np.abs(terms).sum(axis=1), self.dim))
        with np.errstate(invalid="ignore"):  # −∞ + ∞ on free coordinates, replaced below
            mid = np.where(np.isfinite(self.lo) & np.isfinite(self.hi), (self.lo + self.hi) / 2,
                           np.where(np.isfinite(self.lo), self.lo,
                                    np.where(np.isfinite(self.hi), self.hi, 0.0)))
        points = np.where(D > 0, self.hi, np.where(D < 0, self.lo, mid))
        points[~np.isfinite(values)] = np.nan
        return values, points

    def _is_empty(self) -> bool:
        return False

    def _contains(self, p: np.ndarray, margin: float) -> bool:
        return bool(np.all(p >= self.lo - margin) and np.all(p <= self.hi + margin))

    def interval_hull(self, *, path: str = "auto", certified: bool = False) -> "Box":
        if self._check_path(path) == "generic":
            return super().interval_hull(path=path, certified=certified)
        return self

    def _chebyshev_center(self) -> np.ndarray:
        return self.midpoint()

    def sample(self, rng: np.random.Generator, size: int = 1, *, method: str = "auto") -> np.ndarray:
        """Uniform samples, shape (size, dim); exact for every ``method`` (accepted for the common signature)."""
        check_rng(rng)
        size = check_count(size)
        if not self.is_bounded:
            raise ValueError("cannot sample uniformly from an unbounded box")
        return rng.uniform(self.lo, self.hi, size=(size, self.dim))

    def _as_constrained_zonotope(self):
        free = np.isneginf(self.lo) & np.isposinf(self.hi)
        finite = np.isfinite(self.lo) & np.isfinite(self.hi)
        if not np.all(free | finite):
            return None  # a half-line has no CZ form
        lo, hi = np.where(finite, self.lo, 0.0), np.where(finite, self.hi, 0.0)
        center, radius, pad = rounding.box_center_radius(lo, hi)
        radius = np.where(finite, radius, 1.0)
        h = np.where(finite, 1.0, np.inf)
        return ConstrainedZonotope._trusted(np.diag(radius), center, np.zeros((0, self.dim)),
                                            np.zeros(0), h, pad=pad)

    def to_zonotope(self):
        """The box as the zonotope Z(diag(r), m) with radius r and midpoint m (bounded boxes); where
        m ± r is not exactly [lo, hi] in floating point, the zonotope's pad holds the difference."""
        from .zonotope import Zonotope

        if not self.is_bounded:
            raise ValueError("an unbounded box has no zonotope form")
        center, radius, pad = rounding.box_center_radius(self.lo, self.hi)
        return Zonotope._trusted(np.diag(radius), center, pad)

    def to_hpolytope(self):
        """The box as {x : [I; −I] x ≤ [hi; −lo]} (finite faces only)."""
        from .hpolytope import HPolytope

        eye = np.eye(self.dim)
        H = np.vstack([eye, -eye])
        k = np.concatenate([self.hi, -self.lo])
        keep = np.isfinite(k)
        return HPolytope._trusted(H[keep], k[keep], self.dim)

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_translate(self, v: np.ndarray) -> "Box":
        # Rounded outward: the box holds every point of the exact translate.
        return Box._trusted(rounding.sum_down(self.lo, v), rounding.sum_up(self.hi, v))

    def _project(self, idx: np.ndarray) -> "Box":
        return Box._trusted(self.lo[idx], self.hi[idx])

    def _closed_linear_map(self, M):
        if self.is_bounded:
            return self.to_zonotope()._closed_linear_map(M)
        return NotImplemented

    def _closed_sum(self, other):
        if isinstance(other, Box):
            return Box._trusted(rounding.sum_down(self.lo, other.lo), rounding.sum_up(self.hi, other.hi))
        return NotImplemented

    def _closed_intersection(self, other):
        if isinstance(other, Box):
            lo, hi = np.maximum(self.lo, other.lo), np.minimum(self.hi, other.hi)
            return EmptySet(self.dim) if np.any(lo > hi) else Box._trusted(lo, hi)
        return NotImplemented

    def _closed_product(self, other):
        from .zonotope import Zonotope

        if isinstance(other, Box):
            return Box._trusted(np.concatenate([self.lo, other.lo]), np.concatenate([self.hi, other.hi]))
        if isinstance(other, Zonotope) and self.is_bounded:
            return self.to_zonotope()._closed_product(other)
        return NotImplemented
