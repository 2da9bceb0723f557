"""Point estimates and spread of a uniform density on a support (LSU paper Section 3.3, and beyond).

* Method 1, ``'interval_hull'``: x̂₁ = the centre of the interval hull of the support (Rego et al.
  2020a): 2n support values.
* Method 2, ``'closest'``: x̂₂ = the point of the support closest to the centre c of its unconstrained
  zonotope Z(G, c). We use the **∞-norm**, so it is one LP, as the paper's "linear programs" require
  (the 2-norm would be a QP), and because the ∞-ball is the shape of the interval hulls and noise
  boxes the filter works with. The paper cites "two linear programs" (Raghuraman & Koeln 2022)
  without stating them; we solve one: the lifted set
  Q = {(x, t) : x ∈ 𝕏, ‖x − c‖∞ ≤ t ≤ ρ} is itself a constrained zonotope (the cone
  |x − c| ≤ t cut at height ρ ≥ max_{x∈𝕏} ‖x − c‖∞ is a CZ with 2n slack factors), and its support
  point in direction −e_t is a closest point, on the CZ fast path — about 8× faster here than the
  general `ConvexSet.center('closest')` program, with the same distance (tested). The ∞-norm minimizer
  need not be unique; the solver's is taken. When the support's hull is known in up to three
  dimensions (LSU-CZ's supports, `summarize`), the minimum is found exactly among a few hundred
  candidate points of its boundary instead (`closest_point_of_hull`, tested against the LP), and
  ties go to the candidate nearest c in the Euclidean norm.
* ``'centroid'``: the mean of the uniform density on the support, i.e. the posterior mean of the
  LSU approximation (the Bayes estimate under squared loss). Exact from the vertex hull in low
  dimension (`sets.cz_vertices`), else the mean of hit-and-run draws.

`posterior_std` gives the standard deviations of the uniform density on the support (the "STD" we
plot for Fig. 3): closed form for boxes and parallelotopes, exact from the simplices otherwise.
"""

from __future__ import annotations

import functools
import itertools

import numpy as np
import scipy.sparse as sp

from ... import tolerances as tol
from ...sets.base import ConvexSet
from ...sets.box import Box
from ...sets.constrained_zonotope import ConstrainedZonotope
from ...sets.empty import EmptySet
from ...sets.sampling import EXACT_SAMPLING_MAX_DIM, exact_geometry, hit_and_run
from ...sets.cz_vertices import HullGeometry, cz_vertices, hull_geometry
from ...sets.zonotope import Zonotope

__all__ = ["POINT_ESTIMATES", "lsu_point_estimate", "closest_to_zonotope_center", "posterior_std"]

#: The point estimates `lsu_point_estimate` knows: Method 1, Method 2, and the centroid.
POINT_ESTIMATES = ("interval_hull", "closest", "centroid")

#: Hit-and-run draws behind the centroid of a support without an enumerable vertex set.
CENTROID_DRAWS = 2000

#: `summarize` takes Method 2 from the hull (`closest_point_of_hull`) up to this dimension: a 3-D
#: boundary triangle costs 22 small systems (~0.25 ms for a support of LSU-CZ's, ~5 ms by the LP), a
#: 4-D facet 144 and a 5-D one 816, where the LP is cheaper (measured: 2× and 35× slower than it).
CLOSEST_FROM_HULL_MAX_DIM = 3


def lsu_point_estimate(support: ConvexSet, method: str = "interval_hull",
                       rng: np.random.Generator | None = None) -> np.ndarray:
    """A point estimate from the support of a uniform posterior (LSU paper Section 3.3).

    Parameters
    ----------
    support : ConvexSet
        The support 𝕏_t of f(x_t | d(t)) (a CZ for LSU-CZ; a Box or a parallelotope for LSUO/LSUP).
    method : {'interval_hull', 'closest', 'centroid'}
        Method 1, Method 2 (∞-norm closest point to the zonotope centre; the centre itself for an
        unconstrained zonotope or box), or the centroid (exact in low dimension).
    rng : numpy.random.Generator, optional
        Needed only for a centroid that has to be sampled (no enumerable vertex set).

    Returns
    -------
    ndarray, shape (n,)
        NaN entries when the support is empty.

    Raises
    ------
    ValueError
        For an unknown ``method``, or a sampled centroid without ``rng``.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> segment = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.0])
    >>> ss.lsu_point_estimate(segment, "closest").round(6).tolist()
    [0.5, 0.5]
    >>> ss.lsu_point_estimate(ss.Box([0, 0], [1, 2]), "centroid").tolist()
    [0.5, 1.0]
    """
    if method not in POINT_ESTIMATES:
        raise ValueError(f"method must be one of {POINT_ESTIMATES}, got {method!r}")
    n = support.dim
    if isinstance(support, EmptySet):
        return np.full(n, np.nan)
    if method == "interval_hull":
        return support.center("interval_hull")
    if method == "closest":
        Z = support if isinstance(support, ConstrainedZonotope) else support._flat_cz
        if Z is None:
            raise ValueError(f"Method 2 needs a set with a zonotope centre; {type(support).__name__} "
                             "has no constrained-zonotope form")
        return closest_to_zonotope_center(Z)
    if isinstance(support, Box):
        return support.midpoint()
    if isinstance(support, Zonotope):   # centrally symmetric: the centroid is the centre
        return support.c.copy()
    geometry = exact_geometry(support)
    if geometry is not None:
        return geometry.centroid
    if rng is None:
        raise ValueError("this support has no enumerable vertex set: its centroid is sampled, pass rng")
    return hit_and_run(support, rng, CENTROID_DRAWS).mean(axis=0)


