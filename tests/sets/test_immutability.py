"""Sets are immutable: their arrays are read-only copies and no operation changes an operand."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss

D = np.random.default_rng(0).standard_normal((6, 2))


def make_sets():
    return {
        "box": ss.Box([0.0, 0.0], [1.0, 2.0]),
        "zonotope": ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.0, 0.0]),
        "cz": ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[0.5]),
        "hpolytope": ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
        "ellipsoid": ss.Ellipsoid([0.0, 0.0], np.diag([4.0, 1.0])),
        "reals": ss.Reals(2),
        "lazy sum": ss.Ellipsoid([0.0, 0.0], np.eye(2)) + ss.HPolytope([[1.0, 0.0]], [0.0]),
    }


ARRAYS = {
    "box": ("lo", "hi"), "zonotope": ("G", "c"), "cz": ("G", "c", "A", "b", "h"),
    "hpolytope": ("H", "k"), "ellipsoid": ("c", "Q"), "reals": ("G", "c", "A", "b", "h"),
}


@pytest.mark.parametrize("name", ARRAYS)
def test_the_arrays_of_a_set_are_read_only(name):
    S = make_sets()[name]
    for attr in ARRAYS[name]:
        arr = getattr(S, attr)
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0.0


def test_lazy_sets_keep_read_only_copies_of_their_matrices():
    M, R, v = np.array([[1.0, 2.0], [0.0, 1.0]]), np.array([[1.0, 1.0]]), np.array([1.0, -1.0])
    P = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
    L = ss.LinearMap(M, P, offset=v)
    G = ss.GeneralizedIntersection(P, R, ss.Ellipsoid([0.0], [[1.0]]))
    before = L.support_many(D), G.support_many(D)
    M[:] = 7.0
    R[:] = 7.0
    v[:] = 7.0
    np.testing.assert_array_equal(L.support_many(D), before[0])
    np.testing.assert_array_equal(G.support_many(D), before[1])
    for arr in (L.M, L.offset, G.R):
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0.0


def test_mutating_the_caller_s_arrays_after_construction_changes_nothing():
    lo, hi = np.zeros(2), np.ones(2)
    G, c, A, b, h = np.eye(2), np.zeros(2), np.array([[1.0, 1.0]]), np.array([0.5]), np.ones(2)
    H, k, Q = np.vstack([np.eye(2), -np.eye(2)]), np.ones(4), np.eye(2)
    Gs, As = sp.csc_matrix(G), sp.csc_matrix(A)
    sets = [ss.Box(lo, hi), ss.Zonotope(G, c), ss.ConstrainedZonotope(G, c, A=A, b=b, h=h),
            ss.ConstrainedZonotope(Gs, c, A=As, b=b), ss.HPolytope(H, k), ss.Ellipsoid(c, Q)]
    before = [S.support_many(D) for S in sets]
    for arr in (lo, hi, G, c, A, b, h, H, k, Q, Gs.data, As.data):
        arr[...] = 3.0
    for S, values in zip(sets, before):
        np.testing.assert_array_equal(S.support_many(D), values)


@pytest.mark.parametrize("left", ["box", "zonotope", "cz", "hpolytope", "ellipsoid", "reals",
                                  "lazy sum"])
@pytest.mark.parametrize("right", ["box", "cz", "ellipsoid"])
def test_no_operation_changes_the_supports_of_its_operands(left, right):
    sets = make_sets()
    S, T = sets[left], sets[right] + np.array([0.25, 0.25])
    before = S.support_many(D), T.support_many(D)
    M = np.array([[2.0, 1.0], [0.0, 1.0]])
    results = [S & T, T & S, S + T, S - T, S * T, M @ S, S + np.ones(2), S.project([1]),
               S.intersect_preimage(M, T), T.intersect_preimage(M, S), S.preimage(M)]
    for R in results:
        R.support_many(np.ones((1, R.dim)))  # query the results: solver caches must not leak back
    np.testing.assert_array_equal(S.support_many(D), before[0])
    np.testing.assert_array_equal(T.support_many(D), before[1])


def test_an_intersection_leaves_its_operands_supports_and_factor_sets_unchanged():
    Z = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[0.5])
    before = Z.support_many(D)
    factors, A, b = Z.factors, Z.A.copy(), Z.b.copy()
    X = Z & ss.Box([0.4, -1.0], [0.6, 1.0])
    assert X.support([1.0, 0.0]) == pytest.approx(0.6, abs=1e-7)
    assert Z.factors is factors and X.factors is not factors
    np.testing.assert_array_equal(Z.A, A)
    np.testing.assert_array_equal(Z.b, b)
    np.testing.assert_array_equal(Z.support_many(D), before)
