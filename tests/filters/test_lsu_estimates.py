"""Point estimates of the LSU paper (Section 3.3) and the posterior spread, against independent oracles."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.filters.lsu import closest_to_zonotope_center, posterior_std
from setsmooth.filters.lsu.estimates import closest_point_of_hull, summarize
from setsmooth.sets.cz_vertices import cz_vertices, hull_geometry

rng = np.random.default_rng(11)
CZ3 = ss.ConstrainedZonotope(rng.standard_normal((3, 7)), rng.standard_normal(3),
                             A=rng.standard_normal((2, 7)), b=0.4 * rng.standard_normal(2))
PENTAGON = ss.ConstrainedZonotope([[1.0, 0.5, 0.2], [0.0, 1.0, 0.7]], [0.3, -0.2],
                                  A=[[1.0, 1.0, 0.5]], b=[0.6])


def polygon_centroid(V: np.ndarray) -> np.ndarray:
    """Shoelace centroid of a polygon given by its ordered vertices (independent of Qhull)."""
    x, y = V[:, 0], V[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)


def test_method_1_is_the_centre_of_the_lp_interval_hull():
    values, _ = summarize(CZ3, ("interval_hull",), False)
    np.testing.assert_allclose(values["interval_hull"], CZ3.interval_hull(certified=False).midpoint(),
                               atol=1e-7)


def test_method_2_point_is_in_the_set_at_the_closest_point_distance_of_the_generic_program():
    for Z in (CZ3, PENTAGON):
        point = closest_to_zonotope_center(Z)
        reference = Z.center("closest", reference=Z.c, norm=np.inf)    # solvers.closest
        assert Z.contains(point, tol=1e-7)
        assert np.abs(point - Z.c).max() == pytest.approx(np.abs(reference - Z.c).max(), rel=1e-6, abs=1e-9)
    unconstrained = ss.ConstrainedZonotope(np.eye(2), [1.0, 2.0])
    np.testing.assert_array_equal(closest_to_zonotope_center(unconstrained), [1.0, 2.0])


def random_cz_cut_away_from_its_centre(rng: np.random.Generator, n: int, axis_generators: bool):
    """A CZ whose constraints push the factors far from 0 (its centre c is mostly outside it); with
    ``axis_generators`` its first n generators are the unit vectors, so some of its edges and faces
    are parallel to the axes."""
    ng = int(rng.integers(n + 1, n + 4))
    nc = int(rng.integers(1, min(2, ng - n) + 1))
    G = rng.standard_normal((n, ng))
    if axis_generators:
        G[:, :n] = np.eye(n)
    A = rng.standard_normal((nc, ng))
    b = rng.uniform(0.5, 0.95, nc) * np.abs(A).sum(axis=1) * rng.choice([-1.0, 1.0], nc)
    return ss.ConstrainedZonotope(G, rng.standard_normal(n), A=A, b=b)


def random_prism_facing_its_centre_with_an_axis_face(rng: np.random.Generator, n: int):
    """c + βw₁e₁ + Σⱼ ξⱼwⱼeⱼ (j ≥ 2) + ξg: a prism on the side x₁ > c₁ of its centre whose face
    nearest c, x₁ − c₁ = βw₁ − |g₁|, is perpendicular to e₁; its ∞-norm minimizers are often a whole
    segment (2-D) or polygon (3-D) of that face."""
    w = rng.uniform(0.2, 1.0, n)
    g = rng.standard_normal(n)
    g[0] = rng.uniform(0.0, 0.4) * w[0]
    G = np.column_stack([np.diag(w), g])
    A = np.zeros((1, n + 1))
    A[0, 0] = 1.0
    return ss.ConstrainedZonotope(G, rng.standard_normal(n), A=A, b=[rng.uniform(0.5, 0.95)])


@pytest.mark.parametrize("n", [2, 3])
def test_method_2_from_the_hull_reaches_the_lp_distance_with_a_point_of_the_set(n):
    rng = np.random.default_rng(40 + n)
    outside = 0
    for trial in range(90):
        Z = (random_prism_facing_its_centre_with_an_axis_face(rng, n) if trial % 3 == 2
             else random_cz_cut_away_from_its_centre(rng, n, axis_generators=trial % 3 == 1))
        V = cz_vertices(Z)
        if V.shape[0] == 0:
            continue
        point = closest_point_of_hull(hull_geometry(V), Z.c)
        distance = np.abs(point - Z.c).max()
        lp_distance = np.abs(closest_to_zonotope_center(Z) - Z.c).max()
        assert Z.contains(point, tol=1e-9)
        assert distance == pytest.approx(lp_distance, rel=1e-10, abs=1e-12)
        outside += distance > 0
    assert outside >= 45


def test_method_2_from_the_hull_is_the_centre_itself_when_the_centre_is_inside():
    Z = ss.ConstrainedZonotope([[1.0, 0.5, 0.2, 0.0], [0.0, 1.0, 0.7, 0.1], [0.3, 0.0, 1.0, 0.5]],
                               [0.3, -0.2, 1.0], A=[[1.0, 1.0, 0.5, -0.4]], b=[0.0])
    np.testing.assert_array_equal(closest_point_of_hull(hull_geometry(cz_vertices(Z)), Z.c), Z.c)
    polygon = ss.ConstrainedZonotope(PENTAGON.G, PENTAGON.c, A=PENTAGON.A, b=[0.0])
    np.testing.assert_array_equal(closest_point_of_hull(hull_geometry(cz_vertices(polygon)), polygon.c),
                                  polygon.c)


def test_method_2_ties_go_to_the_minimizer_vertex_nearest_the_centre_in_the_euclidean_norm():
    # The box [1, 3] × [−0.5, 1] seen from the origin: every point of its left edge is at ∞-distance 1,
    # a segment of minimizers whose ends are (1, −0.5) and (1, 1); the first is nearer in the 2-norm.
    box = hull_geometry(np.array([[1.0, -0.5], [3.0, -0.5], [3.0, 1.0], [1.0, 1.0]]))
    np.testing.assert_array_equal(closest_point_of_hull(box, np.zeros(2)), [1.0, -0.5])
    # In 3-D, the facet x₃ = 1 of the box [−0.2, 2] × [0.5, 3] × [1, 2] holds the minimizers from the
    # origin (the square |x₁|, |x₂| ≤ 1 cut by the box); the nearest of its vertices is (−0.2, 0.5, 1).
    corners = np.array([[x, y, z] for x in (-0.2, 2.0) for y in (0.5, 3.0) for z in (1.0, 2.0)])
    np.testing.assert_allclose(closest_point_of_hull(hull_geometry(corners), np.zeros(3)), [-0.2, 0.5, 1.0],
                               rtol=0, atol=1e-15)


def test_summarize_takes_method_2_from_the_hull_at_the_lp_distance():
    values, _ = summarize(CZ3, ("closest",), False)
    lp = closest_to_zonotope_center(CZ3)
    assert CZ3.contains(values["closest"], tol=1e-9)
    assert np.abs(values["closest"] - CZ3.c).max() == pytest.approx(np.abs(lp - CZ3.c).max(), rel=1e-10)


def test_centroid_matches_the_shoelace_centroid_of_the_oracle_polygon():
    centroid = ss.lsu_point_estimate(PENTAGON, "centroid")
    np.testing.assert_allclose(centroid, polygon_centroid(PENTAGON.vertices_2d()), atol=1e-9)


def test_spread_of_box_parallelotope_and_cz_forms_agree():
    box = ss.Box([0.0, -1.0, 2.0], [1.0, 3.0, 2.5])
    np.testing.assert_allclose(posterior_std(box), box.widths() / np.sqrt(12))
    np.testing.assert_allclose(posterior_std(box.to_constrained_zonotope()), box.widths() / np.sqrt(12),
                               rtol=1e-9)
    T = np.array([[1.0, 0.3, 0.0], [0.0, 1.0, 0.2], [0.1, 0.0, 0.5]])
    par = ss.Zonotope(T, np.zeros(3))
    np.testing.assert_allclose(posterior_std(par), posterior_std(par.to_constrained_zonotope()), rtol=1e-9)


def test_sampled_centroid_needs_an_rng_and_approximates_the_exact_one():
    big = ss.ConstrainedZonotope(np.random.default_rng(3).standard_normal((7, 9)), np.zeros(7))
    with pytest.raises(ValueError, match="pass rng"):
        ss.lsu_point_estimate(big + ss.HPolytope(np.vstack([np.eye(7), -np.eye(7)]), np.ones(14)),
                              "centroid")
    with pytest.raises(ValueError, match="method must be one of"):
        ss.lsu_point_estimate(PENTAGON, "median")
    assert np.isnan(ss.lsu_point_estimate(ss.EmptySet(2), "centroid")).all()
