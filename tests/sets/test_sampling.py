"""Uniform sampling by rejection from the interval hull."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.sets.sampling import rejection_sample

TRIANGLE = ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [1.0, 0.0, 0.0])


def test_rejection_samples_are_members_and_reproducible():
    a = TRIANGLE.sample(np.random.default_rng(0), size=30)
    assert a.shape == (30, 2)
    assert np.all(a.sum(axis=1) <= 1.0) and np.all(a >= 0.0)
    np.testing.assert_array_equal(a, TRIANGLE.sample(np.random.default_rng(0), size=30))


def test_rejection_samples_are_uniform():
    # The corner triangle {x1 + x2 ≤ 1/2} holds a quarter of the area.
    a = rejection_sample(TRIANGLE, np.random.default_rng(1), size=400)
    assert np.mean(a.sum(axis=1) <= 0.5) == pytest.approx(0.25, abs=0.06)


def test_zonotope_and_cz_samples_lie_in_the_set():
    rng = np.random.default_rng(2)
    Z = ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.0, 0.0]) & ss.Box([-0.5, -2], [2, 2])
    for p in Z.sample(rng, size=10):
        assert Z.contains(p)
        assert p[0] >= -0.5 - 1e-9


def test_sampling_needs_a_non_empty_bounded_set_with_volume():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="empty set"):
        rejection_sample(ss.ConstrainedZonotope(np.eye(1), [0], A=[[0.0]], b=[1.0]), rng)
    with pytest.raises(ValueError, match="unbounded"):
        rejection_sample(ss.HPolytope([[1.0, 0.0]], [0.0]), rng)
    # A flat set without a CZ form (the diagonal segment as an H-polytope) is found by rejection.
    flat = ss.HPolytope([[1.0, -1.0], [-1.0, 1.0], [1.0, 0.0], [-1.0, 0.0]], [0.0, 0.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="too thin"):
        rejection_sample(flat, rng, max_tries=50)
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        rejection_sample(TRIANGLE, np.random.RandomState(0))


def test_sampling_a_flat_constrained_zonotope_fails_at_once_naming_the_reason():
    # A segment in the plane (two generators, one constraint): rejection can never accept.
    W = ss.ConstrainedZonotope(G=0.1 * np.eye(2), c=np.zeros(2), A=[[1.0, 0.5]], b=[0.2])
    with pytest.raises(ValueError, match="affine subspace of dimension 1 < 2"):
        W.sample(np.random.default_rng(0), 1)
    with pytest.raises(ValueError, match="no interior"):
        ss.Zonotope(G=[[1.0], [1.0]], c=[0.0, 0.0]).sample(np.random.default_rng(0), 1)


def test_a_full_dimensional_constrained_zonotope_is_not_called_flat():
    from setsmooth.sets.sampling import affine_rank

    Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=np.zeros((0, 2)), b=np.zeros(0))
    assert affine_rank(Z) == 2
    T = ss.ConstrainedZonotope([[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], [0.0, 0.0], A=[[1.0, 1.0, 1.0]], b=[1.0])
    assert affine_rank(T) == 2
    assert T.sample(np.random.default_rng(1), 3).shape == (3, 2)
