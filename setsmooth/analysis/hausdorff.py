"""Estimation gaps (stability paper Definition 3, (9)–(10)) and diameters of convex polytopes.

The Hausdorff distance d_H(S, T) = max{sup_{s∈S} dist(s, T), sup_{t∈T} dist(t, S)}. For convex
polytopes dist(·, T) is convex, so its supremum over S is attained at a vertex of S: the exact
distance is a maximum over the vertices of each set of the distance to the other *set*. Two routes:

- in 2-D both polygons come from `vertices_2d`, and the distance from a vertex to the other polygon
  is closed-form plane geometry (zero inside; otherwise the nearest point of an edge, in the 2- or
  ∞-norm) — no solver in the loop;
- in higher dimension the vertices must be enumerable (box corners up to dimension 12), and each
  distance is one closest-point program (`ConvexSet.center(method='closest')`: a QP in the 2-norm,
  an LP in the ∞-norm).

`vertex_hausdorff_surrogate` is the authors' curve in Figs. 2–3: the vertex-to-vertex distance
max_a min_b ‖a − b‖₂, symmetrized; it is an upper bound on d_H and equals it when the nearest points
happen to be vertices.
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np

__all__ = ["hausdorff_distance", "vertex_hausdorff_surrogate", "polytope_vertices", "diameter",
           "point_polygon_distance"]

_MAX_CORNER_DIM = 12


def _norm_order(norm: Any) -> float:
    if isinstance(norm, str) and norm.lower() == "inf":
        return math.inf
    if norm in (2, 2.0):
        return 2.0
    if norm == math.inf:
        return math.inf
    raise ValueError(f"norm must be 2 or inf, got {norm!r}")


def _is_vertex_array(S) -> bool:
    return isinstance(S, (np.ndarray, list, tuple))


def _as_polygon(S) -> np.ndarray:
    V = np.asarray(S, dtype=float)
    if V.size == 0:
        return V.reshape(0, 2)
    if V.ndim != 2 or V.shape[1] not in (1, 2):
        raise ValueError("a vertex array must have shape (k, 1) or (k, 2) (a polygon's vertices, "
                         f"counter-clockwise as from vertices_2d), got {V.shape}")
    return V


def polytope_vertices(S) -> np.ndarray:
    """Vertices of a bounded polytopic set, shape (k, dim): 1-D interval ends, 2-D polygon, box corners.

    A vertex array (shape (k, 1) or (k, 2), a polygon counter-clockwise as `vertices_2d` gives it) is
    returned as it is, so that a polygon computed once can be passed to every function here.

    Raises
    ------
    NotImplementedError
        For other sets of dimension > 2 (vertex enumeration is not attempted).
    ValueError
        When the set is empty.
    """
    from ..sets import Box
    if _is_vertex_array(S):
        return _as_polygon(S)
    if S.is_empty():
        raise ValueError("the set is empty: it has no vertices")
    if S.dim == 1:
        hull = S.interval_hull()
        return np.array([hull.lo, hull.hi]) if hull.hi[0] > hull.lo[0] else np.array([hull.lo])
    if S.dim == 2:
        return np.asarray(S.vertices_2d(), dtype=float)
    if isinstance(S, Box) and S.is_bounded and S.dim <= _MAX_CORNER_DIM:
        return np.array([[S.hi[i] if bit else S.lo[i] for i, bit in enumerate(bits)]
                         for bits in itertools.product((0, 1), repeat=S.dim)])
    raise NotImplementedError(f"vertex enumeration of a {type(S).__name__} in dimension {S.dim} is not "
                              "available (2-D sets and boxes only)")


def _dim(S) -> int:
    return _as_polygon(S).shape[1] if _is_vertex_array(S) else S.dim


def _empty(S) -> bool:
    return len(_as_polygon(S)) == 0 if _is_vertex_array(S) else S.is_empty()


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray, order: float) -> float:
    """min_{λ∈[0,1]} ‖p − a − λ(b − a)‖ in the 2- or ∞-norm, in closed form."""
    e = b - a
    r = p - a
    if order == 2.0:
        ee = float(e @ e)
        lam = 0.0 if ee == 0.0 else min(1.0, max(0.0, float(r @ e) / ee))
        return float(np.linalg.norm(r - lam * e))
    # ∞-norm: max_i |r_i − λ e_i| is convex piecewise linear in λ; its minimum over [0, 1] lies at an
    # end, where a component vanishes, or where two components cross (r_i − λe_i = ±(r_j − λe_j)).
    cands = [0.0, 1.0]
    dim = len(e)
    for i in range(dim):
        if e[i] != 0.0:
            cands.append(r[i] / e[i])
        for j in range(i + 1, dim):
            for s in (1.0, -1.0):
                den = e[i] - s * e[j]
                if den != 0.0:
                    cands.append((r[i] - s * r[j]) / den)
    return min(float(np.max(np.abs(r - lam * e))) for lam in cands if 0.0 <= lam <= 1.0)


def point_polygon_distance(p: Any, V: Any, norm: Any = 2) -> float:
    """Distance from a point to a convex polygon given by its counter-clockwise vertices (2- or ∞-norm).

    Zero when the point is inside (all edge cross products non-negative up to rounding); otherwise
    the smallest distance to an edge (`_segment_distance`). A polygon of one or two vertices (a point
    or a segment) is handled as such.
    """
    order = _norm_order(norm)
    p = np.asarray(p, dtype=float)
    V = np.asarray(V, dtype=float)
    if len(V) == 1:
        return float(np.linalg.norm(p - V[0], ord=order))
    if len(V) >= 3:
        E = np.roll(V, -1, axis=0) - V
        R = p - V
        cross = E[:, 0] * R[:, 1] - E[:, 1] * R[:, 0]
        scale = np.abs(E).max() * (np.abs(R).max() + 1.0)
        if np.all(cross >= -1e-14 * scale):
            return 0.0
    pairs = zip(V, np.roll(V, -1, axis=0)) if len(V) >= 3 else [(V[0], V[1])]
    return min(_segment_distance(p, a, b, order) for a, b in pairs)


def _directed(VS: np.ndarray, T, VT: np.ndarray | None, order: float) -> float:
    """max over vertices a of S of dist(a, T)."""
    if VT is not None:
        if VT.shape[1] == 1:
            lo, hi = VT.min(), VT.max()
            return float(max(max(lo - a[0], a[0] - hi, 0.0) for a in VS))
        return max(point_polygon_distance(a, VT, order) for a in VS)
    norm = 2 if order == 2.0 else np.inf

    def dist(a: np.ndarray) -> float:
        # A member (up to the membership margin) is at distance 0; the program is kept for the rest,
        # where the optimum is away from the degenerate zero-distance face.
        if T.contains(a):
            return 0.0
        return float(np.linalg.norm(a - T.center(method="closest", reference=a, norm=norm), ord=order))

    return max(dist(a) for a in VS)


def hausdorff_distance(S, T, norm: Any = 2) -> float:
    """Exact Hausdorff distance d_H(S, T) of stability paper (10) between bounded convex polytopes.

    Parameters
    ----------
    S, T : ConvexSet or ndarray
        Bounded polytopic sets of the same dimension whose vertices `polytope_vertices` enumerates
        (1-D and 2-D sets of any representation, boxes up to dimension 12), or polygons given by
        their counter-clockwise vertices (shape (k, 2), as from `vertices_2d`).
    norm : {2, inf}
        The norm of (10).

    Returns
    -------
    float
        d_H(S, T); 0 when both are empty, ``inf`` when exactly one is empty.

    Notes
    -----
    sup_{s∈S} dist(s, T) is attained at a vertex of S (a convex function on a polytope), so
    d_H = max(max_{a ∈ vert S} dist(a, T), max_{b ∈ vert T} dist(b, S)): vertices on both sides are
    needed. In 2-D the distances are computed in closed form from the polygons; otherwise each is a
    closest-point program on the other set.

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth import analysis
    >>> S, T = ss.Box([0, 0], [1, 1]), ss.Box([0, 0], [2, 2])
    >>> round(analysis.hausdorff_distance(S, T, 2), 12), analysis.hausdorff_distance(S, T, "inf")
    (1.414213562373, 1.0)
    """
    order = _norm_order(norm)
    if _dim(S) != _dim(T):
        raise ValueError(f"S and T must have the same dimension, got {_dim(S)} and {_dim(T)}")
    empty_s, empty_t = _empty(S), _empty(T)
    if empty_s or empty_t:
        return 0.0 if (empty_s and empty_t) else math.inf
    VS, VT = polytope_vertices(S), polytope_vertices(T)
    planar = _dim(S) <= 2
    return max(_directed(VS, T, VT if planar else None, order),
               _directed(VT, S, VS if planar else None, order))


def vertex_hausdorff_surrogate(S, T, norm: Any = 2) -> float:
    """The authors' estimation-gap curve of Figs. 2–3: max_a min_b ‖a − b‖, symmetrized, over vertices.

    An upper bound on `hausdorff_distance` (each vertex's distance to the other set is at most its
    distance to that set's nearest vertex). ``inf`` when exactly one set is empty.
    """
    order = _norm_order(norm)
    empty_s, empty_t = _empty(S), _empty(T)
    if empty_s or empty_t:
        return 0.0 if (empty_s and empty_t) else math.inf
    VS, VT = polytope_vertices(S), polytope_vertices(T)
    D = np.linalg.norm(VS[:, None, :] - VT[None, :, :], ord=order, axis=2)
    return float(max(D.min(axis=1).max(), D.min(axis=0).max()))


def diameter(S, norm: Any = 2) -> float:
    """sup_{s,s'∈S} ‖s − s'‖ in the 2- or ∞-norm.

    The ∞-norm diameter is the widest edge of the interval hull (`ConvexSet.diameter`, any set); the
    2-norm diameter of a polytope is the largest distance between two of its vertices (Figs. 2–3),
    for sets `polytope_vertices` can enumerate. ``-inf`` for the empty set.
    """
    order = _norm_order(norm)
    if _empty(S):
        return -math.inf
    if order == math.inf and not _is_vertex_array(S):
        return float(S.diameter())
    V = polytope_vertices(S)
    if order == math.inf:
        return float(np.max(V.max(axis=0) - V.min(axis=0)))
    return float(np.linalg.norm(V[:, None, :] - V[None, :, :], axis=2).max())
