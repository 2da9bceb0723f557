"""Ellipsoids E(c, Q), Q ⪰ 0 (possibly singular): closed-form support, maps and interval hull."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss


def random_ellipsoid(seed=0, n=3, rank=None):
    rng = np.random.default_rng(seed)
    L = rng.standard_normal((n, n if rank is None else rank))
    return ss.Ellipsoid(rng.uniform(-1, 1, n), L @ L.T)


@pytest.mark.parametrize("rank", [0, 1, 2, 3])
def test_closed_form_support_equals_the_generic_program(rank):
    E = random_ellipsoid(rank, rank=rank)
    D = np.random.default_rng(1).standard_normal((8, 3))
    expected = D @ E.c + np.sqrt(np.einsum("ij,jk,ik->i", D, E.Q, D))
    np.testing.assert_allclose(E.support_many(D), expected, atol=1e-12)
    np.testing.assert_allclose(E.support_many(D, path="generic"), expected,
                               atol=1e-6 * (1 + np.abs(expected).max()))


def test_support_point_lies_on_the_boundary_and_attains_the_value():
    E = random_ellipsoid(2)
    d = np.array([1.0, -2.0, 0.5])
    p = E.support_point(d)
    assert d @ p == pytest.approx(E.support(d))
    assert (p - E.c) @ np.linalg.solve(E.Q, p - E.c) == pytest.approx(1.0)


def test_a_zero_shape_matrix_is_the_centre_point():
    E = ss.Ellipsoid([1.0, 2.0], np.zeros((2, 2)))
    assert E.support([3.0, 4.0]) == 11.0
    assert E.support_point([3.0, 4.0]).tolist() == [1.0, 2.0]
    assert E.contains([1.0, 2.0]) and not E.contains([1.0, 2.1])


def test_interval_hull_half_widths_are_square_roots_of_the_diagonal():
    E = random_ellipsoid(3)
    hull = E.interval_hull()
    r = np.sqrt(np.diag(E.Q))
    np.testing.assert_allclose(hull.lo, E.c - r)
    np.testing.assert_allclose(hull.hi, E.c + r)
    generic = E.interval_hull(path="generic")
    np.testing.assert_allclose(generic.hi, hull.hi, atol=1e-6)


def test_linear_map_of_an_ellipsoid_is_an_ellipsoid_possibly_degenerate():
    E = random_ellipsoid(4)
    M = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0]])  # rank one
    F = M @ E
    assert isinstance(F, ss.Ellipsoid)
    np.testing.assert_allclose(F.Q, M @ E.Q @ M.T)
    assert F.support([2.0, -1.0]) == pytest.approx((M @ E.c) @ [2.0, -1.0], abs=1e-9)


def test_translation_and_projection_keep_the_ellipsoid():
    E = random_ellipsoid(5)
    T = E + np.ones(3)
    assert isinstance(T, ss.Ellipsoid)
    np.testing.assert_allclose(T.c, E.c + 1)
    P = E.project([2, 0])
    assert isinstance(P, ss.Ellipsoid)
    np.testing.assert_allclose(P.Q, E.Q[np.ix_([2, 0], [2, 0])])


def test_symmetric_square_root_reproduces_q():
    E = random_ellipsoid(6, rank=2)
    np.testing.assert_allclose(E.root @ E.root.T, E.Q, atol=1e-12)
    np.testing.assert_allclose(E.root, E.root.T)


def test_samples_lie_inside_and_fill_the_ellipse():
    E = ss.Ellipsoid([1.0, -1.0], np.array([[4.0, 1.0], [1.0, 1.0]]))
    x = E.sample(np.random.default_rng(0), size=4000)
    q = np.einsum("ij,jk,ik->i", x - E.c, np.linalg.inv(E.Q), x - E.c)
    assert np.all(q <= 1.0 + 1e-12)
    # uniform in a 2-D ellipse: P(q ≤ 1/4) = 1/4
    assert np.mean(q <= 0.25) == pytest.approx(0.25, abs=0.03)


def test_chebyshev_centre_is_the_centre():
    E = random_ellipsoid(7)
    assert E.center("chebyshev").tolist() == E.c.tolist()
    np.testing.assert_allclose(E.center(), E.c)


def test_ellipsoid_plus_zonotope_is_a_lazy_sum_with_summed_supports():
    E, Z = random_ellipsoid(8), ss.Zonotope(np.eye(3), np.zeros(3))
    S = E + Z
    assert isinstance(S, ss.MinkowskiSum)
    D = np.random.default_rng(2).standard_normal((5, 3))
    np.testing.assert_allclose(S.support_many(D), E.support_many(D) + Z.support_many(D))


def test_a_nearly_symmetric_q_is_symmetrized():
    Q = np.array([[2.0, 1.0], [1.0 + 1e-12, 1.0]])
    E = ss.Ellipsoid([0.0, 0.0], Q)
    np.testing.assert_array_equal(E.Q, E.Q.T)
