"""Floating-point-sound primitives for `Polygon`: certified hulls, clipping, and their error charges.

Every function works on an (k, 2) array of points and returns, besides its result, a nonnegative
*charge* c: a Euclidean distance such that the exact result is contained in conv(result) ⊕ B₂(c).
The callers add charges to the polygon's pad, so a stored polygon always contains the exact set.

Error model: IEEE double, unit roundoff u = 2⁻⁵³, round to nearest. A sum or product of two
computed numbers has relative error ≤ u; the bounds below (Higham's γ_n = nu/(1 − nu), written
generously as a small multiple of u) bound the error of short dot products and orientation
determinants by that multiple of the sum of the absolute values of their terms, plus ``TINY`` for
underflow. Orientation signs are decided only when the computed determinant exceeds its error
bound (Shewchuk's static filter, ccwerrboundA = 3u + 16u², here 8u): a chain whose turns all pass
is exactly (in real arithmetic, on the stored floats) a strictly convex counter-clockwise polygon.
"""

from __future__ import annotations

import math

import numpy as np

from ..floating import U

#: Absolute slack for underflow in products of tiny numbers.
TINY = 1e-290
#: Multiple of u bounding the error of a 2-term orientation determinant or dot product.
ORIENT_ERR = 8 * U
SQRT2_UP = math.sqrt(2.0) * (1 + 4 * U)


def up(x: float) -> float:
    """A float ≥ x: x rounded once more upward (covers the last rounding of a nonnegative bound)."""
    return float(np.nextafter(x, np.inf))


def _certainly_left(ox: float, oy: float, ax: float, ay: float, bx: float, by: float) -> bool:
    """Whether the turn o → a → b is certainly counter-clockwise (exact determinant > 0)."""
    left = (ax - ox) * (by - oy)
    right = (ay - oy) * (bx - ox)
    return left - right > ORIENT_ERR * (abs(left) + abs(right)) + TINY


