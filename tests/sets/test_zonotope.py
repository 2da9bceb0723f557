"""Zonotopes Z(G, c): support function, support points and interval hull in closed form."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss


def random_zonotope(seed=0, n=3, ng=5):
    rng = np.random.default_rng(seed)
    return ss.Zonotope(rng.standard_normal((n, ng)), rng.uniform(-1, 1, n))


def test_support_is_centre_term_plus_l1_norm_of_projected_generators():
    Z = random_zonotope()
    D = np.random.default_rng(1).standard_normal((15, 3))
    expected = D @ Z.c + np.abs(D @ Z.G).sum(axis=1)
    np.testing.assert_allclose(Z.support_many(D), expected, atol=1e-12)
    signs = np.array(list(itertools.product([-1, 1], repeat=Z.ng)))
    np.testing.assert_allclose(expected, ((signs @ Z.G.T + Z.c) @ D.T).max(axis=0), atol=1e-12)


def test_support_point_is_the_centre_plus_generators_signed_by_the_direction():
    Z = random_zonotope()
    d = np.array([0.3, -1.0, 2.0])
    p = Z.support_point(d)
    np.testing.assert_allclose(p, Z.c + Z.G @ np.sign(Z.G.T @ d))
    assert d @ p == pytest.approx(Z.support(d))
    assert Z.contains(p)


def test_interval_hull_radius_is_the_absolute_row_sum_of_the_generators():
    Z = random_zonotope()
    hull = Z.interval_hull()
    r = np.abs(Z.G).sum(axis=1)
    np.testing.assert_allclose(hull.lo, Z.c - r)
    np.testing.assert_allclose(hull.hi, Z.c + r)
    generic = Z.interval_hull(path="generic")
    np.testing.assert_allclose(generic.lo, hull.lo, atol=1e-7)
    np.testing.assert_allclose(generic.hi, hull.hi, atol=1e-7)


def test_a_zonotope_without_generators_is_its_centre():
    Z = ss.Zonotope(np.zeros((2, 0)), [1.0, 2.0])
    assert Z.ng == 0
    assert Z.support([1.0, 1.0]) == 3.0
    assert Z.support_point([1.0, 1.0]).tolist() == [1.0, 2.0]
    assert Z.diameter() == 0.0


def test_linear_map_of_a_zonotope_maps_generators_and_centre():
    Z = random_zonotope()
    M = np.random.default_rng(2).standard_normal((2, 3))
    for W in (M @ Z, sp.csr_matrix(M) @ Z):
        assert isinstance(W, ss.Zonotope)
        np.testing.assert_allclose(W.G, M @ Z.G)
        np.testing.assert_allclose(W.c, M @ Z.c)


def test_sum_of_zonotopes_concatenates_generators_and_adds_centres():
    Z, W = random_zonotope(0), random_zonotope(1, ng=2)
    S = Z + W
    assert isinstance(S, ss.Zonotope) and S.ng == Z.ng + W.ng
    np.testing.assert_allclose(S.c, Z.c + W.c)


def test_difference_of_zonotopes_is_the_sum_with_the_reflection():
    Z, W = random_zonotope(0), random_zonotope(1, ng=2)
    D = np.random.default_rng(3).standard_normal((5, 3))
    np.testing.assert_allclose((Z - W).support_many(D),
                               Z.support_many(D) + W.support_many(-D), atol=1e-12)
    np.testing.assert_allclose((-Z).support_many(D), Z.support_many(-D), atol=1e-12)


def test_product_of_zonotopes_is_block_diagonal():
    Z, W = random_zonotope(0, n=2, ng=3), random_zonotope(1, n=1, ng=2)
    P = Z * W
    assert isinstance(P, ss.Zonotope) and P.dim == 3 and P.ng == 5
    np.testing.assert_allclose(P.G[:2, 3:], 0.0)
    np.testing.assert_allclose(P.G[2:, :3], 0.0)


def test_projection_selects_rows():
    Z = random_zonotope()
    P = Z.project([2, 1])
    assert isinstance(P, ss.Zonotope)
    np.testing.assert_allclose(P.G, Z.G[[2, 1]])


def test_cz_form_has_no_constraints_and_unit_bounds():
    Z = random_zonotope()
    cz = Z.to_constrained_zonotope()
    assert cz.nc == 0 and cz.h.tolist() == [1.0] * Z.ng
    D = np.random.default_rng(4).standard_normal((6, 3))
    np.testing.assert_allclose(cz.support_many(D), Z.support_many(D), atol=1e-12)
    assert not Z.is_empty()


def test_repr_names_dimension_and_generators():
    assert repr(random_zonotope()) == "Zonotope(dim=3, ng=5)"


def test_product_of_large_zonotopes_keeps_a_dense_generator_matrix():
    n = 40  # the block-diagonal G has more entries than the sparse-storage threshold
    Z = ss.Zonotope(np.eye(n), np.zeros(n))
    P = Z * Z
    assert isinstance(P.G, np.ndarray) and P.G.shape == (2 * n, 2 * n)
    assert P.support(np.ones(2 * n)) == 2 * n
