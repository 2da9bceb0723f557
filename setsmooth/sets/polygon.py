"""Convex polygons: the exact sets of 2-D polytope estimation in closed form, sound in floating point.

In the plane every set of the linear smoothing recursion (smoothing paper Algorithm 1: linear maps,
Minkowski sums with polytopes, intersections with half-planes and preimages of polygons) is a convex
polygon, computable in closed form: vertex images, vertex sums, clipping. `Polygon` carries the
rounding of those computations in a pad, so that every stored polygon *contains* the exact set and
exceeds it only at rounding level; its support values and interval hulls are therefore certified
(true upper bounds) without any solver.
"""

from __future__ import annotations

from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .._validation import as_matrix, real_number
from . import _matrices as mx
from . import _polygon_geometry as geo
from .base import ConvexSet
from .box import Box
from .empty import EmptySet
from .hpolytope import HPolytope
from .vpolytope import VPolytope
from .zonotope import Zonotope

U = geo.U


class Polygon(ConvexSet):
    """The convex polygon conv(vertices) ⊕ B₂(pad) ⊂ ℝ², with closed-form, floating-point-sound algebra.

    ``pad`` is a Euclidean radius ≥ 0 charged by the closed forms with a rigorous bound on their
    rounding: each operation returns a polygon containing the exact result of the operation on the
    exact operand, larger only at rounding level, so hulls agree with the exact constrained-zonotope
    path to ~1e-12 relative. A Euclidean rather than a box pad, because rotations (‖A‖₂ = 1 but
    ‖A‖∞ up to √2) must not grow it.

    Error analysis (unit roundoff u = 2⁻⁵³; `setsmooth.sets._polygon_geometry`):

    * vertices are kept as a certified hull: a point, a segment, or a chain whose every turn is
      certainly counter-clockwise (orientation determinants beyond Shewchuk's error bound), so the
      chain is exactly the boundary of conv(vertices); points dropped as nearly collinear are charged
      an upper bound of their distance to the hull;
    * linear map by a 2×2 M (singular too): vertices M v, pad ‖M‖₂·pad (an upper bound of the
      spectral norm) + the rounding of M v (≤ 3u|M||v| per coordinate);
    * Minkowski sum: the hull of all vertex sums, pads added, + u|v + w|;
    * intersection with a half-plane aᵀx ≤ h: the vertex part is clipped by aᵀx ≤ h + ‖a‖₂·pad;
      a vertex is dropped only when certainly outside, and crossing points are computed with the
      edge parameter moved outward by its error bound (`_polygon_geometry.clip`);
    * generalized intersection {x ∈ P : R x ∈ Y}: Y's half-planes N y ≤ h (for a polygon Y: the edge
      normals with offsets the maximum over all vertices, rounded up, + ‖n‖₂·pad_Y) give the
      half-planes (N R) x ≤ h + |fl(N R) − N R|·max|x| in x, the last term bounding the rounding
      of the rows over the current polygon;
    * emptiness is declared (an `EmptySet`) only when every vertex is certainly outside a half-plane;
      a `Polygon` itself is never empty.

    The pad only grows: a cut acts on the vertices, so each step of a filter adds some 20–60 u|x| and
    nothing removes it. Relative to |x| that stays at rounding level (4e-10 after 4000 steps of
    example (31)), but relative to the set's width it does not when the states sit far from the
    origin in units of the noise: at offset 1e8 with noise 1e-4, hulls 5× too wide by k = 200. The
    constrained-zonotope forms have no such drift; use them there.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        Points whose convex hull is the polygon (any order, duplicates and interior points allowed).
    pad : float
        Euclidean radius added around the hull (default 0).

    Examples
    --------
    >>> import setsmooth as ss
    >>> P = ss.Polygon([[0, 0], [2, 0], [0, 1], [1, 0.25]])
    >>> len(P.vertices), P.support([1, 1]) >= 2.0
    (3, True)
    """

    def __init__(self, vertices: Any, pad: float = 0.0):
        V = as_matrix(vertices, "vertices", cols=2)
        if np.ndim(vertices) != 2:  # no silent reshape of a flat list into one point
            raise ValueError(f"vertices must be a (k, 2) array of points, got an array of shape "
                             f"{np.shape(vertices)}")
        if V.shape[0] == 0:
            raise ValueError("vertices must hold at least one point (the empty set is EmptySet(2))")
        pad = real_number(pad, "pad")
        if not np.isfinite(pad) or pad < 0:
            raise ValueError(f"pad must be a finite number ≥ 0, got {pad}")
        self._init(*_hulled(V, pad))

    def _init(self, V: np.ndarray, pad: float) -> None:
        self.vertices = mx.readonly(np.ascontiguousarray(V, dtype=float))
        self.pad = float(pad)
        self.dim = 2

    @classmethod
    def _trusted(cls, V: np.ndarray, pad: float) -> "Polygon":
        """A polygon from a certified hull (`_polygon_geometry.certified_hull`) and its pad."""
        obj = cls.__new__(cls)
        obj._init(V, pad)
        return obj

    @classmethod
    def from_set(cls, S: ConvexSet) -> "Polygon":
        """The polygon of a 2-D set with a polytope closed form: a `Polygon`, a bounded `Box`, a
        `Zonotope` or a `VPolytope` (rounding charged to the pad, as everywhere).

        Raises
        ------
        TypeError
            For another representation or dimension.
        """
        P = _as_polygon(S)
        if P is None:
            raise TypeError(f"no polygon closed form for {type(S).__name__} of dimension {S.dim} "
                            "(Polygon, bounded Box, Zonotope or VPolytope of dimension 2)")
        return P

    def __repr__(self) -> str:
        return f"Polygon(k={len(self.vertices)}, pad={self.pad:.3g})"

    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        lam = cp.Variable(len(self.vertices), nonneg=True)
        cons = [cp.sum(lam) == 1]
        if self.pad > 0:
            b = cp.Variable(2)
            cons += [x == self.vertices.T @ lam + b, cp.norm(b, 2) <= self.pad]
        else:
            cons.append(x == self.vertices.T @ lam)
        return cons

    # -- closed forms ------------------------------------------------------------------------------
    def _support(self, D: np.ndarray, certified: bool):
        """max_j dᵀv_j + pad‖d‖₂, every rounding covered: always a certified upper bound (within a
        few ulps of the exact support), attained up to the pad at the vertex returned."""
        dots = D @ self.vertices.T
        err = 4 * U * (np.abs(D) @ np.abs(self.vertices).T) + geo.TINY
        best = np.argmax(dots, axis=1)
        values = (dots + err).max(axis=1)
        values = values + np.abs(values) * 2 * U + np.hypot(D[:, 0], D[:, 1]) * self.pad * (1 + 4 * U)
        return np.nextafter(values, np.inf), self.vertices[best].copy()

    def _is_empty(self) -> bool:
        return False

    def half_planes(self) -> tuple[np.ndarray, np.ndarray]:
        """(N, h) with the polygon ⊆ {x : N x ≤ h}, equal up to rounding (edge normals, offsets
        rounded up over all vertices plus ‖n‖₂·pad)."""
        return geo.h_form(self.vertices, self.pad)

    # -- closed-form algebra -----------------------------------------------------------------------
    def _closed_linear_map(self, M):
        M = M.toarray() if sp.issparse(M) else np.asarray(M)
        if M.shape != (2, 2):
            return NotImplemented
        V = self.vertices
        image = V @ M.T
        err = 3 * U * float((np.abs(V) @ np.abs(M).T).max()) * geo.SQRT2_UP + geo.TINY
        pad = (geo.spectral_norm_bound(M) * self.pad * (1 + 4 * U) if self.pad else 0.0) + err
        Ms = M / max(float(np.abs(M).max()), np.finfo(float).tiny)  # no overflow in the products
        if Ms[0, 0] * Ms[1, 1] < Ms[0, 1] * Ms[1, 0]:  # probably orientation-reversing: chain reversed
            image = image[::-1]
        return Polygon._trusted(*_hulled(image, geo.up(pad), ordered=True))

    def _closed_translate(self, v: np.ndarray):
        image = self.vertices + v
        err = U * float((np.abs(self.vertices) + np.abs(v)).max()) * geo.SQRT2_UP + geo.TINY
        return Polygon._trusted(*_hulled(image, geo.up(self.pad * (1 + 2 * U) + err), ordered=True))

    def _closed_sum(self, other):
        Q = _as_polygon(other)
        if Q is None:
            return NotImplemented
        sums = (self.vertices[:, None, :] + Q.vertices[None, :, :]).reshape(-1, 2)
        err = U * float(np.abs(sums).max()) * geo.SQRT2_UP * (1 + 2 * U) + geo.TINY
        return Polygon._trusted(*_hulled(sums, geo.up((self.pad + Q.pad) * (1 + 2 * U) + err)))

    def _closed_intersection(self, other):
        if other.dim != 2:
            return NotImplemented
        return self._closed_generalized_intersection(np.eye(2), other)

    def _closed_generalized_intersection(self, R, Y):
        halves = _half_planes(Y)
        if halves is None:
            return NotImplemented
        return self.cut_preimage(R.toarray() if sp.issparse(R) else np.asarray(R), *halves)

    def cut_preimage(self, R: np.ndarray, N: np.ndarray, h: np.ndarray) -> "Polygon | ConvexSet":
        """{x ∈ self : N R x ≤ h}, soundly: a Polygon containing it (up to rounding), or `EmptySet`
        when it is certainly empty. Trusted arguments: R of shape (m, 2), N of shape (r, m), h of
        shape (r,) (infinite entries are no constraint). The rows N R are computed once and their
        rounding (≤ (m + 2)u|N||R|) is charged over a bound of |x| on this polygon."""
        rows = N @ R
        row_err = (N.shape[1] + 2) * U * (np.abs(N) @ np.abs(R)) + geo.TINY
        return _clip_all(self.vertices, self.pad, rows, h, row_err)

    def _closed_reflected_generalized_intersection(self, S, R):
        """{s ∈ S : R s ∈ self} for a 2-D S with a polygon form (a Box, a Zonotope)."""
        P = _as_polygon(S)
        if P is None or S is P:
            return NotImplemented
        return P._closed_generalized_intersection(R, self)


