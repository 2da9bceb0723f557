"""The recursion's sets are certified against the model data
(`setsmooth.trajectories.recursion_certificates`)."""

from __future__ import annotations

import pickle

import numpy as np

import setsmooth as ss
from setsmooth.trajectories.recursion_certificates import certified_against_data


def _system(offset: float = 0.0):
    rng = np.random.default_rng(7)
    A = np.array([[0.9, 0.35], [-0.2, 0.8]])
    box = ss.Box([-0.1, -0.1], [0.1, 0.1])
    o = np.array([offset, -offset])
    u = np.tile((np.eye(2) - A) @ o, (12, 1))
    system = ss.LinearSystem(A, np.eye(2), [[1.0, 0.0]], W=box, V=ss.Box([-0.2], [0.2]), u=u)
    xs = [o + rng.uniform(-0.5, 0.5, 2)]
    for k in range(12):
        xs.append(A @ xs[-1] + rng.uniform(-0.1, 0.1, 2) + u[k])
    ys = np.array([[x[0] + rng.uniform(-0.2, 0.2)] for x in xs])
    X0 = ss.Box(o - 0.5, o + 0.5)
    return system, X0, ys


def test_recursion_sets_take_their_certified_hulls_from_the_trajectory_projections():
    system, X0, ys = _system(offset=1e6)
    filtered = ss.classical_filter(system, X0, ys, form="recursion")
    views = ss.classical_filter(system, X0, ys)            # the trajectory views of the same data
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion")
    reference = ss.optimal_smoother(system, X0, ys, method="trajectory")
    for ours, theirs in ((filtered, views), (smoothed, reference)):
        for S, R in zip(ours, theirs):
            assert type(S) is ss.ConstrainedZonotope and S._reference is not None
            certified, exact = S.interval_hull(certified=True), R.interval_hull(certified=True)
            assert np.array_equal(certified.lo, exact.lo) and np.array_equal(certified.hi, exact.hi)
            plain = S.interval_hull(certified=False)             # the recursion's own program
            assert np.all(certified.lo <= plain.lo + 1e-9) and np.all(plain.hi <= certified.hi + 1e-9)
            assert np.allclose(plain.lo, exact.lo, rtol=0, atol=1e-7)
            assert np.allclose(plain.hi, exact.hi, rtol=0, atol=1e-7)


def test_a_set_certified_against_the_data_pickles_and_certifies_again():
    system, X0, ys = _system()
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion")
    S = smoothed[3]
    before = S.interval_hull(certified=True)
    T = pickle.loads(pickle.dumps(S))
    after = T.interval_hull(certified=True)
    assert T._reference is not None
    assert np.array_equal(before.lo, after.lo) and np.array_equal(before.hi, after.hi)


def test_outer_bounds_and_plain_lists_are_not_certified_against_the_exact_sets():
    system, X0, ys = _system()
    reduced = ss.classical_filter(system, X0, ys, reduce=ss.Girard(4))
    outer = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=reduced)
    assert all(getattr(S, "_reference", None) is None for S in outer)
    plain_list = list(ss.classical_filter(system, X0, ys, form="recursion"))
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=plain_list)
    assert all(S._reference is None for S in smoothed[:-1])


def test_only_exact_constrained_zonotopes_get_a_reference():
    system, X0, ys = _system()
    sets = [ss.Box([-1.0, -1.0], [1.0, 1.0]), X0.to_constrained_zonotope()]
    out = certified_against_data(sets, system, X0, ys[:2], "filtered")
    assert out[0] is sets[0] and out[1]._reference is not None
