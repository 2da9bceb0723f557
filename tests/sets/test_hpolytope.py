"""H-polytopes {x : Hx ≤ k}: closed-form intersections, preimages by polyhedra, translations."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss

SQUARE = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))


def test_support_of_a_square_is_its_l1_norm_and_agrees_across_paths():
    D = np.random.default_rng(0).standard_normal((10, 2))
    np.testing.assert_allclose(SQUARE.support_many(D), np.abs(D).sum(axis=1), atol=1e-7)
    np.testing.assert_allclose(SQUARE.support_many(D, path="generic"), np.abs(D).sum(axis=1),
                               atol=1e-7)


def test_membership_relaxes_each_face_by_the_margin_times_its_l1_norm():
    P = ss.HPolytope([[2.0, 0.0]], [2.0])  # x1 ≤ 1 with a scaled normal
    assert P.contains([1.0, 5.0], tol=0.0)
    assert not P.contains([1.01, 5.0], tol=0.0)
    assert P.contains([1.01, 5.0], tol=0.02)
    assert P.contains([1.01, 5.0], tol=0.02, path="generic")


def test_translation_shifts_the_offsets():
    P = SQUARE + np.array([2.0, -1.0])
    assert isinstance(P, ss.HPolytope)
    np.testing.assert_allclose(P.support_many(np.eye(2)), [3.0, 0.0], atol=1e-7)


def test_intersection_with_a_box_stacks_its_finite_faces():
    P = SQUARE & ss.Box([0.0, -np.inf], [np.inf, 0.5])
    assert isinstance(P, ss.HPolytope) and P.H.shape == (6, 2)
    np.testing.assert_allclose(P.interval_hull().lo, [0.0, -1.0], atol=1e-7)
    np.testing.assert_allclose(P.interval_hull().hi, [1.0, 0.5], atol=1e-7)
    assert isinstance(ss.Box([0, 0], [2, 2]) & SQUARE, ss.HPolytope)


def test_generalized_intersection_with_a_polyhedron_maps_its_faces_back():
    R = np.array([[1.0, 1.0]])
    P = SQUARE.intersect_preimage(R, ss.Box([-0.5], [0.5]))
    assert isinstance(P, ss.HPolytope)
    assert P.support([1.0, 1.0]) == pytest.approx(0.5, abs=1e-7)
    assert P.support([1.0, -1.0]) == pytest.approx(2.0, abs=1e-7)


def test_product_of_polytopes_is_block_diagonal():
    P = SQUARE * ss.Box([2.0], [3.0])
    assert isinstance(P, ss.HPolytope) and P.dim == 3
    assert P.support([0.0, 0.0, 1.0]) == pytest.approx(3.0, abs=1e-7)


def test_linear_map_of_a_polytope_stays_lazy_and_exact():
    M = np.array([[1.0, 1.0], [0.0, 2.0], [1.0, 0.0]])
    S = M @ SQUARE
    assert isinstance(S, ss.LinearMap) and S.dim == 3
    d = np.array([1.0, -1.0, 0.5])
    assert S.support(d) == pytest.approx(SQUARE.support(M.T @ d), abs=1e-7)


def test_an_infeasible_polyhedron_is_empty():
    P = ss.HPolytope([[1.0, 0.0], [-1.0, 0.0]], [1.0, -2.0])
    assert P.is_empty() and P.support([0.0, 1.0]) == -np.inf
    assert isinstance(P.interval_hull(), ss.EmptySet)
    assert np.isnan(P.center("chebyshev")).all()


def test_chebyshev_centre_is_the_centre_of_the_largest_inscribed_ball():
    P = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), [3.0, 1.0, 1.0, 1.0])
    np.testing.assert_allclose(P.center("chebyshev")[1], 0.0, atol=1e-7)
    assert -1.0 + 1.0 - 1e-7 <= P.center("chebyshev")[0] <= 3.0 - 1.0 + 1e-7


def test_repr_names_dimension_and_faces():
    assert repr(SQUARE) == "HPolytope(dim=2, m=4)"


def test_product_of_large_polytopes_keeps_a_dense_h():
    n = 40  # the block-diagonal H has more entries than the sparse-storage threshold
    cube = ss.HPolytope(np.vstack([np.eye(n), -np.eye(n)]), np.ones(2 * n))
    P = cube * cube
    assert isinstance(P.H, np.ndarray) and P.H.shape == (4 * n, 2 * n)
    assert P.contains(np.zeros(2 * n)) and not P.contains(np.full(2 * n, 1.5))
