"""V-polytopes (exactly CZs) and the Chebyshev ball of a CZ, against scipy: convex hulls, LPs."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import setsmooth as ss
from tests.sets.test_oracles import chebyshev_center, cz_points, directions, zonotope_points

SEEDS = range(6)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", [2, 3])
def test_vpolytope_closed_forms_and_cz_form_agree_with_the_points(seed, n):
    rng = np.random.default_rng(seed)
    pts = rng.standard_normal((9, n)) + rng.standard_normal(n) * 5
    P = ss.VPolytope(pts)
    D = directions(n, seed=seed)
    exact = (pts @ D.T).max(axis=0)
    np.testing.assert_allclose(P.support_many(D), exact, rtol=0, atol=1e-12)
    cz = P.to_constrained_zonotope()
    np.testing.assert_allclose(cz.support_many(D), exact, atol=1e-7)
    np.testing.assert_allclose(cz.support_many(D, certified=True), exact, atol=1e-7)
    assert np.all(cz.support_many(D, certified=True) >= exact - 1e-12)
    np.testing.assert_allclose(P.support_many(D, path="generic"), exact, atol=1e-6)
    hull = P.interval_hull()
    np.testing.assert_allclose(hull.lo, pts.min(axis=0))
    np.testing.assert_allclose(hull.hi, pts.max(axis=0))
    # membership: a convex combination is in, a point beyond a facet is out
    w = rng.dirichlet(np.ones(9))
    assert w @ pts in P
    eq = ConvexHull(pts).equations[0]
    beyond = pts[ConvexHull(pts).simplices[0]].mean(axis=0) + 1e-4 * eq[:-1]
    assert beyond not in P and not cz.contains(beyond)


def test_vpolytope_algebra_stays_a_vpolytope_and_matches_the_cz_algebra():
    P = ss.VPolytope([[0, 0], [2, 0], [0, 1], [0.5, 0.2]])
    M = np.array([[1.0, 2.0], [0.5, -1.0]])
    D = directions(2)
    assert isinstance(M @ P, ss.VPolytope) and isinstance(P + [1.0, 2.0], ss.VPolytope)
    Q = ss.VPolytope([[0, 0], [1, 1], [1, -1]])
    assert isinstance(P + Q, ss.VPolytope)
    np.testing.assert_allclose((P + Q).support_many(D),
                               (P.to_constrained_zonotope() + Q.to_constrained_zonotope()).support_many(D),
                               atol=1e-7)
    np.testing.assert_allclose((M @ P).support_many(D), P.support_many(D @ M), atol=1e-12)
    assert P.area() == pytest.approx(1.0, abs=1e-12)
    assert (P & ss.Box([0, 0], [1, 1])).area() == pytest.approx(ConvexHull(
        [[0, 0], [1, 0], [1, 0.5], [0, 1]]).volume, abs=1e-6)


def test_vpolytope_is_immutable_and_pickles():
    import pickle

    P = ss.VPolytope([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    P.contains([0.2, 0.2])  # caches derived data, which must not travel
    Q = pickle.loads(pickle.dumps(P))
    assert Q.support([1.0, 1.0]) == 1.0 and not Q.points.flags.writeable
    with pytest.raises(ValueError):
        P.points[0, 0] = 5.0


def test_vpolytope_refuses_bad_points():
    with pytest.raises(ValueError, match="at least one point"):
        ss.VPolytope(np.zeros((0, 2)))
    with pytest.raises(ValueError, match="points"):
        ss.VPolytope([[0.0, np.nan]])


@pytest.mark.parametrize("seed", SEEDS)
def test_chebyshev_ball_of_a_2d_cz_is_the_lp_ball_of_its_polygon(seed):
    rng = np.random.default_rng(seed)
    while True:
        Z = ss.ConstrainedZonotope(rng.standard_normal((2, 5)), rng.standard_normal(2),
                                   rng.standard_normal((1, 5)), rng.uniform(-0.3, 0.3, 1))
        if not Z.is_empty():
            break
    eq = ConvexHull(cz_points(Z.G, Z.c, Z.A, Z.b, Z.h)).equations
    H, k = eq[:, :-1], -eq[:, -1]
    ball = Z.chebyshev_ball()
    oracle_radius = np.min(k - H @ chebyshev_center(H, k))
    assert ball.exact and ball.radius == pytest.approx(oracle_radius, rel=1e-6)
    assert np.all(H @ ball.center + ball.radius <= k + 1e-7)
    np.testing.assert_allclose(Z.center("chebyshev"), ball.center)


@pytest.mark.parametrize("seed", SEEDS)
def test_chebyshev_ball_of_a_3d_zonotope_is_exact_and_of_a_3d_cz_lies_inside(seed):
    rng = np.random.default_rng(seed)
    G, c = rng.standard_normal((3, 5)), rng.standard_normal(3)
    eq = ConvexHull(zonotope_points(G, c)).equations
    H, k = eq[:, :-1], -eq[:, -1]
    ball = ss.Zonotope(G, c).to_constrained_zonotope().chebyshev_ball()
    assert ball.exact
    assert ball.radius == pytest.approx(np.min(k - H @ chebyshev_center(H, k)), rel=1e-6)
    # with a constraint: the lifted SOCP ball is inside (checked on the polytope's facets)
    Z = ss.ConstrainedZonotope(G, c, rng.standard_normal((1, 5)) * 0.3, [0.1])
    if Z.is_empty():
        return
    eq = ConvexHull(cz_points(Z.G, Z.c, Z.A, Z.b, Z.h)).equations
    H, k = eq[:, :-1], -eq[:, -1]
    inner = Z.chebyshev_ball()
    best = np.min(k - H @ chebyshev_center(H, k))
    assert np.all(H @ inner.center + inner.radius <= k + 1e-6)
    assert 0 <= inner.radius <= best + 1e-6
    assert inner.radius >= 0.2 * best  # a useful ball, not a point


def test_chebyshev_ball_of_flat_empty_and_unbounded_sets():
    segment = ss.Zonotope([[1.0], [1.0]], [0.0, 0.0]).to_constrained_zonotope()
    ball = segment.chebyshev_ball()
    assert ball.radius == 0.0 and np.allclose(ball.center, 0.0, atol=1e-9)
    from setsmooth.sets.constrained_zonotope import empty_constrained_zonotope

    empty = empty_constrained_zonotope(3).chebyshev_ball()
    assert empty.radius == -np.inf and np.isnan(empty.center).all()
    with pytest.raises(ValueError, match="unbounded"):
        ss.Reals(2).chebyshev_ball()
