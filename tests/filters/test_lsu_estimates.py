"""Point estimates of the LSU paper (Section 3.3) and the posterior spread, against independent oracles."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.filters.lsu import closest_to_zonotope_center, posterior_std
from setsmooth.filters.lsu.estimates import summarize

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
