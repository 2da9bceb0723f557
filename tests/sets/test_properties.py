"""Algebraic identities of support functions, checked on random sets of every representation.

h_{MS}(d) = h_S(Mᵀd), h_{S⊕T} = h_S + h_T, h_{S×T}(d₁, d₂) = h_S(d₁) + h_T(d₂), h_{S∩T} ≤ min(h_S, h_T);
the closed forms, the CZ fast path and the generic CVXPY path agree; support points are members that
attain the value; known members never exceed the support; certified values bound the solver's.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import setsmooth as ss
from setsmooth import tolerances

from . import strategies as sst

PROPERTY = settings(max_examples=30, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
FEW = settings(PROPERTY, max_examples=20)


def _absorbing_sum(a, b):
    with np.errstate(invalid="ignore"):
        out = a + b
    out[np.isneginf(a) | np.isneginf(b)] = -np.inf
    return out


@PROPERTY
@given(st.data())
def test_support_of_linear_map_equals_support_in_transposed_direction(data):
    n, m = data.draw(sst.dims()), data.draw(sst.dims())
    S = data.draw(sst.sets(m, depth=1), label="S")
    rng = data.draw(sst.rngs())
    M = rng.standard_normal((n, m))
    D = sst.directions(rng, n)
    sst.assert_supports_close((M @ S.set).support_many(D), S.set.support_many(D @ M))


@PROPERTY
@given(st.data())
def test_support_of_minkowski_sum_is_sum_of_supports(data):
    n = data.draw(sst.dims())
    S = data.draw(sst.sets(n, depth=1), label="S")
    T = data.draw(sst.sets(n, depth=1), label="T")
    D = sst.directions(data.draw(sst.rngs()), n)
    expected = _absorbing_sum(S.set.support_many(D), T.set.support_many(D))
    sst.assert_supports_close((S.set + T.set).support_many(D), expected)


@PROPERTY
@given(st.data())
def test_support_of_cartesian_product_splits_over_the_factors(data):
    n1, n2 = data.draw(sst.dims(3)), data.draw(sst.dims(3))
    S = data.draw(sst.sets(n1, depth=1), label="S")
    T = data.draw(sst.sets(n2, depth=1), label="T")
    D = sst.directions(data.draw(sst.rngs()), n1 + n2)
    expected = _absorbing_sum(S.set.support_many(D[:, :n1]), T.set.support_many(D[:, n1:]))
    product = S.set * T.set
    assert product.dim == n1 + n2
    sst.assert_supports_close(product.support_many(D), expected)


@PROPERTY
@given(st.data())
def test_support_of_intersection_is_at_most_the_smaller_support(data):
    n = data.draw(sst.dims())
    S = data.draw(sst.sets(n, depth=1), label="S")
    T = data.draw(sst.sets(n, depth=1, full=True), label="T")
    if len(S.members):
        T = sst._shift(T, S.members[0])
    D = sst.directions(data.draw(sst.rngs()), n)
    both = (S.set & T.set).support_many(D)
    bound = np.minimum(S.set.support_many(D), T.set.support_many(D))
    scale = sst.support_scale(both, bound)
    assert np.all(both <= bound + 1e-6 * scale)


@PROPERTY
@given(st.data())
def test_generalized_intersection_maps_into_the_constraint_set(data):
    n, q = data.draw(sst.dims()), data.draw(sst.dims(3))
    S = data.draw(sst.sets(n, depth=1), label="S")
    Y = data.draw(sst.sets(q, depth=1, full=True), label="Y")
    rng = data.draw(sst.rngs())
    R = rng.standard_normal((q, n))
    if len(S.members):
        Y = sst._shift(Y, R @ S.members[0])
    X = S.set.intersect_preimage(R, Y.set)
    D = sst.directions(rng, n)
    E = sst.directions(rng, q)
    inside_S, image = X.support_many(D), (R @ X).support_many(E)
    hs, hy = S.set.support_many(D), Y.set.support_many(E)
    scale = sst.support_scale(inside_S, image, hs, hy)
    assert np.all(inside_S <= hs + 1e-6 * scale)
    assert np.all(image <= hy + 1e-6 * scale)


@PROPERTY
@given(st.data())
def test_support_of_translate_shifts_by_the_direction_times_the_vector(data):
    n = data.draw(sst.dims())
    S = data.draw(sst.sets(n, depth=1), label="S")
    rng = data.draw(sst.rngs())
    v = rng.uniform(-2, 2, n)
    D = sst.directions(rng, n)
    sst.assert_supports_close((S.set + v).support_many(D), S.set.support_many(D) + D @ v)
    sst.assert_supports_close((S.set - v).support_many(D), S.set.support_many(D) - D @ v)


@PROPERTY
@given(st.data())
def test_support_of_projection_is_support_in_the_embedded_direction(data):
    m = data.draw(sst.dims())
    n = data.draw(st.integers(1, m))
    S = data.draw(sst.sets(m, depth=1), label="S")
    rng = data.draw(sst.rngs())
    idx = rng.permutation(m)[:n]
    D = sst.directions(rng, n)
    embedded = np.zeros((D.shape[0], m))
    embedded[:, idx] = D
    sst.assert_supports_close(S.set.project(idx).support_many(D), S.set.support_many(embedded))


@PROPERTY
@given(st.data())
def test_preimage_under_an_invertible_map_is_the_image_under_its_inverse(data):
    n = data.draw(sst.dims(4))
    S = data.draw(sst.sets(n, depth=1), label="S")
    rng = data.draw(sst.rngs())
    M = rng.standard_normal((n, n)) + 2 * np.eye(n)
    D = sst.directions(rng, n)
    sst.assert_supports_close(S.set.preimage(M).support_many(D),
                              (np.linalg.inv(M) @ S.set).support_many(D))


@PROPERTY
@given(st.data())
def test_generic_path_agrees_with_the_fast_path(data):
    S = data.draw(sst.sets(), label="S")
    D = sst.directions(data.draw(sst.rngs()), S.set.dim)
    sst.assert_supports_close(S.set.support_many(D, path="generic"),
                              S.set.support_many(D, path="auto"))


@PROPERTY
@given(st.data())
def test_intersection_with_the_whole_space_changes_no_support_value(data):
    # S ∩ ℝⁿ is a CZ with n equality constraints for every flattenable S, so the closed forms
    # (Box, Zonotope, unconstrained CZ) are compared with the sparse LP of the fast path.
    S = data.draw(sst.sets(flattenable=True), label="S")
    n = S.set.dim
    D = sst.directions(data.draw(sst.rngs()), n)
    same = S.set & ss.Reals(n)
    assert isinstance(same, ss.ConstrainedZonotope) and same.nc >= n
    sst.assert_supports_close(same.support_many(D), S.set.support_many(D))


@PROPERTY
@given(st.data())
def test_lazy_forms_equal_the_closed_forms(data):
    n = data.draw(sst.dims(4))
    S = data.draw(sst.sets(n, depth=1), label="S")
    T = data.draw(sst.sets(n, depth=1, full=True), label="T")
    rng = data.draw(sst.rngs())
    if len(S.members):
        T = sst._shift(T, S.members[0])
    M = rng.standard_normal((n, n))
    D = sst.directions(rng, n, k=4)
    pairs = [
        (ss.LinearMap(M, S.set), M @ S.set),
        (ss.MinkowskiSum(S.set, T.set), S.set + T.set),
        (ss.Intersection(S.set, T.set), S.set & T.set),
        (ss.GeneralizedIntersection(S.set, M, M @ T.set), S.set.intersect_preimage(M, M @ T.set)),
    ]
    for lazy, closed in pairs:
        sst.assert_supports_close(lazy.support_many(D, path="generic"), closed.support_many(D))
        sst.assert_supports_close(lazy.support_many(D), closed.support_many(D))


@PROPERTY
@given(st.data())
def test_support_points_are_members_that_attain_the_support(data):
    S = data.draw(sst.sets(), label="S")
    rng = data.draw(sst.rngs())
    for path in ("auto", "generic"):
        for d in sst.directions(rng, S.set.dim, k=3):
            value = S.set.support(d, path=path)
            point = S.set.support_point(d, path=path)
            if not np.isfinite(value):
                assert np.isnan(point).all()
                continue
            scale = 1.0 + abs(value) + np.abs(point).max()
            assert abs(d @ point - value) <= 1e-6 * scale
            assert S.set.contains(point, tol=1e-6 * scale)


@PROPERTY
@given(st.data())
def test_known_members_are_contained_and_never_exceed_the_support(data):
    S = data.draw(sst.sets(), label="S")
    D = sst.directions(data.draw(sst.rngs()), S.set.dim)
    values = S.set.support_many(D)
    if len(S.members) == 0:
        return
    scale = 1.0 + np.abs(S.members).max()
    assert np.all(S.members @ D.T <= values + 1e-6 * scale)
    for p in S.members:
        assert S.set.contains(p, tol=1e-6 * scale)
    assert not S.set.is_empty()


@FEW
@given(st.data())
def test_sampled_points_are_members_and_never_exceed_the_support(data):
    n = data.draw(sst.dims(3))
    S = data.draw(sst.full_dimensional(n), label="S")
    rng = data.draw(sst.rngs())
    points = S.set.sample(rng, size=5)
    assert points.shape == (5, n)
    D = sst.directions(rng, n)
    assert np.all(points @ D.T <= S.set.support_many(D) + 1e-9)
    assert all(S.set.contains(p) for p in points)


@PROPERTY
@given(st.data())
def test_certified_support_bounds_the_solver_value_from_above_and_tightly(data):
    S = data.draw(sst.sets(flattenable=True), label="S")
    n = S.set.dim
    D = sst.directions(data.draw(sst.rngs()), n)
    certified = S.set.support_many(D, certified=True)
    solved = S.set.support_many(D)
    assert np.array_equal(np.isinf(certified), np.isinf(solved))
    assert np.array_equal(certified[np.isinf(certified)], solved[np.isinf(solved)])
    scale = sst.support_scale(certified, solved)
    finite = np.isfinite(solved)
    # The solver's value may exceed the exact one by its feasibility error (SOLVER_TOL·scale); the
    # certified value never falls below the exact one (checked exactly against oracles elsewhere).
    assert np.all(certified[finite] >= solved[finite] - tolerances.SOLVER_TOL * scale)
    assert np.all(solved[finite] >= certified[finite] - 1e-6 * scale)


@PROPERTY
@given(st.data())
def test_interval_hull_and_emptiness_agree_between_paths(data):
    S = data.draw(sst.sets(), label="S")
    auto, generic = S.set.interval_hull(), S.set.interval_hull(path="generic")
    assert S.set.is_empty() == S.set.is_empty(path="generic") == auto.is_empty()
    if auto.is_empty():
        assert isinstance(auto, ss.EmptySet) and isinstance(generic, ss.EmptySet)
        assert S.set.diameter() == -np.inf
        return
    sst.assert_supports_close(auto.lo, generic.lo)
    sst.assert_supports_close(auto.hi, generic.hi)
    assert np.all(auto.lo <= auto.hi)
    D = sst.directions(data.draw(sst.rngs()), S.set.dim)
    hull_values = auto.support_many(D)
    values = S.set.support_many(D)
    assert np.all(values <= hull_values + 1e-6 * sst.support_scale(values, hull_values))
    width = np.max(auto.hi - auto.lo)
    assert S.set.diameter() == pytest.approx(width, rel=1e-9, abs=1e-9)
