"""The Pontryagin difference S ⊖ T against an independent 2-D computation: S's polygon (vertex
enumeration by scipy) as halfspaces, shifted by T's support values computed from T's vertices."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import setsmooth as ss
from tests.sets.test_oracles import cz_points, zonotope_points

SEEDS = range(8)


def oracle_difference(S_points, T_points):
    """Vertices of {x : Hx ≤ k − max_t Ht} for S = conv(S_points), T = conv(T_points) (2-D)."""
    eq = ConvexHull(S_points).equations
    H, k = eq[:, :-1], -eq[:, -1]
    shifted = k - (T_points @ H.T).max(axis=0)
    return ss.HPolytope(H, shifted)


def support_gap(A, B, count=48):
    """max_d |h_A(d) − h_B(d)| over unit directions (Hausdorff distance of convex sets, sampled)."""
    angles = np.linspace(0, 2 * np.pi, count, endpoint=False) + 0.05
    D = np.column_stack([np.cos(angles), np.sin(angles)])
    return float(np.max(np.abs(A.support_many(D) - B.support_many(D))))


def random_cz(rng):
    while True:
        Z = ss.ConstrainedZonotope(rng.standard_normal((2, 5)) * 1.5, rng.standard_normal(2) * 0.2,
                                   rng.standard_normal((1, 5)), rng.uniform(-0.2, 0.2, 1))
        if not Z.is_empty():
            return Z


def small_zonotope(rng):
    return ss.Zonotope(rng.standard_normal((2, 3)) * 0.15, rng.standard_normal(2) * 0.05)


@pytest.mark.parametrize("seed", SEEDS)
def test_cz_difference_exact_matches_the_polygon_oracle_and_outer_inner_bracket_it(seed):
    rng = np.random.default_rng(seed)
    S, T = random_cz(rng), small_zonotope(rng)
    oracle = oracle_difference(cz_points(S.G, S.c, S.A, S.b, S.h), zonotope_points(T.G, T.c))
    exact = S.pontryagin_difference(T)
    if oracle.is_empty():
        assert exact.is_empty()
        return
    assert support_gap(exact, oracle) < 1e-6
    outer = S.pontryagin_difference(T, method="outer")
    inner = S.pontryagin_difference(T, method="inner")
    area = oracle.area()
    assert area <= outer.area() * (1 + 1e-7) + 1e-9
    assert inner.is_empty() or inner.area() <= area * (1 + 1e-7) + 1e-9
    if not inner.is_empty():  # every point of the inner set, moved by T, stays in S
        assert (inner + T).is_subset(S)


@pytest.mark.parametrize("seed", SEEDS)
def test_hpolytope_and_box_differences_are_exact_for_any_bounded_subtrahend(seed):
    rng = np.random.default_rng(seed)
    pts = rng.standard_normal((9, 2)) * 2
    eq = ConvexHull(pts).equations
    P = ss.HPolytope(eq[:, :-1], -eq[:, -1])
    T = ss.Ellipsoid([0.1, -0.1], np.diag([0.05, 0.02]))  # any bounded set: support values only
    D = P.pontryagin_difference(T)
    assert isinstance(D, ss.HPolytope)
    # D ⊕ T ⊆ P, and D is the largest such polytope: its faces touch P's after adding T.
    assert np.all((D + T).support_many(P.H) <= P.k + 1e-9)
    np.testing.assert_allclose(D.support_many(P.H) + T.support_many(P.H), P.k, atol=1e-6)
    box = ss.Box([-1, -2], [3, 2])
    Z = small_zonotope(rng)
    B = box.pontryagin_difference(Z)
    hull = Z.interval_hull()
    np.testing.assert_allclose(B.lo, box.lo - hull.lo)
    np.testing.assert_allclose(B.hi, box.hi - hull.hi)


def test_minus_is_the_minkowski_sum_with_the_negation_not_the_difference():
    S, T = ss.Box([-2, -2], [2, 2]), ss.Box([0, 0], [1, 1])
    minus = (S - T).interval_hull()
    assert np.allclose([minus.lo, minus.hi], [[-3, -3], [2, 2]])  # {s − t}
    diff = S.pontryagin_difference(T)
    assert np.allclose([diff.lo, diff.hi], [[-2, -2], [1, 1]])  # {x : x + T ⊆ S}
    assert (diff + T).is_subset(S) and not (S - T + T).is_subset(S)


def test_difference_by_a_too_large_set_is_empty_and_by_the_empty_set_is_everything():
    S = ss.Box([0, 0], [1, 1])
    assert isinstance(S.pontryagin_difference(ss.Box([0, 0], [2, 0.5])), ss.EmptySet)
    cz = S.to_constrained_zonotope()
    assert cz.pontryagin_difference(ss.Zonotope(np.eye(2), [0, 0])).is_empty()
    assert isinstance(S.pontryagin_difference(ss.EmptySet(2)), ss.Reals)


def test_bad_difference_operands_are_refused_clearly():
    cz = ss.Box([0, 0], [1, 1]).to_constrained_zonotope()
    with pytest.raises(ValueError, match="method must be one of"):
        cz.pontryagin_difference(ss.Box([0, 0], [0.1, 0.1]), method="approx")
    with pytest.raises(TypeError, match="T a Box or a Zonotope"):
        cz.pontryagin_difference(ss.Ellipsoid([0, 0], 0.01 * np.eye(2)))
    with pytest.raises(ValueError, match="needs a bounded T"):
        ss.Box([0, 0], [1, 1]).pontryagin_difference(ss.HPolytope([[1.0, 0.0]], [0.0]))
    with pytest.raises(ValueError, match="2\\^11 copies"):
        cz.pontryagin_difference(ss.Zonotope(np.full((2, 11), 1e-3), [0, 0]))
    with pytest.raises(TypeError, match="Ellipsoid is none of these"):
        ss.Ellipsoid([0, 0], np.eye(2)).pontryagin_difference(ss.Box([0, 0], [0.1, 0.1]))
