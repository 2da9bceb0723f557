"""Generator reduction (Girard 2005, Combastel 2003) and the certified interval hull. Outer.

A zonotope of order ng/n above ``order`` keeps its ⌊order·n⌋ − n highest-scoring generators and
replaces the others by the box of their sum, diag(Σ|g|) (n more generators, zero rows dropped):

* `Girard`: score ‖g‖₁ − ‖g‖∞ (how much boxing g would add), Girard 2005;
* `Combastel`: score ‖g‖₂, Combastel 2003.

A constrained zonotope goes through its lifted zonotope [G; A], [c; −b] (Scott et al. 2016 §4.3): the
reduced lifted zonotope [G'; A'], [c; −b] gives Z(G', c, A', b) ⊇ Z, with the order counted in degrees of
freedom, (ng − nc)/n ≤ order, i.e. lifted order (order·n + nc)/(n + nc). Free factors (h = ∞) span a
subspace of the lifted space; they are kept as they are and the bounded part is reduced, which is
exact for them.

The box radii are sums of absolute values rounded upward (γ_k bound), so the box contains the boxed
generators' zonotope in floating point too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..empty import EmptySet
from ..zonotope import Zonotope
from ._base import (CZData, ReductionMethod, abs_sum_upper, certified_margin, round_down, round_up,
                    scaled_abs_upper)

__all__ = ["Girard", "Combastel", "IntervalHull"]


def _check_order(order) -> None:
    if isinstance(order, bool) or not isinstance(order, (int, float, np.integer, np.floating)):
        raise TypeError(f"order must be a finite number ≥ 1, got {order!r} ({type(order).__name__})")
    if not np.isfinite(order) or order < 1:
        raise ValueError(f"order must be a finite number ≥ 1, got {order!r}")


def _box_reduce(L: np.ndarray, h: np.ndarray, target: int,
                scores: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Keep the target − d best columns of L (d × k, bounds h) and box the rest.

    Returns the columns and their bounds, ``target`` columns at most: the kept columns unchanged with
    their bounds (no rounding), then diag(Σ h_j |L_j|) over the boxed ones with bound 1, each radius
    rounded up (`scaled_abs_upper`, `abs_sum_upper`), so the box contains the boxed part in floating
    point too; zero rows of the box are dropped.
    """
    d, k = L.shape
    if k <= target:
        return L, h
    keep_count = target - d
    order = np.argsort(-scores, kind="stable")
    keep, rest = np.sort(order[:keep_count]), order[keep_count:]
    radius = abs_sum_upper(scaled_abs_upper(L[:, rest], h[rest]))
    nz = np.flatnonzero(radius > 0.0)
    box = np.zeros((d, nz.size))
    box[nz, np.arange(nz.size)] = radius[nz]
    return np.hstack([L[:, keep], box]), np.concatenate([h[keep], np.ones(nz.size)])


