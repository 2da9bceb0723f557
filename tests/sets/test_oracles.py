"""2-D and 3-D sets against brute-force vertex enumeration with scipy, independent of setsmooth.

Zonotopes by all 2^ng sign vectors, H-polytopes by `HalfspaceIntersection`, constrained zonotopes by
the vertices of their factor polytope {ξ0 + Nt : |ξ0 + Nt| ≤ h} (N a null-space basis of A) mapped
through G, lazy sums by pairwise vertex sums and lazy intersections by stacked halfspaces. Support
values are compared over many directions, `vertices_2d` and `area` with the oracle polygons.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection

import setsmooth as ss

SEEDS = range(6)
REL = 1e-6


# -- oracles ---------------------------------------------------------------------------------------

def zonotope_points(G, c):
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=G.shape[1])))
    return signs @ G.T + c


def chebyshev_center(H, k):
    """Centre of the largest ball in {Hx ≤ k} by scipy's LP (asserts a non-empty interior)."""
    norms = np.linalg.norm(H, axis=1)
    res = linprog(np.r_[np.zeros(H.shape[1]), -1.0], A_ub=np.c_[H, norms], b_ub=k,
                  bounds=[(None, None)] * H.shape[1] + [(0, None)])
    assert res.status == 0 and res.x[-1] > 1e-9
    return res.x[:-1]


def polytope_points(H, k):
    hs = HalfspaceIntersection(np.c_[H, -k], chebyshev_center(H, k))
    return hs.intersections


def hull_halfspaces(points):
    eq = ConvexHull(points).equations
    return eq[:, :-1], -eq[:, -1]


def cz_points(G, c, A, b, h):
    """Vertices (and possibly more boundary points) of a bounded CZ with finite h."""
    xi0 = np.linalg.lstsq(A, b, rcond=None)[0]
    N = scipy.linalg.null_space(A)
    if N.shape[1] == 0:
        return (G @ xi0 + c)[None, :]
    Ht = np.vstack([N, -N])
    kt = np.concatenate([h - xi0, h + xi0])
    if N.shape[1] == 1:
        col = Ht[:, 0]
        t_hi = np.min(kt[col > 0] / col[col > 0])
        t_lo = np.max(kt[col < 0] / col[col < 0])
        ts = np.array([[t_lo], [t_hi]])
    else:
        ts = polytope_points(Ht, kt)
    return (xi0 + ts @ N.T) @ G.T + c


def oracle_support(points, D):
    return (points @ D.T).max(axis=0)


def directions(n, count=64, seed=0):
    rng = np.random.default_rng(seed)
    D = rng.standard_normal((count, n))
    return np.vstack([D, np.eye(n), -np.eye(n)])


def assert_support_matches(S, points, D):
    expected = oracle_support(points, D)
    scale = 1.0 + np.abs(expected).max()
    np.testing.assert_allclose(S.support_many(D), expected, rtol=0, atol=REL * scale)


def assert_polygon_matches(S, points):
    hull = ConvexHull(points)
    expected = points[hull.vertices]
    verts = S.vertices_2d()
    scale = 1.0 + np.abs(expected).max()
    assert len(verts) == len(expected)
    for v in verts:
        assert np.min(np.linalg.norm(expected - v, axis=1)) <= REL * scale
    assert S.area() == pytest.approx(hull.volume, rel=REL)
    x, y = verts[:, 0], verts[:, 1]
    signed = (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2
    assert signed > 0  # counter-clockwise


# -- random data -----------------------------------------------------------------------------------

def random_zonotope(rng, n):
    ng = rng.integers(n, n + 4)
    return ss.Zonotope(rng.standard_normal((n, ng)), rng.uniform(-1, 1, n))


def random_hpolytope(rng, n):
    m = rng.integers(n + 2, n + 7)
    H = rng.standard_normal((m, n))
    H = np.vstack([H, -H.sum(axis=0, keepdims=True)])  # the normals span positively: bounded
    x0 = rng.uniform(-1, 1, n)
    return ss.HPolytope(H, H @ x0 + rng.uniform(0.3, 2.0, H.shape[0]))


def random_cz(rng, n):
    ng = rng.integers(n + 1, n + 5)
    nc = rng.integers(1, ng - n + 1)
    G, A = rng.standard_normal((n, ng)), rng.standard_normal((nc, ng))
    h = rng.uniform(0.5, 1.5, ng)
    xi0 = rng.uniform(-0.7, 0.7, ng) * h
    return ss.ConstrainedZonotope(G, rng.uniform(-1, 1, n), A=A, b=A @ xi0, h=h)


def points_of(S):
    if isinstance(S, ss.Zonotope):
        return zonotope_points(S.G, S.c)
    if isinstance(S, ss.HPolytope):
        return polytope_points(S.H, S.k)
    return cz_points(S.G, S.c, S.A, S.b, S.h)


# -- tests -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("make", [random_zonotope, random_hpolytope, random_cz],
                         ids=["zonotope", "hpolytope", "cz"])
def test_support_equals_the_maximum_over_enumerated_vertices(make, seed, n):
    S = make(np.random.default_rng(seed), n)
    points = points_of(S)
    D = directions(n, seed=seed)
    assert_support_matches(S, points, D)
    generic = S.support_many(D[:12], path="generic")
    np.testing.assert_allclose(generic, oracle_support(points, D[:12]), rtol=0,
                               atol=REL * (1 + np.abs(generic).max()))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("make", [random_zonotope, random_hpolytope, random_cz],
                         ids=["zonotope", "hpolytope", "cz"])
