"""Unbounded sets (ℝⁿ, strips, half-planes, half-lines) and empty sets, on both solver paths."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss

AXES2 = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])


def strip():
    """{x ∈ ℝ² : 0 ≤ x₁ ≤ 1}."""
    return ss.Reals(2).intersect_preimage([[1.0, 0.0]], ss.Box([0.0], [1.0]))


def contradictory_cz():
    """ξ1 = 1/2 and ξ1 = −1/2: no factor satisfies both."""
    return ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1.0, 0.0], [1.0, 0.0]], b=[0.5, -0.5])


# -- unbounded -------------------------------------------------------------------------------------

@pytest.mark.parametrize("path", ["auto", "generic"])
def test_a_strip_is_bounded_across_and_unbounded_along(path):
    S = strip()
    assert isinstance(S, ss.ConstrainedZonotope)
    values = S.support_many(AXES2, path=path)
    np.testing.assert_allclose(values[:2], [1.0, 0.0], atol=1e-8)
    assert values[2:].tolist() == [np.inf, np.inf]
    assert S.support([1.0, 1e-3], path=path) == np.inf


def test_a_strip_has_an_interval_hull_with_infinite_sides_and_infinite_diameter():
    hull = strip().interval_hull()
    np.testing.assert_allclose(hull.lo[0], 0.0, atol=1e-8)
    np.testing.assert_allclose(hull.hi[0], 1.0, atol=1e-8)
    assert hull.lo[1] == -np.inf and hull.hi[1] == np.inf
    assert strip().diameter() == np.inf
    assert strip().diameter(path="generic") == np.inf


def test_membership_in_a_strip():
    S = strip()
    for path in ("auto", "generic"):
        assert S.contains([0.5, 1e6], path=path)
        assert not S.contains([1.5, 0.0], path=path)
    assert not S.is_empty() and not S.is_empty(path="generic")


def test_certified_support_of_a_strip():
    values = strip().support_many(AXES2, certified=True)
    assert values[0] >= 1.0 - 1e-12 and values[0] == pytest.approx(1.0, abs=1e-7)
    assert values[2:].tolist() == [np.inf, np.inf]


@pytest.mark.parametrize("path", ["auto", "generic"])
def test_the_whole_space_has_infinite_support_except_in_the_zero_direction(path):
    R = ss.Reals(2)
    assert R.support_many(AXES2, path=path).tolist() == [np.inf] * 4
    assert R.support([0.0, 0.0], path=path) == 0.0
    assert R.contains([1e9, -1e9], path=path)
    assert not R.is_empty(path=path)


@pytest.mark.parametrize("path", ["auto", "generic"])
def test_a_half_plane_is_unbounded_except_along_its_normal(path):
    P = ss.HPolytope([[1.0, 1.0]], [1.0])
    values = P.support_many(np.array([[1.0, 1.0], [1.0, 0.0], [-1.0, -1.0]]), path=path)
    assert values[0] == pytest.approx(1.0, abs=1e-7)
    assert values[1:].tolist() == [np.inf, np.inf]


@pytest.mark.parametrize("path", ["auto", "generic"])
def test_a_half_line_box_is_unbounded_on_its_open_side(path):
    B = ss.Box([-np.inf, 0.0], [2.0, 1.0])
    np.testing.assert_allclose(B.support_many(AXES2, path=path)[[0, 2, 3]], [2.0, 1.0, 0.0],
                               atol=1e-8)
    assert B.support([-1.0, 0.0], path=path) == np.inf


def test_an_unbounded_set_has_no_polygon_and_cannot_be_sampled():
    with pytest.raises(ValueError, match="bounded"):
        strip().vertices_2d()
    with pytest.raises(ValueError, match="unbounded"):
        strip().sample(np.random.default_rng(0))


def test_a_linear_map_can_make_an_unbounded_set_bounded():
    flat = np.array([[1.0, 0.0], [0.0, 0.0]]) @ strip()
    np.testing.assert_allclose(flat.support_many(AXES2), [1.0, 0.0, 0.0, 0.0], atol=1e-8)


def test_unbounded_sets_in_lazy_combinations_stay_unbounded_on_both_paths():
    S = ss.Ellipsoid([0.0, 0.0], np.eye(2)) + ss.HPolytope([[1.0, 0.0]], [0.0])
    assert isinstance(S, ss.MinkowskiSum)
    for path in ("auto", "generic"):
        values = S.support_many(AXES2, path=path)
        assert values[0] == pytest.approx(1.0, abs=1e-6)
        assert values[1:].tolist() == [np.inf] * 3


# -- empty -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("path", ["auto", "generic"])
def test_a_cz_with_contradictory_constraints_is_empty(path):
    Z = contradictory_cz()
    assert Z.is_empty(path=path)
    assert Z.support_many(AXES2, path=path).tolist() == [-np.inf] * 4
    assert np.isnan(Z.support_point([1.0, 0.0], path=path)).all()
    assert not Z.contains([0.0, 0.0], path=path)
    assert isinstance(Z.interval_hull(path=path), ss.EmptySet)
    assert Z.diameter(path=path) == -np.inf


def test_an_empty_cz_has_no_centre_vertices_or_area():
    Z = contradictory_cz()
    assert np.isnan(Z.center()).all()
    assert Z.vertices_2d().shape == (0, 2)
    assert Z.area() == 0.0
    assert Z.support([1.0, 0.0], certified=True) == -np.inf


def test_an_empty_cz_with_free_factors_is_empty():
    # ξ1 free: ξ1 = 1 and ξ1 = 2.
    Z = ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1.0, 0.0], [1.0, 0.0]], b=[1.0, 2.0],
                               h=[np.inf, 1.0])
    assert Z.is_empty() and Z.is_empty(path="generic")
    assert Z.support_many(AXES2).tolist() == [-np.inf] * 4


def test_intersecting_disjoint_sets_gives_an_empty_set_on_every_path():
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2)) & ss.Box([2.0, 2.0], [3.0, 3.0])
    assert isinstance(E, ss.Intersection)
    assert E.is_empty() and E.support([1.0, 1.0]) == -np.inf
    Z = ss.Zonotope(np.eye(2), [0, 0]) & ss.Box([2.0, 2.0], [3.0, 3.0])
    assert isinstance(Z, ss.ConstrainedZonotope) and Z.is_empty()


def test_the_empty_set_answers_every_query():
    E = ss.EmptySet(2)
    assert E.is_empty() and E.is_empty(path="generic")
    assert E.support_many(AXES2).tolist() == [-np.inf] * 4
    assert E.support_many(AXES2, path="generic").tolist() == [-np.inf] * 4
    assert E.support([1.0, 0.0], certified=True) == -np.inf
    assert not E.contains([0.0, 0.0]) and not E.contains([0.0, 0.0], path="generic")
    assert E.interval_hull() is E and E.diameter() == -np.inf
    assert np.isnan(E.center()).all() and np.isnan(E.center("closest", reference=[0, 0])).all()
    assert E.area() == 0.0 and E.vertices_2d().shape == (0, 2)
    assert E.to_constrained_zonotope().is_empty()
    with pytest.raises(ValueError, match="empty set"):
        E.sample(np.random.default_rng(0))
    assert repr(E) == "EmptySet(2)" and E == ss.EmptySet(2) and E != ss.EmptySet(3)
    assert hash(E) == hash(ss.EmptySet(2))
    assert E.plot() is None


SETS = {
    "box": ss.Box([0, 0], [1, 1]),
    "zonotope": ss.Zonotope(np.eye(2), [0, 0]),
    "cz": ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1.0, 1.0]], b=[0.0]),
    "hpolytope": ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
    "ellipsoid": ss.Ellipsoid([0, 0], np.eye(2)),
    "reals": ss.Reals(2),
    "lazy": ss.Ellipsoid([0, 0], np.eye(2)) + ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]),
                                                           np.ones(4)),
}


@pytest.mark.parametrize("name", SETS)
def test_the_empty_set_absorbs_every_operation(name):
    S, E = SETS[name], ss.EmptySet(2)
    M = np.array([[1.0, 2.0], [0.0, 1.0], [1.0, 1.0]])
    results = {
        "sum": S + E, "reflected sum": E + S, "difference": S - E,
        "intersection": S & E, "reflected intersection": E & S,
        "preimage intersection": S.intersect_preimage(np.eye(2), E),
        "reflected preimage intersection": E.intersect_preimage(np.eye(2), S),
        "translation": E + np.ones(2), "map": M @ E, "preimage": E.preimage(M.T),
        "projection": E.project([1]),
    }
    for what, R in results.items():
        assert isinstance(R, ss.EmptySet), what
    assert (S * E) == ss.EmptySet(4) and (E * S) == ss.EmptySet(4)
    assert results["map"].dim == 3 and results["preimage"].dim == 3
    assert results["projection"].dim == 1


def test_an_empty_operand_inside_a_lazy_set_makes_it_empty():
    empty_cz = contradictory_cz()
    E = ss.Ellipsoid([0, 0], np.eye(2))
    for S in (ss.MinkowskiSum(E, empty_cz), ss.CartesianProduct(E, empty_cz),
              ss.LinearMap(np.eye(2), empty_cz), ss.Intersection(E, empty_cz)):
        D = np.ones((1, S.dim))
        assert S.is_empty()
        assert S.support_many(D).tolist() == [-np.inf]
        assert S.support_many(D, path="generic").tolist() == [-np.inf]


def test_an_empty_set_plus_an_unbounded_one_is_empty_not_nan():
    S = ss.MinkowskiSum(contradictory_cz(), ss.HPolytope([[1.0, 0.0]], [0.0]))
    assert S.support_many(AXES2).tolist() == [-np.inf] * 4
