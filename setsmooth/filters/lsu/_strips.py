"""The vertices of a zonotope cut by a strip, without the intersection's rounding charges.

LSUO and LSUP read the small CZ Q = Z(G, c) ∩_C strip only through `sets.cz_vertices.cz_vertices`,
which reads Q's G, c, A, b, h and nothing else (no pad, no slack; the vertex ranges are widened by
`vertex_bounds`). `intersection_vertices` builds exactly those five arrays, the same operations as
`ConstrainedZonotope._generalized_intersection` (G = [G 0], A = [C G, −G_y], b = fl(c_y − C c),
h = [1; h_y]) without the rounding charges of the new rows (`rounding.linear_image`, two thirds of
the intersection's cost), which the enumeration does not use. Where the enumeration declines (too
many candidates) the filters build the full, charged Q as before and take its certified values.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...sets import rounding
from ...sets.box import Box
from ...sets.constrained_zonotope import ConstrainedZonotope
from ...sets.cz_vertices import vertices_of

__all__ = ["intersection_vertices", "box_form"]


def box_form(box: Box) -> tuple[np.ndarray, np.ndarray] | None:
    """(G, c) of a finite box's CZ form (``box._flat_cz.G``, ``.c`` bit for bit: the same
    `rounding.box_center_radius`; its pad, which the vertices do not read, is not kept); None for an
    unbounded box."""
    if not (np.all(np.isfinite(box.lo)) and np.all(np.isfinite(box.hi))):
        return None
    center, radius, _ = rounding.box_center_radius(box.lo, box.hi)
    return np.diag(radius), center


def intersection_vertices(G: np.ndarray, c: np.ndarray, C: np.ndarray,
                          strip: ConstrainedZonotope) -> np.ndarray | None:
    """``cz_vertices(generalized_intersection(Z, C, strip))`` bit for bit, for the zonotope
    Z = Z(G, c) (dense G, every factor bound 1: a `Zonotope` or a finite `Box`'s CZ form) and a
    strip without constraints (`LSUModel.strip_sets`); None where `cz_vertices` declines or the
    arguments are not of that kind (the caller then intersects in full)."""
    strip = strip._flat_cz   # a CZ is its own form; a Box's is cached on it
    if strip is None or strip.nc or sp.issparse(G) or sp.issparse(strip.G) or sp.issparse(C):
        return None
    Gy = np.asarray(strip.G)
    n, ng = G.shape
    # Q's five arrays, enumerated without building Q (its stored copies keep these C layouts).
    return vertices_of(
        np.hstack([G, np.zeros((n, Gy.shape[1]))]), np.asarray(c, dtype=float),
        np.hstack([np.asarray(C @ G), -Gy]),           # the block [[A_z, 0], [0, A_y]] above has no rows
        strip.c + -np.asarray(C @ c).reshape(-1),       # fl(c_y − C c), as rounding.sum_with_error gives it
        np.concatenate([np.ones(ng), strip.h]))