def test_vertices_and_area_of_a_polygon_match_its_convex_hull(make, seed):
    S = make(np.random.default_rng(seed), 2)
    assert_polygon_matches(S, points_of(S))


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("seed", SEEDS)
def test_box_support_matches_its_corners(seed, n):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-2, 1, n)
    hi = lo + rng.uniform(0.1, 2, n)
    corners = np.array(list(itertools.product(*zip(lo, hi))))
    assert_support_matches(ss.Box(lo, hi), corners, directions(n, seed=seed))


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("seed", SEEDS)
def test_certified_support_of_a_cz_is_never_below_the_exact_value(seed, n):
    S = random_cz(np.random.default_rng(seed), n)
    D = directions(n, seed=seed)
    exact = oracle_support(points_of(S), D)
    certified = S.support_many(D, certified=True)
    scale = 1.0 + np.abs(exact).max()
    assert np.all(certified >= exact - 1e-10 * scale)
    assert np.all(certified <= exact + REL * scale)


@pytest.mark.parametrize("seed", SEEDS)
def test_intersection_of_zonotope_and_box_matches_halfspace_intersection(seed):
    rng = np.random.default_rng(seed)
    Z = random_zonotope(rng, 2)
    center = Z.c + 0.3 * rng.uniform(-1, 1, 2)
    B = ss.Box(center - rng.uniform(0.2, 1.0, 2), center + rng.uniform(0.2, 1.0, 2))
    X = Z & B
    assert isinstance(X, ss.ConstrainedZonotope)
    H, k = hull_halfspaces(zonotope_points(Z.G, Z.c))
    H = np.vstack([H, np.eye(2), -np.eye(2)])
    k = np.concatenate([k, B.hi, -B.lo])
    points = polytope_points(H, k)
    assert_support_matches(X, points, directions(2, seed=seed))
    assert_polygon_matches(X, points)


@pytest.mark.parametrize("seed", SEEDS)
def test_generalized_intersection_matches_halfspace_intersection(seed):
    rng = np.random.default_rng(seed)
    Z = random_zonotope(rng, 2)
    R = rng.standard_normal((1, 2))
    y = R @ Z.c
    Y = ss.Box(y - 0.5, y + rng.uniform(0.1, 1.0))
    X = Z.intersect_preimage(R, Y)
    H, k = hull_halfspaces(zonotope_points(Z.G, Z.c))
    H = np.vstack([H, R, -R])
    k = np.concatenate([k, Y.hi, -Y.lo])
    assert_support_matches(X, polytope_points(H, k), directions(2, seed=seed))


@pytest.mark.parametrize("seed", SEEDS)
def test_lazy_sum_of_hpolytope_and_zonotope_matches_pairwise_vertex_sums(seed):
    rng = np.random.default_rng(seed)
    P, Z = random_hpolytope(rng, 2), random_zonotope(rng, 2)
    S = P + Z
    assert isinstance(S, ss.MinkowskiSum)
    points = (polytope_points(P.H, P.k)[:, None, :] + zonotope_points(Z.G, Z.c)[None]).reshape(-1, 2)
    assert_support_matches(S, points, directions(2, seed=seed))
    assert_polygon_matches(S, points)


@pytest.mark.parametrize("seed", SEEDS)
def test_lazy_intersection_of_hpolytope_and_zonotope_matches_stacked_halfspaces(seed):
    rng = np.random.default_rng(seed)
    P, Z = random_hpolytope(rng, 2), random_zonotope(rng, 2)
    Z = Z + (chebyshev_center(P.H, P.k) - Z.c)
    S = P & Z
    assert isinstance(S, ss.Intersection)
    Hz, kz = hull_halfspaces(zonotope_points(Z.G, Z.c))
    points = polytope_points(np.vstack([P.H, Hz]), np.concatenate([P.k, kz]))
    assert_support_matches(S, points, directions(2, count=16, seed=seed))
    assert_polygon_matches(S, points)


@pytest.mark.parametrize("seed", SEEDS)
def test_lazy_linear_map_of_hpolytope_matches_mapped_vertices(seed):
    rng = np.random.default_rng(seed)
    P = random_hpolytope(rng, 3)
    M = rng.standard_normal((2, 3))
    S = M @ P
    assert isinstance(S, ss.LinearMap)
    points = polytope_points(P.H, P.k) @ M.T
    assert_support_matches(S, points, directions(2, seed=seed))
    assert_polygon_matches(S, points)


@pytest.mark.parametrize("seed", SEEDS)
def test_projection_of_a_3d_cz_matches_projected_vertices(seed):
    S = random_cz(np.random.default_rng(seed), 3)
    points = cz_points(S.G, S.c, S.A, S.b, S.h)[:, [2, 0]]
    assert_polygon_matches(S.project([2, 0]), points)


@pytest.mark.parametrize("seed", SEEDS)
def test_rejection_samples_lie_in_the_oracle_polygon(seed):
    rng = np.random.default_rng(seed)
    S = random_cz(rng, 2)
    H, k = hull_halfspaces(cz_points(S.G, S.c, S.A, S.b, S.h))
    samples = S.sample(rng, size=20)
    assert np.all(samples @ H.T <= k + 1e-7)


def test_ellipse_area_converges_to_pi_sqrt_det_q():
    Q = np.array([[4.0, 1.0], [1.0, 2.0]])
    E = ss.Ellipsoid([0.5, -1.0], Q)
    # A 512-gon inscribed in the ellipse: relative area defect ≈ (2π/512)²/6 ≈ 2.5e-5.
    assert E.area() == pytest.approx(np.pi * np.sqrt(np.linalg.det(Q)), rel=1e-4)
    verts = E.vertices_2d()
    inside = np.einsum("ij,jk,ik->i", verts - E.c, np.linalg.inv(Q), verts - E.c)
    np.testing.assert_allclose(inside, 1.0, atol=1e-9)