def closest_to_zonotope_center(Z: ConstrainedZonotope, reach: float | None = None) -> np.ndarray:
    """Method 2: a point of Z(G, c, A, b) closest to c in the ∞-norm (NaN when Z is empty).

    One support query of the lifted CZ Q = {(x, t) : x ∈ Z, ‖x − c‖∞ ≤ t ≤ ρ}: with e = x − c = ρη,
    t = ρ(1 + τ)/2 and slacks t ∓ e_i = ρ(1 + s±_i) (|η|, |τ|, |s±| ≤ 1; ρ bounds ‖x − c‖∞ on Z, from
    the interval hull), Q is Z × [0, ρ] intersected with that cone, and argmin t is its support
    point in direction −e_t. ``reach`` ≥ max_{x∈Z} ‖x − c‖∞ may be given (else it comes from the
    interval hull).
    """
    n = Z.dim
    if Z.nc == 0:
        return Z.c.copy()
    if reach is None:
        hull = Z.interval_hull()
        if isinstance(hull, EmptySet) or hull.is_empty():
            return np.full(n, np.nan)
        reach = float(np.max(np.maximum(hull.hi - Z.c, Z.c - hull.lo)))
    rho = reach
    if rho <= 0.0:
        return Z.c.copy()
    rho *= 2.0  # room: the cone's slacks must not bind before the distance does
    G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    ng, nc = G.shape[1], A.shape[0]
    k = ng + 1 + 2 * n                                   # factors ξ, τ, s+, s−
    Gq = np.zeros((n + 1, k))
    Gq[:n, :ng] = G
    Gq[n, ng] = rho / 2
    Aq = np.zeros((nc + 2 * n, k))
    bq = np.zeros(nc + 2 * n)
    Aq[:nc, :ng], bq[:nc] = A, Z.b
    for i in range(n):
        for sign, row, slack in ((1.0, nc + i, ng + 1 + i), (-1.0, nc + n + i, ng + 1 + n + i)):
            # t − sign·(G_i ξ) − ρ s = ρ  (the centre cancels: x − c = Gξ), divided by ρ
            Aq[row, ng] = 0.5
            Aq[row, :ng] = -sign * G[i] / rho
            Aq[row, slack] = -1.0
            bq[row] = 0.5
    Q = ConstrainedZonotope._trusted(Gq, np.concatenate([Z.c, [rho / 2]]), Aq, bq,
                                     np.concatenate([Z.h, np.ones(1 + 2 * n)]))
    point = Q.support_point(-np.eye(n + 1)[n])
    return point[:n]


