"""Exact polygons of 2-D sets from support points, their areas, and plotting.

`vertices_2d` walks the boundary by support points: starting from a few directions, it queries the
outward normal of every chord between consecutive boundary points and inserts the support point
whenever it lies beyond the chord. For a polytope every inserted point is a vertex or lies on an edge,
so the walk ends with the exact polygon (collinear points are then dropped); for a curved set it stops
when every chord is within ``tol`` of the boundary or at ``max_vertices``. All chords of one round are
queried as one stacked program. Each round keeps the convex hull of the points found so far: a support
point computed to the solver's accuracy can fall a little inside the current polygon or beside the
chord it was asked for (thin sets far from the origin), and splicing it in by position would make the
walk wind round the polygon several times.

`boundary_walk` also returns the support values the walk asked for; `support_bound_2d` turns such
values into upper bounds on the support function along any direction (weak duality in the plane),
without using the support points.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .. import tolerances as tol_policy


def vertices_2d(S, tol: float | None = None, max_vertices: int = 512) -> np.ndarray:
    """Vertices of a bounded 2-D set, counter-clockwise, shape (k, 2).

    Parameters
    ----------
    S : ConvexSet
        A set with ``dim == 2``.
    tol : float, optional
        Absolute distance below which a support point counts as on a chord; defaults to
        ``VERTEX_TOL`` times the set's extent.
    max_vertices : int
        Stop refining curved boundaries beyond this many points.

    Returns
    -------
    ndarray, shape (k, 2)
        k = 0 for the empty set, 1 for a point, 2 for a segment.

    Raises
    ------
    ValueError
        If ``S.dim != 2`` or the set is unbounded.
    """
    return boundary_walk(S, tol, max_vertices)[0]


def boundary_walk(S, tol: float | None = None, max_vertices: int = 512
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`vertices_2d`'s vertices with the support values the walk asked for on the way.

    Returns
    -------
    vertices : ndarray, shape (k, 2)
        ``vertices_2d(S, tol, max_vertices)``, the same array.
    normals, values : ndarray, shapes (q, 2) and (q,)
        Every direction queried (unit rows) and the solver's support value h_S along it: each
        ``normals[i]ᵀ x ≤ values[i]`` holds on S to the solver's accuracy, whether or not the walk
        found every vertex, so `support_bound_2d` of them bounds h_S from above. Empty for the
        empty set.

    Raises
    ------
    ValueError
        As `vertices_2d`.
    """
    if S.dim != 2:
        raise ValueError(f"vertices_2d needs a 2-D set, got dim = {S.dim} (project it first)")
    if S.is_empty():
        return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0)
    angles = 2 * np.pi * (np.arange(8) + 0.1234) / 8
    D = np.column_stack([np.cos(angles), np.sin(angles)])
    values, points = S._support_points(D, "auto", False)
    if not np.isfinite(values).all():
        raise ValueError("vertices_2d needs a bounded set; this one is unbounded")
    asked, answers = [D], [values]
    extent = np.ptp(points, axis=0).max()
    eps = tol if tol is not None else tol_policy.scaled(tol_policy.VERTEX_TOL, extent)
    poly = _dedupe(_convex_hull(points), eps)
    while len(poly) >= 2 and len(poly) < max_vertices:
        nxt = np.roll(poly, -1, axis=0)
        chords = nxt - poly
        normals = np.column_stack([chords[:, 1], -chords[:, 0]])  # outward for a CCW walk
        lengths = np.linalg.norm(normals, axis=1)
        normals = normals / lengths[:, None]
        values, found = S._support_points(normals, "auto", False)
        asked.append(normals)
        answers.append(values)
        gap = values - np.einsum("ij,ij->i", normals, poly)
        grow = np.flatnonzero(gap > eps)
        if grow.size == 0:
            break
        grown = _dedupe(_convex_hull(np.vstack([poly, found[grow]])), eps)
        if len(grown) == len(poly) and np.array_equal(grown, poly):
            break   # the new points were inside to within rounding: nothing left to refine
        poly = grown
    return _drop_collinear(poly, eps), np.vstack(asked), np.concatenate(answers)


