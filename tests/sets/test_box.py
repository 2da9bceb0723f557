"""Boxes: every query in closed form, bounds may be infinite."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

import setsmooth as ss


def corners(B):
    return np.array(list(itertools.product(*zip(B.lo, B.hi))))


def test_support_is_attained_at_the_corner_picked_by_the_signs_of_the_direction():
    B = ss.Box([-1.0, 0.0, 2.0], [1.0, 3.0, 2.5])
    rng = np.random.default_rng(0)
    D = rng.standard_normal((20, 3))
    values = B.support_many(D)
    np.testing.assert_allclose(values, (corners(B) @ D.T).max(axis=0), atol=1e-12)
    for d, v in zip(D, values):
        p = B.support_point(d)
        assert d @ p == pytest.approx(v) and B.contains(p, tol=0.0)


def test_a_coordinate_the_direction_does_not_see_contributes_nothing_even_when_unbounded():
    B = ss.Box([-np.inf, 0.0], [np.inf, 1.0])
    assert B.support([0.0, 1.0]) == 1.0
    assert B.support([0.0, -1.0]) == 0.0
    assert B.support([1e-9, 1.0]) == np.inf
    point = B.support_point([0.0, 1.0])
    assert point.tolist() == [0.0, 1.0]


def test_unbounded_sides_give_infinite_support_only_in_their_direction():
    B = ss.Box([-np.inf, 0.0], [0.0, np.inf])
    D = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    assert B.support_many(D).tolist() == [0.0, np.inf, np.inf, 0.0]
    assert np.isnan(B.support_point([-1.0, 0.0])).all()
    np.testing.assert_allclose(B.support_many(D, path="generic"), [0.0, np.inf, np.inf, 0.0],
                               atol=1e-8)


def test_queries_on_unbounded_boxes_emit_no_warnings():
    B = ss.Box([-np.inf, 0.0, -np.inf], [np.inf, 1.0, 2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        B.support_many(np.eye(3))
        ss.Box([-np.inf, 0.0], [np.inf, 1.0]).to_constrained_zonotope()
        B.midpoint()
        B.interval_hull()


def test_interval_hull_of_a_box_is_the_box_itself():
    B = ss.Box([0, -np.inf], [1, 2])
    assert B.interval_hull() is B
    hull = ss.Box([0, 1], [2, 3]).interval_hull(path="generic")
    np.testing.assert_allclose(hull.lo, [0, 1], atol=1e-8)
    np.testing.assert_allclose(hull.hi, [2, 3], atol=1e-8)


def test_diameter_is_the_widest_edge():
    assert ss.Box([0, 0], [1, 3]).diameter() == 3.0
    assert ss.Box([0, -np.inf], [1, 3]).diameter() == np.inf


def test_membership_uses_the_margin():
    B = ss.Box([0, 0], [1, 1])
    assert B.contains([1.0, 0.5])
    assert not B.contains([1.001, 0.5])
    assert B.contains([1.001, 0.5], tol=1e-2)
    assert ss.Box([-np.inf], [0]).contains([-1e12])


def test_midpoint_widths_and_boundedness():
    B = ss.Box([0, -np.inf], [2, 1])
    assert B.widths().tolist() == [2.0, np.inf]
    mid = B.midpoint()
    assert mid[0] == 1.0 and np.isnan(mid[1])
    assert not B.is_bounded and ss.Box([0], [1]).is_bounded


def test_a_box_with_equal_corners_is_a_point():
    B = ss.Box([1.0, 2.0], [1.0, 2.0])
    assert B.support([3.0, -1.0]) == 1.0
    assert B.vertices_2d().tolist() == [[1.0, 2.0]]
    assert B.area() == 0.0


def test_intersection_of_boxes_takes_the_tighter_bounds():
    both = ss.Box([0, 0], [2, 2]) & ss.Box([1, -1], [3, 1])
    assert isinstance(both, ss.Box)
    assert both.lo.tolist() == [1, 0] and both.hi.tolist() == [2, 1]


def test_intersection_of_disjoint_boxes_is_the_empty_set():
    assert ss.Box([0, 0], [1, 1]) & ss.Box([2, 0], [3, 1]) == ss.EmptySet(2)


def test_sum_of_boxes_adds_the_corners():
    S = ss.Box([0, -1], [1, 1]) + ss.Box([1, 1], [2, np.inf])
    assert isinstance(S, ss.Box)
    assert S.lo.tolist() == [1, 0] and S.hi.tolist() == [3, np.inf]


def test_product_of_boxes_concatenates_the_bounds():
    P = ss.Box([0], [1]) * ss.Box([2, 3], [4, 5])
    assert isinstance(P, ss.Box)
    assert P.lo.tolist() == [0, 2, 3] and P.hi.tolist() == [1, 4, 5]


def test_projection_keeps_the_chosen_coordinates_in_order():
    P = ss.Box([0, 1, 2], [3, 4, 5]).project([2, 0])
    assert isinstance(P, ss.Box)
    assert P.lo.tolist() == [2, 0] and P.hi.tolist() == [5, 3]


def test_translation_moves_both_corners():
    B = ss.Box([0, -np.inf], [1, 0]) + np.array([1.0, 2.0])
    assert B.lo.tolist() == [1, -np.inf] and B.hi.tolist() == [2, 2]


def test_zonotope_hpolytope_and_cz_forms_have_the_supports_of_the_box():
    B = ss.Box([-1, 0, 2], [1, 0.5, 4])
    D = np.random.default_rng(1).standard_normal((10, 3))
    for form in (B.to_zonotope(), B.to_hpolytope(), B.to_constrained_zonotope()):
        np.testing.assert_allclose(form.support_many(D), B.support_many(D), atol=1e-7)


def test_a_free_coordinate_has_a_cz_form_but_a_half_line_has_none():
    Z = ss.Box([-np.inf, 0], [np.inf, 1]).to_constrained_zonotope()
    assert Z.h.tolist() == [np.inf, 1.0]
    with pytest.raises(TypeError, match="no exact constrained-zonotope form"):
        ss.Box([-np.inf], [0]).to_constrained_zonotope()
    with pytest.raises(ValueError, match="unbounded box has no zonotope form"):
        ss.Box([-np.inf], [0]).to_zonotope()


def test_hpolytope_form_of_an_unbounded_box_keeps_only_its_finite_faces():
    P = ss.Box([-np.inf, 0], [np.inf, 1]).to_hpolytope()
    assert P.H.shape == (2, 2)
    assert P.support([0.0, 1.0]) == pytest.approx(1.0, abs=1e-8)


def test_centres_of_a_box_are_its_midpoint():
    B = ss.Box([0, 0], [2, 4])
    assert B.center().tolist() == [1, 2]
    assert B.center("chebyshev").tolist() == [1, 2]
    np.testing.assert_allclose(B.center("closest", reference=[5, 1]), [2, 1], atol=1e-6)


def test_samples_are_uniform_in_a_bounded_box_and_reproducible():
    B = ss.Box([0, 10], [1, 20])
    a = B.sample(np.random.default_rng(3), size=2000)
    assert a.shape == (2000, 2)
    assert np.all((a >= B.lo) & (a <= B.hi))
    assert np.abs(a.mean(axis=0) - [0.5, 15]).max() < 0.3
    np.testing.assert_array_equal(a, B.sample(np.random.default_rng(3), size=2000))
    with pytest.raises(ValueError, match="unbounded box"):
        ss.Box([0], [np.inf]).sample(np.random.default_rng(0))
