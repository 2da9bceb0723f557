"""Brute-force filtering and smoothing of 2-D examples with vertex/halfspace polytopes (scipy only).

Independent of setsmooth's set algebra: Minkowski sums and linear maps by vertex enumeration and
convex hulls, intersections by stacking halfspaces and `HalfspaceIntersection`.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection


def box_vertices(lo, hi) -> np.ndarray:
    return np.array(list(itertools.product(*zip(lo, hi))), dtype=float)


def hull_halfspaces(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(H, k) with {x : Hx ≤ k} = conv(points)."""
    eq = ConvexHull(points).equations  # a·x + b ≤ 0
    return eq[:, :-1], -eq[:, -1]


def vertices(H: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Vertices of {x : Hx ≤ k} (bounded, full-dimensional)."""
    norms = np.linalg.norm(H, axis=1)
    res = linprog(np.r_[np.zeros(H.shape[1]), -1.0], A_ub=np.c_[H, norms], b_ub=k,
                  bounds=[(None, None)] * H.shape[1] + [(0, None)])
    assert res.status == 0 and res.x[-1] > 1e-9, "polytope is empty or flat"
    hs = HalfspaceIntersection(np.c_[H, -k], res.x[:-1])
    pts = hs.intersections
    return pts[ConvexHull(pts).vertices]


def minkowski_vertices(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    return (P[:, None, :] + Q[None, :, :]).reshape(-1, P.shape[1])


def brute_force_filter_and_smoother(A, B, C, w_lo, w_hi, v_lo, v_hi, x0_lo, x0_hi, ys):
    """Posterior and smoothed polytopes (as vertex arrays) for x+ = Ax + Bw, y = Cx + v, boxes."""
    W = box_vertices(w_lo, w_hi) @ B.T
    posts_h = []
    H, k = hull_halfspaces(box_vertices(x0_lo, x0_hi))
    for t, y in enumerate(ys):
        if t > 0:
            prior = minkowski_vertices(vertices(*posts_h[-1]) @ A.T, W)
            H, k = hull_halfspaces(prior)
        # C x ∈ y − V  ⇔  y − v_hi ≤ Cx ≤ y − v_lo
        H = np.vstack([H, C, -C])
        k = np.concatenate([k, y - v_lo, -(y - v_hi)])
        posts_h.append((H, k))
    T = len(ys) - 1
    smoothed_h = [None] * (T + 1)
    smoothed_h[T] = posts_h[T]
    minus_W = -W
    for t in range(T - 1, -1, -1):
        reach = minkowski_vertices(vertices(*smoothed_h[t + 1]), minus_W)
        Hr, kr = hull_halfspaces(reach)
        H, k = posts_h[t]
        smoothed_h[t] = (np.vstack([H, Hr @ A]), np.concatenate([k, kr]))
    return [vertices(*p) for p in posts_h], [vertices(*s) for s in smoothed_h]
