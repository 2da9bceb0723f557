"""Lazy sets: exact, represented by their operands; they flatten to a CZ when every operand does."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss

E = ss.Ellipsoid([0.0, 0.0], np.diag([4.0, 1.0]))
SQUARE = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
D = np.random.default_rng(0).standard_normal((8, 2))


def close(a, b):
    np.testing.assert_allclose(a, b, atol=1e-6 * (1 + np.abs(b[np.isfinite(b)]).max(initial=0)))


def test_linear_map_support_is_the_support_in_the_transposed_direction():
    M = np.array([[1.0, 2.0], [0.0, 1.0], [3.0, -1.0]])
    S = ss.LinearMap(M, SQUARE, offset=[1.0, 0.0, -1.0])
    D3 = np.random.default_rng(1).standard_normal((6, 3))
    close(S.support_many(D3), SQUARE.support_many(D3 @ M) + D3 @ S.offset)
    close(S.support_many(D3, path="generic"), S.support_many(D3))
    p = S.support_point(D3[0])
    assert S.contains(p, tol=1e-6)


def test_composed_maps_collapse_into_one_lazy_map():
    A, B = np.array([[1.0, 1.0], [0.0, 1.0]]), np.array([[2.0, 0.0], [1.0, -1.0]])
    S = B @ (A @ SQUARE + np.array([1.0, 2.0]))
    assert isinstance(S, ss.LinearMap) and S.S is SQUARE
    np.testing.assert_allclose(S.M, B @ A)
    np.testing.assert_allclose(S.offset, B @ [1.0, 2.0])
    close(S.support_many(D), SQUARE.support_many(D @ B @ A) + D @ B @ [1.0, 2.0])


def test_lazy_linear_map_accepts_a_sparse_matrix():
    M = sp.csr_matrix(np.array([[1.0, 2.0], [0.0, 1.0]]))
    S = M @ SQUARE
    assert isinstance(S, ss.LinearMap)
    close(S.support_many(D), SQUARE.support_many(D @ M.toarray()))
    close(S.support_many(D, path="generic"), S.support_many(D))


def test_minkowski_sum_support_is_the_sum_and_support_points_add():
    S = E + SQUARE
    assert isinstance(S, ss.MinkowskiSum)
    close(S.support_many(D), E.support_many(D) + SQUARE.support_many(D))
    close(S.support_many(D, path="generic"), S.support_many(D))
    p = S.support_point(D[0])
    assert D[0] @ p == pytest.approx(S.support(D[0]), abs=1e-6)


def test_cartesian_product_support_splits_the_direction():
    S = E * SQUARE
    assert isinstance(S, ss.CartesianProduct) and S.dim == 4
    D4 = np.random.default_rng(2).standard_normal((6, 4))
    close(S.support_many(D4), E.support_many(D4[:, :2]) + SQUARE.support_many(D4[:, 2:]))
    close(S.support_many(D4, path="generic"), S.support_many(D4))


def test_intersection_of_an_ellipse_and_a_square_is_inside_both():
    S = E & SQUARE
    assert isinstance(S, ss.Intersection)
    values = S.support_many(D)
    assert np.all(values <= np.minimum(E.support_many(D), SQUARE.support_many(D)) + 1e-7)
    np.testing.assert_allclose(S.support([1.0, 0.0]), 1.0, atol=1e-7)
    np.testing.assert_allclose(S.support([0.0, 1.0]), 1.0, atol=1e-7)


def test_generalized_intersection_cuts_by_the_preimage():
    S = E.intersect_preimage([[1.0, 1.0]], ss.Box([-0.5], [0.5]))
    assert isinstance(S, ss.GeneralizedIntersection)
    assert S.support([1.0, 1.0]) == pytest.approx(0.5, abs=1e-6)
    assert S.contains([1.0, -0.6]) and not S.contains([1.0, 0.0])


def test_lazy_sets_of_cz_operands_use_the_fast_path():
    B, Z = ss.Box([0, 0], [1, 1]), ss.Zonotope(np.eye(2), np.zeros(2))
    for lazy in (ss.MinkowskiSum(B, Z), ss.Intersection(B, Z), ss.CartesianProduct(B, Z),
                 ss.LinearMap(np.ones((1, 2)), Z), ss.GeneralizedIntersection(B, np.eye(2), Z)):
        cz = lazy.to_constrained_zonotope()
        assert isinstance(cz, ss.ConstrainedZonotope)
        Dk = np.random.default_rng(3).standard_normal((5, lazy.dim))
        close(lazy.support_many(Dk), cz.support_many(Dk))
        close(lazy.support_many(Dk, path="generic"), lazy.support_many(Dk))
        assert np.isfinite(lazy.support_many(Dk, certified=True)).all()


def test_lazy_sets_of_ellipsoids_have_no_cz_form():
    for lazy in (E + SQUARE, E & SQUARE, E * SQUARE):
        with pytest.raises(TypeError, match="no exact constrained-zonotope form"):
            lazy.to_constrained_zonotope()


def test_emptiness_of_lazy_sets_follows_the_operands():
    far = SQUARE + np.array([10.0, 10.0])
    assert (E & far).is_empty()
    assert not (E + far).is_empty() and not (E * far).is_empty()
    assert not (np.eye(2) @ SQUARE).is_empty()


def test_interval_hull_of_a_lazy_set_comes_from_its_supports():
    S = E + SQUARE
    hull = S.interval_hull()
    np.testing.assert_allclose(hull.hi, [3.0, 2.0], atol=1e-6)
    np.testing.assert_allclose(hull.lo, [-3.0, -2.0], atol=1e-6)
    assert S.diameter() == pytest.approx(6.0, abs=1e-6)
    np.testing.assert_allclose(S.center(), [0.0, 0.0], atol=1e-6)


def test_closest_point_of_a_lazy_set():
    S = E & SQUARE
    np.testing.assert_allclose(S.center("closest", reference=[5.0, 0.0]), [1.0, 0.0], atol=1e-6)


def test_repr_of_a_lazy_set_names_its_type_and_dimension():
    assert repr(E + SQUARE) == "MinkowskiSum(dim=2)"