def support_bound_2d(normals: np.ndarray, values: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Upper bounds on h_S(d) for the rows d of ``D`` from support values ``values[i]`` ≥ h_S(nᵢ).

    Weak duality in the plane: d = a nᵢ + b nⱼ with a, b ≥ 0 gives dᵀx ≤ a hᵢ + b hⱼ on S, and the
    least such bound over all pairs (and over single nᵢ parallel to d) is the support of the
    polygon {x : nᵢᵀx ≤ hᵢ for all i} ⊇ S. It uses no support point, so a walk that missed part of S
    cannot make it smaller than h_S; where the walk is exact it equals h_S up to the rounding of a
    and b. ``+inf`` where no pair spans d (fewer than three directions around the circle).
    """
    N, h = np.asarray(normals, dtype=float), np.asarray(values, dtype=float)
    D = np.asarray(D, dtype=float)

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    det = cross(N[:, None, :], N[None, :, :])                       # (q, q)
    dn = cross(D[:, None, :], N[None, :, :])                        # (k, q): d × nⱼ
    with np.errstate(divide="ignore", invalid="ignore"):
        a = dn[:, None, :] / det                                    # (k, i, j): coefficient of nᵢ
        b = -dn[:, :, None] / det                                   # nᵢ × d = −(d × nᵢ)
        pair = a * h[:, None] + b * h[None, :]
        ok = (det != 0) & (a >= 0) & (b >= 0)
        bound = np.where(ok, pair, np.inf).min(axis=(1, 2), initial=np.inf)
        along = D @ N.T                                             # (k, q): d = (dᵀnᵢ) nᵢ when parallel
        single = np.where((dn == 0) & (along > 0), along * h, np.inf).min(axis=1, initial=np.inf)
    return np.minimum(bound, single)


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull (Andrew's monotone chain), collinear points dropped."""
    pts = np.unique(points, axis=0)          # sorted by x, then y
    if len(pts) <= 2:
        return pts

    def half(sequence):
        chain: list[np.ndarray] = []
        for p in sequence:
            while len(chain) >= 2 and _cross(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def _dedupe(poly: np.ndarray, eps: float) -> np.ndarray:
    """Remove cyclically consecutive points closer than eps."""
    keep = [poly[0]]
    for p in poly[1:]:
        if np.linalg.norm(p - keep[-1]) > eps:
            keep.append(p)
    if len(keep) > 1 and np.linalg.norm(keep[-1] - keep[0]) <= eps:
        keep.pop()
    return np.array(keep)


def _drop_collinear(poly: np.ndarray, eps: float) -> np.ndarray:
    changed = True
    while changed and len(poly) > 2:
        changed = False
        for i in range(len(poly)):
            a, p, b = poly[i - 1], poly[i], poly[(i + 1) % len(poly)]
            chord = b - a
            length = np.linalg.norm(chord)
            if length == 0:
                continue
            # distance of p from the line through a and b
            if abs(chord[0] * (p - a)[1] - chord[1] * (p - a)[0]) / length <= eps:
                poly = np.delete(poly, i, axis=0)
                changed = True
                break
    return poly


def polygon_area(vertices: np.ndarray) -> float:
    """Shoelace area of a simple polygon given in order (0 for fewer than 3 vertices)."""
    if len(vertices) < 3:
        return 0.0
    x, y = vertices[:, 0], vertices[:, 1]
    return float(abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2)


def plot_set(S, ax=None, dims: Sequence[int] = (0, 1), **kwargs):
    """Draw the projection of ``S`` onto ``dims`` and return the matplotlib artist.

    Keyword arguments go to `matplotlib.patches.Polygon` (``facecolor``, ``edgecolor``, ``alpha``,
    ``label`` ...). A point or a segment is drawn as a line. The empty set draws nothing and returns
    None.
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    dims = tuple(dims)
    if len(dims) != 2:
        raise ValueError(f"dims must name two coordinates (or three, for a 3-D axes), got {dims}")
    P = S if (S.dim == 2 and dims == (0, 1)) else S.project(dims)
    verts = vertices_2d(P)
    ax = plt.gca() if ax is None else ax
    if len(verts) == 0:
        return None
    if len(verts) < 3:
        line_kw = {k: v for k, v in kwargs.items() if k in ("color", "label", "alpha", "linewidth")}
        (artist,) = ax.plot(verts[:, 0], verts[:, 1], marker="o" if len(verts) == 1 else None,
                            **line_kw)
        return artist
    kwargs.setdefault("alpha", 0.4)
    artist = Polygon(verts, closed=True, **kwargs)
    ax.add_patch(artist)
    ax.update_datalim(verts)
    ax.autoscale_view()
    return artist
