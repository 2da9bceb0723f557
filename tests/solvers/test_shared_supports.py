"""The interval hulls of CZs over one factor set, solved as one batch (`setsmooth.sets.shared_hulls`):
the smoothed ranges of the trajectory smoother, checked against each set's own hull."""

import threading

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.sets.shared_hulls import shared_interval_hulls
from setsmooth.solvers.shared_supports import shared_supports


def _smoother_problem(T=25, seed=3):
    A = np.array([[0.9, 0.2, 0.0], [-0.2, 0.9, 0.1], [0.0, 0.0, 0.95]])
    E = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, 0.05]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    # W a constrained zonotope (the unit box cut by (w_1 + w_2)/2 >= -0.8), V a box
    W = ss.ConstrainedZonotope([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [0.0, 0.0], [[0.5, 0.5, 1.0]], [0.2])
    system = ss.LinearSystem(A, None, C, E=E, F=np.eye(2), W=W, V=ss.Box([-0.5, -0.5], [0.5, 0.5]))
    X0 = ss.Box(-np.ones(3), np.ones(3))
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    return system, X0, xs, ys


def _smoothed(system, X0, ys):
    return ss.optimal_smoother(system, X0, ys, method="trajectory")


@pytest.mark.parametrize("certified", [True, None, False])
def test_shared_hulls_agree_with_each_sets_own(certified):
    system, X0, xs, ys = _smoother_problem()
    shared = shared_interval_hulls(list(_smoothed(system, X0, ys)), certified)
    own = [S.interval_hull(certified=certified) for S in _smoothed(system, X0, ys)]
    assert shared is not None and len(shared) == len(own)
    for a, b, x in zip(shared, own, xs):
        width = float(np.max(b.hi - b.lo))
        assert np.allclose(a.lo, b.lo, rtol=0, atol=1e-7 * width)
        assert np.allclose(a.hi, b.hi, rtol=0, atol=1e-7 * width)
        if certified is not False:  # certified hulls hold the true state
            assert np.all(a.lo <= x) and np.all(x <= a.hi)


def test_certified_shared_hulls_enclose_the_plain_ones_and_are_kept():
    system, X0, xs, ys = _smoother_problem()
    sets = _smoothed(system, X0, ys)
    certified = sets.interval_hulls(certified=True)
    plain = [S.interval_hull(certified=False) for S in _smoothed(system, X0, ys)]
    for c, p in zip(certified, plain):
        assert np.all(c.lo <= p.lo) and np.all(p.hi <= c.hi)
    # kept on the sets: asked again, the same box
    assert all(S.interval_hull(certified=True) is h for S, h in zip(sets, certified))


def test_shared_hulls_are_bit_for_bit_the_same_in_another_thread():
    system, X0, xs, ys = _smoother_problem(T=15)
    first = shared_interval_hulls(list(_smoothed(system, X0, ys)), True)
    other = {}
    thread = threading.Thread(target=lambda: other.setdefault(
        "hulls", shared_interval_hulls(list(_smoothed(system, X0, ys)), True)))
    thread.start()
    thread.join()
    for a, b in zip(first, other["hulls"]):
        assert np.array_equal(a.lo, b.lo) and np.array_equal(a.hi, b.hi)


def test_sets_that_do_not_share_a_factor_set_are_left_to_their_own_hulls():
    G = np.eye(2)
    Z1 = ss.ConstrainedZonotope(G, np.zeros(2), np.array([[1.0, 1.0]]), np.array([0.5]))
    Z2 = ss.ConstrainedZonotope(G, np.ones(2), np.array([[1.0, -1.0]]), np.array([0.0]))
    assert shared_interval_hulls([Z1, Z2], True) is None
    with pytest.raises(ValueError, match="share one factor set"):
        shared_supports([Z1._program, Z2._program], np.eye(2), True)
    assert shared_interval_hulls([Z1], True) is None  # one set: nothing to share


def test_inconsistent_data_give_empty_sets_through_each_sets_own_path():
    system, X0, xs, ys = _smoother_problem(T=6)
    ys = ys.copy()
    ys[4] += 50.0  # no trajectory explains it
    with pytest.warns(ss.ModelInvalidationWarning):
        smoothed = _smoothed(system, X0, ys)
    hulls = smoothed.interval_hulls(certified=True)
    assert all(h.is_empty() for h in hulls)