def _hulled(points: np.ndarray, pad: float, ordered: bool = False) -> tuple[np.ndarray, float]:
    """A certified hull of ``points`` and the pad plus its charge. ``ordered``: the points are
    probably already a convex counter-clockwise chain (a clip, a map with det > 0, a translation),
    kept as they are when `is_certified_chain` proves it."""
    if ordered and geo.is_certified_chain(points):
        return points, pad
    V, charge = geo.certified_hull(points)
    return V, geo.up(pad + charge) if charge else pad


def _clip_all(V: np.ndarray, pad: float, rows: np.ndarray, h: np.ndarray, row_err: np.ndarray):
    """conv(V) ⊕ B₂(pad) cut by the exact half-planes r_iᵀx ≤ h_i, of which ``rows`` are the computed
    normals with |fl(r_i) − r_i| ≤ row_err_i: a Polygon containing the exact cut, or `EmptySet` when
    a cut certainly leaves nothing. The rows' rounding is charged over a bound of |x| on the
    polygon before the cuts (the result lies inside it)."""
    x_bound = np.abs(V).max(axis=0) + pad
    slack = row_err @ x_bound
    norms = np.hypot(rows[:, 0], rows[:, 1])
    finite = np.isfinite(h)
    rows, h, slack, norms = rows[finite], h[finite], slack[finite], norms[finite]
    # Half-planes that no vertex certainly violates leave the polygon as it is (skipping a cut is
    # always sound): one product decides which ones to clip by.
    values = V @ rows.T - (h + slack + norms * pad)
    errors = 4 * U * (np.abs(V) @ np.abs(rows).T + np.abs(h) + slack + norms * pad) + geo.TINY
    for idx in np.flatnonzero(np.any(values > errors, axis=0)):
        hi, sl, nr = h[idx], slack[idx], norms[idx]
        offset = hi + sl + nr * pad * (1 + 4 * U)
        offset = geo.up(offset + (abs(hi) + sl + nr * pad) * 4 * U)
        cut, charge = geo.clip(V, rows[idx], offset)
        if cut is None:
            return EmptySet(2)
        if cut is not V:
            V, pad = _hulled(cut, geo.up(pad + charge), ordered=True)
    return Polygon._trusted(V, pad)


