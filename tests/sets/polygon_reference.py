"""Exact rational polygon geometry (fractions.Fraction), independent of setsmooth: the oracle the
floating-point `Polygon` is checked against. Every float is converted exactly, so these results are
the exact sets of the operations on the stored floats."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

Point = tuple[Fraction, Fraction]


def exact_points(A: np.ndarray) -> list[Point]:
    return [(Fraction(float(x)), Fraction(float(y))) for x, y in np.asarray(A, dtype=float)]


def _cross(o: Point, a: Point, b: Point) -> Fraction:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def hull(points: list[Point]) -> list[Point]:
    """Exact convex hull vertices (monotone chain, collinear points dropped), counter-clockwise."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts
    lower: list[Point] = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[Point] = []
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def linear_map(M: np.ndarray, points: list[Point]) -> list[Point]:
    (a, b), (c, d) = ((Fraction(float(v)) for v in row) for row in M)
    return hull([(a * x + b * y, c * x + d * y) for x, y in points])


def minkowski_sum(P: list[Point], Q: list[Point]) -> list[Point]:
    return hull([(p[0] + q[0], p[1] + q[1]) for p in P for q in Q])


def clip(points: list[Point], a: tuple[Fraction, Fraction], h: Fraction) -> list[Point]:
    """conv(points) ∩ {aᵀx ≤ h}: the points inside and the crossings of every (inside, outside) pair."""
    value = [a[0] * p[0] + a[1] * p[1] - h for p in points]
    inside = [p for p, s in zip(points, value) if s <= 0]
    crossings = []
    for p, sp in zip(points, value):
        for q, sq in zip(points, value):
            if sp < 0 < sq:
                t = sp / (sp - sq)
                crossings.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return hull(inside + crossings)


def preimage_cut(points: list[Point], R: np.ndarray, N: np.ndarray, h: np.ndarray) -> list[Point]:
    """conv(points) ∩ {x : N R x ≤ h}, the rows N R formed exactly."""
    Rf = [[Fraction(float(v)) for v in row] for row in np.atleast_2d(R)]
    for n_row, hi in zip(np.atleast_2d(N), h):
        nf = [Fraction(float(v)) for v in n_row]
        a = tuple(sum(nf[i] * Rf[i][j] for i in range(len(nf))) for j in range(2))
        points = clip(points, a, Fraction(float(hi)))
        if not points:
            return []
    return points


def support(points: list[Point], d: np.ndarray) -> Fraction:
    dx, dy = Fraction(float(d[0])), Fraction(float(d[1]))
    return max(dx * p[0] + dy * p[1] for p in points)


def is_strictly_convex_ccw(points: list[Point]) -> bool:
    k = len(points)
    return k <= 2 or all(_cross(points[i - 1], points[i], points[(i + 1) % k]) > 0 for i in range(k))