def closest_point_of_hull(geometry: HullGeometry, c: np.ndarray) -> np.ndarray:
    """Method 2 from a hull cut into simplices: the point of conv(V) nearest ``c`` in the ∞-norm.

    Parameters
    ----------
    geometry : HullGeometry
        conv(V) ⊂ ℝⁿ as a fan of simplices from an interior point over its triangulated boundary.
    c : ndarray, shape (n,)
        The centre to approach (Method 2: the centre of the support's unconstrained zonotope).

    Returns
    -------
    ndarray, shape (n,)
        ``c`` itself when it lies in conv(V) (in one of the fan's simplices, its barycentric weights
        there ≥ −``VERTEX_FEASIBILITY_TOL``), else an exact minimizer of ‖x − c‖∞ over conv(V) (up to
        rounding and the weight slack of `_face_crossings`).

    Notes
    -----
    min t s.t. x ∈ conv(V), |xᵢ − cᵢ| ≤ t is an LP in (x, t) with an optimal vertex. For c outside
    conv(V), take the face F (k vertices) of the triangulated boundary with such a vertex's x in its
    relative interior: the vertex's n + 1 independent active constraints leave x the only point of
    aff(F) at which some k of the |xᵢ − cᵢ| are equal (to t), a k × k linear system in x's barycentric
    weights on F. So the minimum is among the
    boundary's vertices (k = 1) and `_face_crossings` of its faces: in 2-D the crossings of the edges
    with the diagonals x₁ − c₁ = ±(x₂ − c₂) through c; in 3-D also the crossings of the edges with the
    six planes σᵢ(xᵢ − cᵢ) = σⱼ(xⱼ − cⱼ) and of the triangles with the four diagonals through c. Every
    candidate is a convex combination of vertices, a point of conv(V), and is scored where it is, so
    the least score is the minimum whatever candidates are superfluous.

    Ties: the minimizers may form a segment or a polygon M = conv(V) ∩ (c + t*·B∞) (a face of
    conv(V) perpendicular to an axis, as LSU-CZ's zonotopic supports have), whose vertices, the LP's
    optimal vertices, are all candidates. Of the candidates scoring within the coordinates' rounding
    (``MAGNITUDE_TOL``) of the least, all points of M, the one nearest ``c`` in the Euclidean norm is
    returned (exact ties: the first enumerated). A simplex solver returns some vertex of M, which one
    depending on its pivoting; this rule depends only on V and c, and among the minimizers prefers
    those nearest c in the usual sense.
    """
    if _in_some_simplex(geometry.simplices - c):
        return c.copy()
    facets = geometry.simplices[:, 1:] - c           # the fan's bases: the boundary's (n − 1)-simplices
    candidates = np.concatenate([geometry.vertices - c]
                                + [_face_crossings(facets, k) for k in range(2, c.size + 1)])
    score = np.abs(candidates).max(axis=1)
    tie = tol.MAGNITUDE_TOL * (np.abs(geometry.vertices).max() + np.abs(c).max())
    tied = np.flatnonzero(score <= score.min() + tie)
    nearest = tied[np.argmin(np.einsum("ij,ij->i", candidates[tied], candidates[tied]))]
    return c + candidates[nearest]


def _in_some_simplex(simplices: np.ndarray) -> bool:
    """Whether the origin lies in one of ``simplices`` (s, n + 1, n): barycentric weights all ≥ −slack."""
    s, m, n = simplices.shape
    M = np.ones((s, m, m))
    M[:, :n, :] = np.transpose(simplices, (0, 2, 1))
    rhs = np.zeros(m)
    rhs[n] = 1.0
    weights = _solved(M, rhs)
    return bool(np.any(np.all(weights >= -tol.VERTEX_FEASIBILITY_TOL, axis=1)))


def _face_crossings(facets: np.ndarray, k: int) -> np.ndarray:
    """Points of the (k − 1)-faces of ``facets`` (s, n, n; coordinates relative to c) at which k chosen
    coordinates have equal magnitude with chosen signs, σᵢxᵢ = σ_{i₀}x_{i₀}, shape (p, n).

    Each face (k vertices of a facet), each k coordinates and each sign pattern (σ_{i₀} = 1; the
    opposite pattern gives the same equations) is one k × k system in the barycentric weights λ: Σλ = 1
    and the k − 1 equalities. Singular systems (a face parallel to the flat) are skipped: their
    minimum lies on a smaller face. Weights are accepted ``VERTEX_FEASIBILITY_TOL`` below 0, then
    clipped and renormalized, so every point returned is a convex combination of the face's vertices.
    """
    n = facets.shape[2]
    corners = np.array(list(itertools.combinations(range(n), k)), dtype=np.intp)
    faces = facets[:, corners].reshape(-1, k, n)                           # (f, k vertices, n)
    axes, signs = _equal_magnitude_patterns(n, k)                          # (q, k) each
    signed = faces[:, :, axes] * signs                                     # (f, k vertices, q, k)
    M = np.ones((faces.shape[0], axes.shape[0], k, k))
    M[:, :, 1:, :] = np.transpose(signed[..., 1:] - signed[..., :1], (0, 2, 3, 1))
    rhs = np.zeros(k)
    rhs[0] = 1.0
    weights = _solved(M.reshape(-1, k, k), rhs)                            # (f·q, k), NaN if singular
    ok = np.all(weights >= -tol.VERTEX_FEASIBILITY_TOL, axis=1)
    weights = np.maximum(weights[ok], 0.0)
    weights /= weights.sum(axis=1, keepdims=True)
    which = np.repeat(np.arange(faces.shape[0]), axes.shape[0])[ok]
    return np.einsum("pk,pkn->pn", weights, faces[which])