def certified_hull(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Vertices of a polygon containing conv(points) up to a charge, and the charge.

    Returns (H, c): H is one point, two distinct points, or a chain whose every cyclic turn is
    certified counter-clockwise (`_certainly_left`), so conv(H) is exactly the polygon H bounds; and
    conv(points) ⊆ conv(H) ⊕ B₂(c). Points that the monotone chain drops because a turn could not be
    certified (nearly collinear or duplicate points) are charged their distance to H, bounded from
    above by the distance to the nearest edge segment unless they are certified inside H.
    """
    rows = sorted(set(map(tuple, points.tolist())))  # lexicographic, exact duplicates removed
    pts = np.array(rows, dtype=float).reshape(-1, 2)
    if len(rows) <= 2:
        return pts, 0.0
    lower: list[int] = []
    for i, (px, py) in enumerate(rows):
        while len(lower) >= 2 and not _certainly_left(*rows[lower[-2]], *rows[lower[-1]], px, py):
            lower.pop()
        lower.append(i)
    upper: list[int] = []
    for i in range(len(rows) - 1, -1, -1):
        px, py = rows[i]
        while len(upper) >= 2 and not _certainly_left(*rows[upper[-2]], *rows[upper[-1]], px, py):
            upper.pop()
        upper.append(i)
    chain = lower[:-1] + upper[:-1]
    # The junctions (leftmost, rightmost point) were not tested by the chain: drop any vertex whose
    # cyclic turn cannot be certified, until all pass or two points remain.
    changed = True
    while changed and len(chain) >= 3:
        changed = False
        for j in range(len(chain)):
            o, a, b = rows[chain[j - 1]], rows[chain[j]], rows[chain[(j + 1) % len(chain)]]
            if not _certainly_left(*o, *a, *b):
                # o, a, b are nearly collinear: drop the one between the other two (a itself, or
                # at a hairpin, a needle's tip, the neighbour nearer to a), not an end of the needle.
                del chain[_middle_of(j, o, a, b) % len(chain)]
                changed = True
                break
    H = pts[chain]
    keep = np.zeros(len(pts), dtype=bool)
    keep[chain] = True
    return H, distance_bound(pts[~keep], H)


def _middle_of(j: int, o: tuple, a: tuple, b: tuple) -> int:
    """Chain index (j − 1, j or j + 1) of the point of the nearly collinear o, a, b lying between
    the other two: the one off the farthest pair (the choice affects the charge only, never soundness)."""
    def far(p, q):
        return abs(p[0] - q[0]) + abs(p[1] - q[1])

    ob, oa, ab = far(o, b), far(o, a), far(a, b)
    if ob >= oa and ob >= ab:
        return j
    return j - 1 if ab >= oa else j + 1


def is_certified_chain(V: np.ndarray) -> bool:
    """Whether the cyclic sequence V (≥ 3 points) is exactly a strictly convex counter-clockwise
    polygon: every turn certainly left (`_certainly_left`'s bound, vectorized) and the sequence
    bitonic in lexicographic order (one increasing and one decreasing run, exact float comparisons),
    so it turns once around: a closed chain of left turns that turns once is convex."""
    if len(V) < 3:
        return False
    k = len(V)
    prev, nxt = V[np.arange(-1, k - 1)], V[np.arange(1, k + 1) % k]
    left = (V[:, 0] - prev[:, 0]) * (nxt[:, 1] - prev[:, 1])
    right = (V[:, 1] - prev[:, 1]) * (nxt[:, 0] - prev[:, 0])
    if not np.all(left - right > ORIENT_ERR * (np.abs(left) + np.abs(right)) + TINY):
        return False
    up_x = (nxt[:, 0] > V[:, 0]) | ((nxt[:, 0] == V[:, 0]) & (nxt[:, 1] > V[:, 1]))
    return int(np.count_nonzero(up_x != up_x[np.arange(-1, k - 1)])) == 2


def distance_bound(P: np.ndarray, H: np.ndarray) -> float:
    """An upper bound on max_p dist(p, conv(H)) over the rows p of P (0 when P is empty).

    H is a point, a segment or a certified convex counter-clockwise chain. A point certified inside
    (every edge's orientation test certainly ≥ 0) costs 0; any other point costs its computed distance
    to the nearest edge segment, enlarged by the rounding of that computation. The segment point used
    is a + t(b − a) for a computed t clamped to [0, 1], a point of conv(H) whatever t's error, so the
    exact distance to it bounds dist(p, conv(H)) from above.
    """
    if len(P) == 0:
        return 0.0
    if len(H) == 1:
        A, B = H, H
    else:
        A, B = H, H[np.arange(1, len(H) + 1) % len(H)]
        if len(H) == 2:
            A, B = H[:1], H[1:]
    cost = np.full(len(P), np.inf)
    if len(H) >= 3:
        ex, ey = (B - A).T
        px, py = P[:, :1] - A[:, 0], P[:, 1:] - A[:, 1]
        left, right = ex * py, ey * px
        inside = np.all(left - right >= ORIENT_ERR * (np.abs(left) + np.abs(right)) + TINY, axis=1)
        cost[inside] = 0.0
    todo = np.isinf(cost)
    if todo.any():
        Q = P[todo]
        E = B - A
        length2 = (E * E).sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = ((Q[:, None, :] - A[None]) * E[None]).sum(axis=2) / length2
        t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)
        S = A[None] + t[..., None] * E[None]
        dist = np.hypot(Q[:, None, 0] - S[..., 0], Q[:, None, 1] - S[..., 1])
        scale = (np.abs(Q).max(axis=1)[:, None] + np.abs(A).max(axis=1)[None] + np.abs(B).max(axis=1)[None])
        bound = dist * (1 + 8 * U) + 8 * U * scale + TINY
        cost[todo] = bound.min(axis=1)
    worst = float(cost.max())
    return up(worst) if worst > 0 else 0.0


def clip(H: np.ndarray, a: np.ndarray, h: float) -> tuple[np.ndarray | None, float]:
    """conv(H) ∩ {x : aᵀx ≤ h}, soundly: (vertices, charge), or (None, 0) when certainly empty.

    H is a point, a segment or a certified convex chain. A vertex is dropped only when it is
    certainly outside (computed aᵀv − h above its error bound); every vertex exactly inside is kept.
    On an edge from a kept vertex i to a dropped vertex j the exact crossing v_i + t(v_j − v_i) has
    t = α/(α + β) with α = h − aᵀv_i ≥ 0, β = aᵀv_j − h > 0; the point is computed with t rounded
    outward (α from above, β from below, the quotient enlarged and clamped to [0, 1]), so the exact
    crossing lies between v_i and the exact new point, and the rounding of the new point is charged.
    The result is conv(kept ∪ new points) ⊇ conv(H) ∩ {aᵀx ≤ h} up to the charge (exactly, since the
    chain is the boundary of conv(H)), in the chain's cyclic order (a crossing follows the vertex its
    edge starts at). Re-certify it (`is_certified_chain`, else `certified_hull`).
    """
    absH = np.abs(H)
    s = H @ a - h
    err = 4 * U * (absH @ np.abs(a) + abs(h)) + TINY
    out = s > err
    if out.all():
        return None, 0.0
    if not out.any():
        return H, 0.0
    k = len(H)
    if k == 2:
        pairs_i, pairs_j, at = np.array([0, 1]), np.array([1, 0]), np.array([0, 0])
    else:
        start = np.arange(k)
        end = (start + 1) % k
        # An edge crossed from either side: the new point sits after the edge's first vertex.
        pairs_i, pairs_j, at = (np.concatenate(p) for p in ((start, end), (end, start), (start, start)))
    cross = ~out[pairs_i] & out[pairs_j]
    i, j = pairs_i[cross], pairs_j[cross]
    alpha = np.maximum(-s[i], 0.0) + err[i]
    beta = s[j] - err[j]                       # > 0: j is certainly outside
    t = np.minimum(alpha / (alpha + beta) * (1 + 8 * U), 1.0)
    new = H[i] + t[:, None] * (H[j] - H[i])
    charge = SQRT2_UP * float((6 * U * (absH[i] + absH[j])).max()) + TINY
    order = np.argsort(np.concatenate([2 * np.flatnonzero(~out), 2 * at[cross] + 1]), kind="stable")
    return np.vstack([H[~out], new])[order], up(charge)


def h_form(V: np.ndarray, pad: float) -> tuple[np.ndarray, np.ndarray]:
    """Half-planes (N, h) with conv(V) ⊕ B₂(pad) ⊆ {x : N x ≤ h}, tight up to rounding.

    Normals are the outward edge normals of a certified convex chain (plus the caps of a segment,
    the axes for a point); each offset is the maximum over *all* vertices, rounded upward, plus
    ‖n‖₂·pad, so the half-planes hold whatever rounding did to the normals.
    """
    k = len(V)
    if k == 1:
        N = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    else:
        E = V[np.arange(1, k + 1) % k] - V
        if k == 2:
            E = E[:1]
            N = np.vstack([E[:, ::-1] * [1.0, -1.0], E[:, ::-1] * [-1.0, 1.0], E, -E])
        else:
            N = E[:, ::-1] * [1.0, -1.0]
    dots = N @ V.T
    err = 4 * U * (np.abs(N) @ np.abs(V).T) + TINY
    h = (dots + err).max(axis=1) + np.hypot(N[:, 0], N[:, 1]) * pad * (1 + 4 * U)
    return N, np.nextafter(h + np.abs(h) * 2 * U + TINY, np.inf)


def spectral_norm_bound(A: np.ndarray) -> float:
    """An upper bound on ‖A‖₂ of a 2×2 matrix: σ² = (F + √(F² − 4 det²))/2 with F = ‖A‖_F², each
    rounding covered (the cancellation in F² − 4det² by an absolute term). A is first scaled by a
    power of two (exactly) so that its largest entry lies in [1/2, 1): F² can neither overflow nor
    underflow."""
    top = float(np.abs(A).max())
    if top == 0.0:
        return 0.0
    e = math.frexp(top)[1]
    A = np.ldexp(A, -e)
    F = float((A * A).sum())
    det = float(A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0])
    det_err = 4 * U * float(abs(A[0, 0] * A[1, 1]) + abs(A[0, 1] * A[1, 0]))
    det_lo = max(abs(det) - det_err, 0.0)
    disc = max(F * F - 4 * det_lo * det_lo, 0.0) + 16 * U * F * F
    sigma2 = (F * (1 + 4 * U) + math.sqrt(disc) * (1 + 4 * U)) / 2 * (1 + 4 * U)
    return up(math.ldexp(up(math.sqrt(sigma2) * (1 + 4 * U) + TINY), e))
