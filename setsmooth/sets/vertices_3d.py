"""Exact 3-D polytopes of sets from support points, and 3-D plotting.

`vertices_3d` grows the convex hull of support points: from the 14 directions ±e_i and (±1, ±1, ±1)
it queries the outward normal of every facet of the current hull (scipy's Qhull) and adds the
support point whenever it lies beyond the facet. For a polytope every added point is on the boundary
and the loop ends with the exact hull (when no facet normal finds a point beyond it); for a curved set
it stops when every facet is within ``tol`` of the boundary or at ``max_vertices``. Flat sets (affine
dimension below 3) fall back to the 2-D walk of `vertices_2d` in their plane.
"""

from __future__ import annotations

import itertools
from typing import Sequence

import numpy as np
from scipy.spatial import ConvexHull

from .. import tolerances as tol_policy
from .vertices_2d import vertices_2d


def vertices_3d(S, tol: float | None = None, max_vertices: int = 400) -> np.ndarray:
    """Boundary points of a bounded 3-D set whose convex hull is the set (exact for polytopes).

    Parameters
    ----------
    S : ConvexSet
        A set with ``dim == 3``.
    tol : float, optional
        Absolute distance below which a support point counts as on a facet; defaults to
        ``VERTEX_TOL`` times the set's extent.
    max_vertices : int
        Stop refining curved boundaries beyond this many points.

    Returns
    -------
    ndarray, shape (k, 3)
        The vertices (k = 0 for the empty set).

    Raises
    ------
    ValueError
        If ``S.dim != 3`` or the set is unbounded.
    """
    if S.dim != 3:
        raise ValueError(f"vertices_3d needs a 3-D set, got dim = {S.dim} (project it first)")
    if S.is_empty():
        return np.zeros((0, 3))
    D = np.vstack([np.eye(3), -np.eye(3), np.array(list(itertools.product([-1.0, 1.0], repeat=3)))])
    values, points = S._support_points(D / np.linalg.norm(D, axis=1, keepdims=True), "auto", False)
    if not np.isfinite(values).all():
        raise ValueError("vertices_3d needs a bounded set; this one is unbounded")
    extent = float(np.ptp(points, axis=0).max())
    eps = tol if tol is not None else tol_policy.scaled(tol_policy.VERTEX_TOL, extent)
    points = _unique(points, eps)
    flat = _flat_basis(points, eps)
    if flat is not None:
        return _flat_vertices(S, points, *flat)
    while len(points) < max_vertices:
        hull = ConvexHull(points)
        normals, offsets = hull.equations[:, :3], -hull.equations[:, 3]
        normals, keep = np.unique(np.round(normals, 12), axis=0, return_index=True)
        values, found = S._support_points(normals, "auto", False)
        gap = values - offsets[keep]
        beyond = np.flatnonzero(gap > eps)
        if beyond.size == 0:
            break
        # Within the budget, the points farthest beyond their facets first.
        beyond = beyond[np.argsort(-gap[beyond])][: max(max_vertices - len(points), 1)]
        points = _unique(np.vstack([points, found[beyond]]), eps)
    return points[ConvexHull(points).vertices]


def _unique(points: np.ndarray, eps: float) -> np.ndarray:
    keep: list[np.ndarray] = []
    for p in points:
        if all(np.linalg.norm(p - q) > eps for q in keep):
            keep.append(p)
    return np.array(keep)


def _flat_basis(points: np.ndarray, eps: float):
    """(origin, basis) of the affine hull when it has dimension < 3, else None."""
    origin = points.mean(axis=0)
    _, sv, Vt = np.linalg.svd(points - origin)
    rank = int(np.sum(sv > eps))
    return None if rank == 3 else (origin, Vt[:rank])


def _flat_vertices(S, points: np.ndarray, origin: np.ndarray, basis: np.ndarray) -> np.ndarray:
    if basis.shape[0] == 0:
        return origin[None, :]
    if basis.shape[0] == 1:
        t = (points - origin) @ basis[0]
        return points[[np.argmin(t), np.argmax(t)]]
    plane = basis @ (S - origin)  # the set in coordinates of its plane
    return vertices_2d(plane) @ basis + origin


def faces_3d(vertices: np.ndarray, eps: float | None = None) -> list[np.ndarray]:
    """The faces of the convex hull of ``vertices`` as polygons (coplanar triangles merged, each
    face's corners ordered around its centre)."""
    hull = ConvexHull(vertices)
    scale = float(np.ptp(vertices, axis=0).max())
    eps = eps if eps is not None else tol_policy.scaled(tol_policy.VERTEX_TOL, scale)
    faces: list[np.ndarray] = []
    done = np.zeros(len(hull.equations), dtype=bool)
    for i, eq in enumerate(hull.equations):
        if done[i]:
            continue
        same = np.flatnonzero((np.abs(hull.equations[:, :3] @ eq[:3] - 1) < 1e-9)
                              & (np.abs(hull.equations[:, 3] - eq[3]) <= eps))
        done[same] = True
        corner = vertices[np.unique(hull.simplices[same])]
        centre = corner.mean(axis=0)
        u = corner[0] - centre
        u /= np.linalg.norm(u)
        w = np.cross(eq[:3], u)
        angles = np.arctan2((corner - centre) @ w, (corner - centre) @ u)
        faces.append(corner[np.argsort(angles)])
    return faces


def plot_set_3d(S, ax=None, dims: Sequence[int] = (0, 1, 2), **kwargs):
    """Draw the projection of ``S`` onto three coordinates on a 3-D axes; return the artist.

    Keyword arguments go to `mpl_toolkits.mplot3d.art3d.Poly3DCollection` (``facecolor``,
    ``edgecolor``, ``alpha``, ``label`` ...). A new 3-D axes is made on the current figure when
    ``ax`` is None or a 2-D axes is current. A flat set is drawn as one polygon, a segment or a
    point as a line; the empty set draws nothing and returns None.
    """
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    dims = tuple(dims)
    P = S if (S.dim == 3 and dims == (0, 1, 2)) else S.project(dims)
    verts = vertices_3d(P)
    if ax is None:
        current = plt.gcf().axes
        ax = current[-1] if current and current[-1].name == "3d" else plt.gcf().add_subplot(projection="3d")
    if getattr(ax, "name", None) != "3d":
        raise ValueError("plotting three coordinates needs a 3-D axes "
                         "(fig.add_subplot(projection='3d'))")
    if len(verts) == 0:
        return None
    if len(verts) < 3:
        line_kw = {k: v for k, v in kwargs.items() if k in ("color", "label", "alpha", "linewidth")}
        (artist,) = ax.plot(verts[:, 0], verts[:, 1], verts[:, 2],
                            marker="o" if len(verts) == 1 else None, **line_kw)
        return artist
    flat = _flat_basis(verts, tol_policy.scaled(tol_policy.VERTEX_TOL, float(np.ptp(verts, axis=0).max())))
    faces = [verts] if flat is not None else faces_3d(verts)
    kwargs.setdefault("alpha", 0.4)
    kwargs.setdefault("edgecolor", "0.2")
    artist = Poly3DCollection(faces, **kwargs)
    ax.add_collection3d(artist)
    ax.auto_scale_xyz(*[(verts[:, i].min(), verts[:, i].max()) for i in range(3)], had_data=True)
    return artist