@functools.lru_cache(maxsize=16)
def _equal_magnitude_patterns(n: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Every choice of k of n coordinates (increasing) with every sign pattern whose first sign is +1:
    arrays (q, k) of coordinate indices and of signs, q = C(n, k)·2^(k−1), read-only."""
    patterns = [(axes, (1.0,) + rest) for axes in itertools.combinations(range(n), k)
                for rest in itertools.product((1.0, -1.0), repeat=k - 1)]
    axes = np.array([a for a, _ in patterns], dtype=np.intp)
    signs = np.array([s for _, s in patterns])
    axes.flags.writeable = signs.flags.writeable = False
    return axes, signs


def _solved(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solutions of the square systems M[i] x = rhs, shape (s, m); rows of NaN for singular M[i]."""
    out = np.full(M.shape[:2], np.nan)
    regular = np.linalg.det(M) != 0.0
    if regular.any():
        columns = np.broadcast_to(rhs[:, None], (int(regular.sum()), rhs.size, 1))
        out[regular] = np.linalg.solve(M[regular], columns)[..., 0]
    return out


def posterior_std(support: ConvexSet) -> np.ndarray:
    """Standard deviations of the components of x uniform on ``support``, shape (n,).

    Closed form for a box ((hi − lo)/√12) and a parallelotope c + Tξ, ξ ~ U[−1, 1]ⁿ (Cov = TTᵀ/3);
    exact second moments of the vertex hull's simplices otherwise. NaN for an empty support.

    Raises
    ------
    ValueError
        For a support with neither form nor an enumerable vertex set.
    """
    n = support.dim
    if isinstance(support, EmptySet):
        return np.full(n, np.nan)
    if isinstance(support, Box):
        return support.widths() / np.sqrt(12.0)
    if isinstance(support, Zonotope) and support.ng == n:
        G = np.asarray(support.G)
        return np.sqrt(np.sum(G * G, axis=1) / 3.0)
    geometry = exact_geometry(support)
    if geometry is None:
        raise ValueError(f"no exact posterior spread for {type(support).__name__}: it needs a "
                         "low-dimensional constrained-zonotope form with an enumerable vertex set")
    return np.sqrt(np.maximum(np.diag(geometry.covariance), 0.0))


def summarize(support: ConvexSet, methods: tuple[str, ...], std: bool,
              rng: np.random.Generator | None = None) -> tuple[dict[str, np.ndarray], np.ndarray | None]:
    """The point estimates ``methods`` and (if ``std``) the spread of one support, sharing the work.

    A CZ support with an enumerable vertex set (`sets.cz_vertices.cz_vertices`; always, at the paper's
    complexity maxima) gives Method 1 (the exact interval hull from its vertices), the centroid, the
    spread and, up to ``CLOSEST_FROM_HULL_MAX_DIM``, Method 2 (`closest_point_of_hull`) from one vertex
    enumeration and one hull, without an LP; in more dimensions Method 2 is one LP.
    Other supports go through `lsu_point_estimate` and `posterior_std`. Returns (None, None) for an
    empty support.
    """
    if isinstance(support, EmptySet):
        return None, None
    Z = support if isinstance(support, ConstrainedZonotope) else None
    V = cz_vertices(Z) if Z is not None and support.dim <= EXACT_SAMPLING_MAX_DIM else None
    if V is not None and V.shape[0] == 0:
        return None, None
    if V is None:
        if support.interval_hull().is_empty():
            return None, None
        out = {m: lsu_point_estimate(support, m, rng) for m in methods}
        return out, (posterior_std(support) if std else None)
    lo, hi = V.min(axis=0), V.max(axis=0)
    closest_from_hull = "closest" in methods and support.dim <= CLOSEST_FROM_HULL_MAX_DIM
    geometry = hull_geometry(V) if ("centroid" in methods or std or closest_from_hull) else None
    out = {}
    for method in methods:
        if method == "interval_hull":
            out[method] = (lo + hi) / 2
        elif method == "centroid":
            out[method] = geometry.centroid
        elif closest_from_hull:
            out[method] = closest_point_of_hull(geometry, Z.c)
        else:
            out[method] = closest_to_zonotope_center(Z, float(np.max(np.maximum(hi - Z.c, Z.c - lo))))
    spread = np.sqrt(np.maximum(np.diag(geometry.covariance), 0.0)) if std else None
    return out, spread
