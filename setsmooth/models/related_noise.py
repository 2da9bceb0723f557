"""Related noises as data: how x_0, the process noises and the measurement noises are related.

Rethinking paper Section III: Theorem 1's optimal filter needs the conditional ranges
⟦w_{k−1} | x_{k−1}, y_{0:k−1}⟧ and ⟦v_k | x_k, y_{0:k−1}⟧, which depend on how x_0, w_{0:k}, v_{0:k} are
related (Definition 2). Assumption 1 (all unrelated: their joint range is the Cartesian product (5)) gives
the classical filter of Theorem 2. This module states relatedness for the two cases of Section IV:

* `JointRange` — for linear systems (23)–(24): one convex joint range ⟦x_0, w_0, …, w_{T−1}, v_0, …, v_T⟧.
  `JointRange.unrelated` is Assumption 1; `JointRange.identical_process_noise` is Section IV-B
  (w_k = w for all k), the product box intersected with the subspace {w_0 = … = w_{T−1}}; `restrict`
  and `restrict_halfspaces` add any affine or polyhedral relation. The optimal filter and smoother for a
  joint range are in `setsmooth.filters.optimal`.
* `ScalarRelatedNoiseSystem` — for scalar nonlinear systems x_{k+1} = η(x_k) + w_k, y_k = g(x_k, v_k)
  (Section IV-A, (27)–(28)): a conditional range ⟦v_k | w_{k−1}⟧ = [lo(w_{k−1}), hi(w_{k−1})], all other
  noises unrelated. Its sampled optimal filter is `setsmooth.filters.sampled`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol_policy
from .._validation import as_matrix, as_vector, check_dim, check_rng
from .intervals import as_interval
from ..sets.algebra import cartesian_product
from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..sets.hpolytope import HPolytope

__all__ = ["JointRange", "ScalarRelatedNoiseSystem"]


class JointRange:
    """The joint range ⟦x_0, w_0, …, w_{T−1}, v_0, …, v_T⟧ of a linear system's initial state and noises.

    Coordinates of ξ, in order: x_0 (n), w_0..w_{T−1} (p each), v_0..v_T (q each); `x0_dims`,
    `w_dims` and `v_dims` name them. The marginal ranges ⟦x_0⟧, ⟦w_k⟧, ⟦v_k⟧ (projections, rethinking
    (1)–(2)) are what the classical filter uses; the joint range is what the optimal filter uses.

    Parameters
    ----------
    set : ConvexSet
        The joint range, of dimension n + Tp + (T+1)q. The optimal filter is exact for any convex set;
        when it flattens to a constrained zonotope the filter is a sparse CZ (fast path).
    n, p, q : int
        Dimensions of x_0, of each w_k and of each v_k.
    T : int
        The last time step: there are T process noises and T + 1 measurement noises.

    Raises
    ------
    ValueError, TypeError
        When ``set`` is not a ConvexSet of dimension n + Tp + (T+1)q, or a size is not a positive
        integer (T may be 0).

    Examples
    --------
    >>> import setsmooth as ss
    >>> J = ss.JointRange.identical_process_noise(ss.Box([-1, -1], [1, 1]), ss.Box([-1], [1]),
    ...                                           ss.Box([-1], [1]), T=3)
    >>> J.dim, list(J.w_dims(2))
    (9, [4])
    >>> round(J.set.support([0, 0, 1, -1, 0, 0, 0, 0, 0]), 9) + 0.0   # w_0 − w_1 = 0 on the range
    0.0
    """

    def __init__(self, set: ConvexSet, n: int, p: int, q: int, T: int):
        self.n, self.p, self.q = check_dim(n, "n"), check_dim(p, "p"), check_dim(q, "q")
        if isinstance(T, bool) or not isinstance(T, (int, np.integer)) or T < 0:
            raise TypeError(f"T must be a non-negative integer (the last time step), got {T!r}")
        self.T = int(T)
        self.dim = self.n + self.T * self.p + (self.T + 1) * self.q
        if not isinstance(set, ConvexSet) or set.dim != self.dim:
            got = set.dim if isinstance(set, ConvexSet) else type(set).__name__
            raise ValueError(f"set must be a ConvexSet of dimension n + T p + (T+1) q = {self.n} + "
                             f"{self.T}·{self.p} + {self.T + 1}·{self.q} = {self.dim}, got {got}")
        self.set = set

    def __repr__(self) -> str:
        return f"JointRange(n={self.n}, p={self.p}, q={self.q}, T={self.T}, set={self.set!r})"

    # -- coordinates and marginals --------------------------------------------------------------------
    def x0_dims(self) -> range:
        """Coordinates of x_0 in ξ."""
        return range(0, self.n)

    def w_dims(self, k: int) -> range:
        """Coordinates of w_k in ξ, 0 ≤ k < T."""
        if not 0 <= k < self.T:
            raise IndexError(f"w_k exists for 0 <= k < T = {self.T}, asked for k = {k}")
        start = self.n + k * self.p
        return range(start, start + self.p)

    def v_dims(self, k: int) -> range:
        """Coordinates of v_k in ξ, 0 ≤ k ≤ T."""
        if not 0 <= k <= self.T:
            raise IndexError(f"v_k exists for 0 <= k <= T = {self.T}, asked for k = {k}")
        start = self.n + self.T * self.p + k * self.q
        return range(start, start + self.q)

    def marginal(self, dims: Any) -> ConvexSet:
        """The marginal range of the coordinates ``dims`` (a projection of the joint range, (1))."""
        return self.set.project(list(dims))

    # -- constructors -----------------------------------------------------------------------------------
    @classmethod
    def unrelated(cls, X0: ConvexSet, W: ConvexSet, V: ConvexSet, T: int) -> "JointRange":
        """Assumption 1: x_0, w_{0:T−1}, v_{0:T} unrelated, ⟦·⟧ = ⟦x_0⟧ × ⟦w⟧^T × ⟦v⟧^{T+1} (rethinking (5)).

        Under this range the optimal filter equals the classical one (Theorem 2, Corollary 1).
        """
        for name, S in (("X0", X0), ("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
        factors = [X0] + [W] * int(T) + [V] * (int(T) + 1)
        product = factors[0]
        for S in factors[1:]:
            product = cartesian_product(product, S)
        return cls(product, X0.dim, W.dim, V.dim, T)

    @classmethod
    def identical_process_noise(cls, X0: ConvexSet, W: ConvexSet, V: ConvexSet, T: int) -> "JointRange":
        """Rethinking Section IV-B: one process noise w_k = w for all k, x_0, w, v_{0:T} unrelated.

        The range is the product ⟦x_0⟧ × ⟦w⟧^T × ⟦v⟧^{T+1} intersected with the subspace
        {w_0 = w_1 = … = w_{T−1}}: a subspace ∩ a box when the ranges are boxes.
        """
        joint = cls.unrelated(X0, W, V, T)
        if joint.T < 2:
            return joint
        p = joint.p
        rows = (joint.T - 1) * p
        E = sp.lil_matrix((rows, joint.dim))
        for k in range(joint.T - 1):
            for i in range(p):
                E[k * p + i, joint.w_dims(k)[i]] = 1.0
                E[k * p + i, joint.w_dims(k + 1)[i]] = -1.0
        return joint.restrict(E.tocsr(), np.zeros(rows))

    # -- relations --------------------------------------------------------------------------------------
    def restrict(self, E: Any, e: Any) -> "JointRange":
        """The joint range intersected with the affine relation {ξ : Eξ = e}.

        Parameters
        ----------
        E : array_like or sparse matrix, shape (r, dim)
        e : array_like, shape (r,)

        Returns
        -------
        JointRange
            A constrained zonotope with r more equality rows when this range is one (exact), else the
            lazy intersection with the point {e} under E.
        """
        E = as_matrix(E, "E", cols=self.dim, allow_sparse=True)
        e = as_vector(e, "e", E.shape[0])
        cz = self.set._flat_cz
        if cz is None:
            return JointRange(self.set.intersect_preimage(E, Box(e, e)), self.n, self.p, self.q, self.T)
        # The generalized intersection with the point {e} under E: rows E G ξ = e − E c, their
        # rounding charged by the algebra (`setsmooth.sets.rounding`).
        point = ConstrainedZonotope._trusted(np.zeros((E.shape[0], 0)), e, np.zeros((0, 0)),
                                             np.zeros(0), np.zeros(0))
        return JointRange(cz._generalized_intersection(E, point), self.n, self.p, self.q, self.T)

    def restrict_halfspaces(self, H: Any, k: Any) -> "JointRange":
        """The joint range intersected with the polyhedral relation {ξ : Hξ ≤ k}.

        For a bounded CZ range the result is again an exact CZ: each row gets one slack factor,
        Hᵢξ + sᵢ = kᵢ with sᵢ ∈ [0, rᵢ], where rᵢ = kᵢ − min over the certified interval hull of Hᵢξ is
        at least the slack's largest value on the range (so the slack bound never cuts the set).
        Otherwise the lazy intersection with the H-polytope.

        Parameters
        ----------
        H : array_like, shape (r, dim)
        k : array_like, shape (r,)

        Returns
        -------
        JointRange
        """
        H = as_matrix(H, "H", cols=self.dim)
        k = as_vector(k, "k", H.shape[0])
        cz = self.set._flat_cz
        hull = self.set.interval_hull(certified=True) if cz is not None else None
        if cz is None or not isinstance(hull, Box) or not hull.is_bounded:
            return JointRange(self.set & HPolytope(H, k), self.n, self.p, self.q, self.T)
        lowest = np.minimum(H * hull.lo, H * hull.hi).sum(axis=1)
        # Rounding of the sum above is covered by a relative margin: r only has to be large enough.
        r = np.maximum(k - lowest, 0.0)
        r = r + tol_policy.scaled(tol_policy.MEMBERSHIP_TOL, np.abs(H).sum(axis=1).max() *
                                  max(np.abs(hull.lo).max(), np.abs(hull.hi).max()))
        # Hξ ∈ [k − r, k] as the generalized intersection with that box (its CZ form, one factor per
        # row): the algebra charges the rounding of the rows (`setsmooth.sets.rounding`); the box's
        # lower end rounded does not matter (r has a margin: it only must not cut the range).
        band = Box(k - r, k).to_constrained_zonotope()
        return JointRange(cz._generalized_intersection(H, band), self.n, self.p, self.q, self.T)


@dataclass(frozen=True)
class ScalarRelatedNoiseSystem:
    """x_{k+1} = η(x_k) + w_k, y_k = g(x_k, v_k) with ⟦v_k | w_{k−1}⟧ given (rethinking Section IV-A).

    x_0, w_{0:k}, v_{0:k} are unrelated except that v_k (k ≥ 1) is related to w_{k−1} through the
    conditional range ⟦v_k | w_{k−1}⟧ = [lo(w_{k−1}), hi(w_{k−1})]. By the law of total range (9) the
    marginal ⟦v_k⟧ is the union of the conditional ranges over w ∈ ⟦w⟧; it must equal ``v_range``, which
    is checked on a grid of w at construction: a conditional range outside the marginal would let the
    classical filter (which uses the marginal, Theorem 2) lose the true state.

    Parameters
    ----------
    eta : callable ndarray -> ndarray
        η, vectorised, continuous and increasing (the classical prediction is [η(a) + w_lo, η(b) + w_hi]).
    measurement : callable (x, v) -> y
        g, vectorised (broadcasting), continuous and monotone in v for every x, so that
        g(x, [lo, hi]) is the interval between g(x, lo) and g(x, hi).
    measurement_interval : callable (y, v_lo, v_hi) -> (lo, hi)
        The states consistent with y for some v ∈ [v_lo, v_hi]: ⋃_v g_v⁻¹({y}) of rethinking (16), as an
        interval (vectorised over y).
    x0_range, w_range, v_range : pair of floats
        ⟦x_0⟧, ⟦w_k⟧ and the marginal ⟦v_k⟧ (also ⟦v_0⟧, which is unrelated to everything).
    v_given_w : callable ndarray -> (ndarray, ndarray)
        w ↦ (lo(w), hi(w)), vectorised: the conditional range ⟦v_k | w_{k−1} = w⟧.

    Raises
    ------
    TypeError, ValueError
        When a function is not callable or a range is not an interval; when ⟦v_k | w⟧ leaves ⟦v_k⟧ or
        the union over the grid of w does not cover it (law of total range (9)).

    Examples
    --------
    >>> from setsmooth.papers.rethinking_examples import rethinking_example_27
    >>> system = rethinking_example_27()
    >>> system.v_given_w(np.array([0.25]))     # ⟦v_k | w_{k−1} = 0.25⟧ = [1, 2 − 0.25]
    (array([1.]), array([1.75]))
    """

    eta: Callable
    measurement: Callable
    measurement_interval: Callable
    x0_range: tuple[float, float]
    w_range: tuple[float, float]
    v_range: tuple[float, float]
    v_given_w: Callable

    def __post_init__(self) -> None:
        for name in ("eta", "measurement", "measurement_interval", "v_given_w"):
            if not callable(getattr(self, name)):
                raise TypeError(f"{name} must be callable, got {type(getattr(self, name)).__name__}")
        for name in ("x0_range", "w_range", "v_range"):
            object.__setattr__(self, name, as_interval(getattr(self, name), name, allow_inf=False))
        self._check_law_of_total_range()

    def conditional_v(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi) of ⟦v_k | w_{k−1} = w⟧ as float arrays broadcast to w's shape."""
        lo, hi = self.v_given_w(w)
        return np.broadcast_to(np.asarray(lo, float), np.shape(w)), np.broadcast_to(np.asarray(hi, float),
                                                                                    np.shape(w))

    def _check_law_of_total_range(self, points: int = 1001) -> None:
        w = np.linspace(*self.w_range, points)
        lo, hi = self.conditional_v(w)
        v_lo, v_hi = self.v_range
        slack = tol_policy.scaled(tol_policy.MEMBERSHIP_TOL, max(abs(v_lo), abs(v_hi)))
        bad = ~np.isfinite(lo) | ~np.isfinite(hi) | (lo > hi)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(f"v_given_w({w[i]:g}) = [{lo[i]:g}, {hi[i]:g}] is not an interval")
        outside = (lo < v_lo - slack) | (hi > v_hi + slack)
        if outside.any():
            i = int(np.argmax(outside))
            raise ValueError(
                f"v_given_w({w[i]:g}) = [{lo[i]:g}, {hi[i]:g}] leaves the marginal range v_range = "
                f"[{v_lo:g}, {v_hi:g}]: by the law of total range (rethinking (9)) every conditional range "
                f"⟦v_k | w_(k-1)⟧ lies inside ⟦v_k⟧")
        if lo.min() > v_lo + slack or hi.max() < v_hi - slack:
            raise ValueError(
                f"the conditional ranges v_given_w(w), w in w_range, cover only [{lo.min():g}, {hi.max():g}]"
                f", not v_range = [{v_lo:g}, {v_hi:g}]: by the law of total range (rethinking (9)) their "
                "union is the marginal ⟦v_k⟧")

    def simulate(self, T: int, rng: np.random.Generator, runs: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """True states and measurements of ``runs`` independent runs, k = 0..T (vectorised over runs).

        x_0, w_k and v_0 are uniform on their ranges and v_k uniform on ⟦v_k | w_{k−1}⟧ (rethinking
        Section IV: 'uniformly distributed in their ranges/conditional ranges').

        Returns
        -------
        xs, ys : ndarray, shape (runs, T+1)
        """
        check_rng(rng)
        T, runs = check_dim(T + 1, "T + 1") - 1, check_dim(runs, "runs")
        xs = np.empty((runs, T + 1))
        vs = np.empty((runs, T + 1))
        xs[:, 0] = rng.uniform(*self.x0_range, runs)
        vs[:, 0] = rng.uniform(*self.v_range, runs)
        for k in range(1, T + 1):
            w = rng.uniform(*self.w_range, runs)
            xs[:, k] = self.eta(xs[:, k - 1]) + w
            lo, hi = self.conditional_v(w)
            vs[:, k] = lo + (hi - lo) * rng.random(runs)
        return xs, self.measurement(xs, vs)