def half_planes(Y: ConvexSet) -> tuple[np.ndarray, np.ndarray] | None:
    """(N, h) with Y ⊆ {y : N y ≤ h}: exactly for a `Box` or an `HPolytope` (any dimension), up to
    rounding for a 2-D set with a polygon form; None for other sets."""
    return _half_planes(Y)


def as_polygon(S: ConvexSet) -> Polygon | None:
    """The `Polygon` of a 2-D set with a polygon closed form (see `Polygon.from_set`), else None."""
    return _as_polygon(S)


def _half_planes(Y: ConvexSet):
    """(N, h) with Y ⊆ {y : N y ≤ h} exactly (Box, HPolytope) or up to rounding (polygons), or None."""
    if isinstance(Y, HPolytope):
        return Y.H, Y.k
    if isinstance(Y, Box):
        H = Y.to_hpolytope()
        return H.H, H.k
    P = _as_polygon(Y)
    return None if P is None else P.half_planes()


def _as_polygon(S: ConvexSet) -> Polygon | None:
    """The polygon of a 2-D Polygon, bounded Box, Zonotope or VPolytope (sound), else None."""
    if isinstance(S, Polygon):
        return S
    if S.dim != 2:
        return None
    # Sets are immutable: the conversion is kept on the set (a system's constant noise images are
    # converted once per data set, not once per step), and not pickled (ConvexSet._DERIVED).
    cached = S.__dict__.get("_polygon_form")
    if cached is None:
        cached = _convert(S)
        if cached is not None:
            S.__dict__["_polygon_form"] = cached
    return cached