@dataclass(frozen=True)
class _GeneratorReduction(ReductionMethod):
    order: float = 1.0

    def __post_init__(self):
        _check_order(self.order)

    def _scores(self, L: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        target = math.floor(self.order * Z.dim)
        if Z.ng <= target:
            return Z
        G, _ = _box_reduce(Z.G, np.ones(Z.ng), target, self._scores(Z.G))
        return Zonotope._trusted(G, Z.c)

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        d = CZData.of(Z)
        free = np.isinf(d.h)
        # Degrees of freedom: ng − nc ≤ order·n, i.e. ⌊order·n⌋ + nc lifted generators.
        target = math.floor(self.order * d.n) + d.nc
        if d.ng <= target:
            return Z
        bounded_target = target - int(free.sum())
        lifted_dim = d.n + d.nc
        if bounded_target < lifted_dim:
            raise ValueError(
                f"{self!r} cannot reach {target} generators on a constrained zonotope with "
                f"{int(free.sum())} free factors (h = inf) in dimension {d.n} with {d.nc} constraints: "
                "the box of the bounded part alone needs n + nc generators (eliminate the free factors "
                "first, e.g. EliminateConstraints)")
        fin = np.flatnonzero(~free)
        # Lifted zonotope of the bounded factors; scores on the columns scaled to unit bounds (their
        # rounding only affects the choice), the kept columns keep their own bounds (no rounding).
        L = np.vstack([d.G[:, fin], d.A[:, fin]])
        R, hR = _box_reduce(L, d.h[fin], bounded_target, self._scores(L * d.h[fin]))
        G = np.hstack([R[:d.n], d.G[:, free]])
        A = np.hstack([R[d.n:], d.A[:, free]])
        h = np.concatenate([hR, d.h[free]])
        return CZData(G, d.c, A, d.b, h, d.sparse).to_set()

    def _on_box(self, B: Box) -> Box:
        return B  # already of order 1 (unbounded coordinates are free directions)


@dataclass(frozen=True)
class Girard(_GeneratorReduction):
    """Girard's reduction to order ``order`` (score ‖g‖₁ − ‖g‖∞). Outer.

    Parameters
    ----------
    order : float
        Target order (≥ 1): ng ≤ ⌊order·n⌋ for a zonotope; (ng − nc) ≤ order·n, degrees of freedom,
        for a constrained zonotope (through the lifted zonotope, Scott et al. 2016 §4.3).

    Raises
    ------
    TypeError
        If ``order`` is not a number (a bool is refused).
    ValueError
        If ``order`` is not finite or < 1; when applied, if a CZ's free factors (h = ∞) leave too few
        generators for the box of the bounded part.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope(np.random.default_rng(0).standard_normal((2, 6)), np.zeros(2))
    >>> ss.reduce(Z, ss.Girard(1)).ng
    2
    """

    def _scores(self, L: np.ndarray) -> np.ndarray:
        return np.abs(L).sum(axis=0) - np.abs(L).max(axis=0, initial=0.0)


@dataclass(frozen=True)
class Combastel(_GeneratorReduction):
    """Combastel's reduction to order ``order`` (score ‖g‖₂: the shortest generators are boxed). Outer.

    Parameters
    ----------
    order : float
        Target order (≥ 1), counted as in `Girard`.

    Raises
    ------
    TypeError
        If ``order`` is not a number (a bool is refused).
    ValueError
        If ``order`` is not finite or < 1; when applied, as `Girard`.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope(np.random.default_rng(0).standard_normal((2, 6)), np.zeros(2))
    >>> ss.reduce(Z, ss.Combastel(2)).ng
    4
    """

    def _scores(self, L: np.ndarray) -> np.ndarray:
        return np.linalg.norm(L, axis=0)


@dataclass(frozen=True)
class IntervalHull(ReductionMethod):
    """The interval hull, as a `Box`, certified to contain the set in floating point. Outer.

    Zonotopes and unconstrained CZs in closed form (c ± Σ h|g|, rounded outward; a free factor gives
    infinite bounds where it moves the set); constrained CZs by certified (weak-duality) support values
    widened by their rounding bound.
    """

    def _on_box(self, B: Box) -> Box:
        return B

    def _on_zonotope(self, Z: Zonotope) -> Box:
        return _box(Z.c, abs_sum_upper(Z.G))

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        d = CZData.of(Z)
        if d.nc == 0:
            return _box(d.c, abs_sum_upper(scaled_abs_upper(d.G, d.h)))
        hull = Z.interval_hull(certified=True)
        if isinstance(hull, EmptySet):
            return hull
        scale = 1.0 + np.abs(d.c) + np.abs(d.G) @ np.where(np.isfinite(d.h), d.h, 0.0) \
            + np.abs(d.b).max(initial=0.0)
        margin = certified_margin(d.ng + d.nc + d.n + 2,
                                  scale + np.maximum(np.abs(hull.lo), np.abs(hull.hi)))
        with np.errstate(invalid="ignore"):
            lo = round_down(hull.lo - margin)
            hi = round_up(hull.hi + margin)
        return Box._trusted(lo, hi)


def _box(c: np.ndarray, radius: np.ndarray) -> Box:
    """[c − r, c + r] rounded outward (r already an upper bound)."""
    return Box._trusted(round_down(c - radius), round_up(c + radius))
