"""Exact Hausdorff distance between convex polytopes (stability (10)), the vertex surrogate, diameters.

Oracles: closed forms for boxes, the closest-point programs (the n-D route) for the 2-D closed-form
geometry, dense sampling of the sets, and brute-force minimization along segments.
"""

import math

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis
from setsmooth.analysis.hausdorff import _directed, _segment_distance


def test_boxes_in_closed_form():
    S, T = ss.Box([0, 0], [1, 1]), ss.Box([0, 0], [2, 3])
    assert analysis.hausdorff_distance(S, T, 2) == pytest.approx(math.hypot(1, 2))
    assert analysis.hausdorff_distance(S, T, "inf") == pytest.approx(2.0)
    # In 3-D (box corners, closest-point programs): the far corner (2, 2, 2) is √3 from [0, 1]^3.
    S3, T3 = ss.Box([0, 0, 0], [1, 1, 1]), ss.Box([0, 0, 0], [2, 2, 2])
    assert analysis.hausdorff_distance(S3, T3, 2) == pytest.approx(math.sqrt(3), rel=1e-6)
    assert analysis.hausdorff_distance(S3, T3, np.inf) == pytest.approx(1.0, rel=1e-6)


def test_surrogate_is_an_upper_bound_that_can_be_strict():
    square, diamond = ss.Box([-1, -1], [1, 1]), ss.Zonotope([[0.5, 0.5], [0.5, -0.5]], [0, 0])
    exact = analysis.hausdorff_distance(square, diamond, 2)
    assert exact == pytest.approx(1 / math.sqrt(2))                  # corner to the diamond's edge
    assert analysis.vertex_hausdorff_surrogate(square, diamond) == pytest.approx(1.0)


def _random_polygon(rng):
    G = rng.standard_normal((2, int(rng.integers(2, 5))))
    return ss.Zonotope(G, rng.standard_normal(2))


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("norm", [2, np.inf])
def test_closed_form_planar_route_agrees_with_closest_point_programs(seed, norm):
    rng = np.random.default_rng(seed)
    S, T = _random_polygon(rng), _random_polygon(rng)
    VS, VT = analysis.polytope_vertices(S), analysis.polytope_vertices(T)
    order = 2.0 if norm == 2 else math.inf
    assert _directed(VS, T, VT, order) == pytest.approx(_directed(VS, T, None, order), rel=1e-6, abs=1e-7)
    assert _directed(VT, S, VS, order) == pytest.approx(_directed(VT, S, None, order), rel=1e-6, abs=1e-7)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("norm", [2, np.inf])
def test_hausdorff_distance_matches_dense_sampling(seed, norm):
    rng = np.random.default_rng(10 + seed)
    S, T = _random_polygon(rng), _random_polygon(rng)
    VS, VT = analysis.polytope_vertices(S), analysis.polytope_vertices(T)
    exact = analysis.hausdorff_distance(S, T, norm)

    def dense(V, n=800):     # convex combinations and boundary points of the polygon
        W = rng.dirichlet(np.ones(len(V)) * 0.3, n)
        t = rng.random((n, 1))
        i = rng.integers(0, len(V), n)
        edge = V[i] + t * (np.roll(V, -1, axis=0)[i] - V[i])
        return np.vstack([W @ V, edge, V])

    PS, PT = dense(VS), dense(VT)
    D = np.linalg.norm(PS[:, None, :] - PT[None, :, :], ord=norm, axis=2)
    sampled = max(D.min(axis=1).max(), D.min(axis=0).max())
    # Sampling T finely overestimates each distance a little and sampling S underestimates the sup.
    scale = max(np.ptp(VS), np.ptp(VT))
    assert abs(sampled - exact) <= 0.03 * scale


@pytest.mark.parametrize("seed", range(20))
def test_segment_distance_in_the_inf_norm_matches_a_fine_search(seed):
    rng = np.random.default_rng(seed)
    p, a, b = rng.standard_normal((3, 2))
    lam = np.linspace(0, 1, 20001)[:, None]
    brute = np.abs(p - a - lam * (b - a)).max(axis=1).min()
    assert _segment_distance(p, a, b, math.inf) == pytest.approx(brute, abs=1e-4)
    assert _segment_distance(p, a, b, math.inf) <= brute + 1e-12


def test_point_inside_a_polygon_is_at_distance_zero():
    V = analysis.polytope_vertices(ss.Box([0, 0], [2, 1]))
    assert analysis.point_polygon_distance([1.0, 0.5], V) == 0.0
    assert analysis.point_polygon_distance([3.0, 2.0], V, "inf") == pytest.approx(1.0)


def test_empty_sets():
    empty = ss.Box([0, 0], [1, 1]) & ss.Box([2, 2], [3, 3])
    S = ss.Box([0, 0], [1, 1])
    assert analysis.hausdorff_distance(S, empty) == math.inf
    assert analysis.hausdorff_distance(empty, empty) == 0.0
    assert analysis.diameter(empty) == -math.inf


def test_diameters_in_both_norms():
    S = ss.Box([0, 0], [1, 2])
    assert analysis.diameter(S, 2) == pytest.approx(math.sqrt(5))
    assert analysis.diameter(S, "inf") == pytest.approx(2.0)
    Z = ss.Zonotope([[1.0, 1.0], [1.0, -1.0]], [0, 0])          # a square rotated by 45°
    assert analysis.diameter(Z, 2) == pytest.approx(4.0)
    with pytest.raises(ValueError, match="norm must be 2 or inf"):
        analysis.diameter(S, 1)
    with pytest.raises(NotImplementedError, match="vertex enumeration"):
        analysis.diameter(ss.Zonotope(np.eye(3), np.zeros(3)), 2)


def test_polygons_given_by_vertices_give_the_same_numbers_as_the_sets():
    rng = np.random.default_rng(5)
    S, T = _random_polygon(rng), _random_polygon(rng)
    VS, VT = S.vertices_2d(), T.vertices_2d()
    for norm in (2, "inf"):
        assert analysis.hausdorff_distance(VS, VT, norm) == pytest.approx(analysis.hausdorff_distance(S, T, norm))
        assert analysis.diameter(VS, norm) == pytest.approx(analysis.diameter(S, norm), rel=1e-6)
    assert analysis.vertex_hausdorff_surrogate(VS, VT) == analysis.vertex_hausdorff_surrogate(S, T)
    assert analysis.hausdorff_distance(VS, np.zeros((0, 2))) == math.inf
    with pytest.raises(ValueError, match="shape"):
        analysis.hausdorff_distance(np.ones((3, 3)), VT)