def _convert(S: ConvexSet) -> Polygon | None:
    if isinstance(S, Box):
        if not S.is_bounded:
            return None
        lo, hi = S.lo, S.hi
        corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        return Polygon._trusted(*_hulled(corners, 0.0))
    if isinstance(S, VPolytope):
        return Polygon._trusted(*_hulled(np.asarray(S.points, dtype=float), 0.0))
    if isinstance(S, Zonotope):
        return _zonotope_polygon(np.asarray(S.G, dtype=float), np.asarray(S.c, dtype=float))
    return None


def _zonotope_polygon(G: np.ndarray, c: np.ndarray) -> Polygon:
    """The 2-D zonotope c + G[−1, 1]^ng: its boundary walks the generators sorted by angle (each
    turned into the upper half-plane) from c − Σg, adding 2g along the lower chain and subtracting
    along the upper. Charged to the pad: the partial sums' rounding (≤ (2ng + 4)u times the sum of
    the magnitudes added) and the vertices a misordered pair of generators would skip (atan2 is
    accurate to a few ulps, so only generators within ~4uπ of each other can swap, and the skipped
    vertex lies within ‖g‖·4uπ of the walk's chord for each such g)."""
    G = G[:, np.any(G != 0, axis=0)]
    flip = (G[1] < 0) | ((G[1] == 0) & (G[0] < 0))
    G = np.where(flip, -G, G)
    G = G[:, np.argsort(np.arctan2(G[1], G[0]), kind="stable")]
    steps = np.hstack([2 * G, -2 * G]).T
    start = c - G.sum(axis=1)
    walk = start + np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    magnitude = np.abs(c) + 5 * np.abs(G).sum(axis=1)
    err = (2 * G.shape[1] + 4) * U * float(magnitude.max()) * geo.SQRT2_UP + geo.TINY
    err += 8 * U * np.pi * float(np.sqrt((G * G).sum(axis=0)).sum())
    return Polygon._trusted(*_hulled(walk, geo.up(err)))
