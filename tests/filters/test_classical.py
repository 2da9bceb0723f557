import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.filters.steps import predict, update
from tests.estimation_helpers import (DIRECTIONS_2D, contains_by_support, example_31, singular_system,
                                      time_varying_system)

SYSTEMS = {"example_31": example_31, "singular": singular_system, "time_varying": time_varying_system}


@pytest.mark.parametrize("name", SYSTEMS)
def test_true_state_lies_in_every_posterior(name):
    sys = SYSTEMS[name]()
    X0 = ss.Box([-3, -3], [3, 3])
    for seed in range(8):
        xs, ys = ss.simulate(sys, X0, 15, np.random.default_rng(seed))
        for k, post in enumerate(ss.classical_filter(sys, X0, ys)):
            assert contains_by_support(post, xs[k], DIRECTIONS_2D), (seed, k)


def test_filter_with_cz_inputs_is_exactly_stability_20_and_21():
    sys = example_31()
    X0 = ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.2, -0.1]).to_constrained_zonotope()
    y = np.array([0.3, -0.2])
    post = update(sys, 0, X0, y)
    # (21): Z([G 0], c, [[A, 0], [0, A_v], [C G, −(−D G_v)]], [b; b_v; y − D c_v − C c], [h; h_v])
    Gv = np.eye(2)
    assert np.allclose(_dense(post.G), np.hstack([X0.G, np.zeros((2, 2))]))
    assert np.allclose(post.c, X0.c)
    assert np.allclose(_dense(post.A), np.hstack([sys.C_at(0) @ X0.G, sys.F_at(0) @ Gv]))
    assert np.allclose(post.b, y - sys.C_at(0) @ X0.c)
    prior = predict(sys, 0, post)
    # (20): Z([A G, B G_w], A c + B c_w, blkdiag(A, A_w), [b; b_w], [h; h_w])
    assert np.allclose(_dense(prior.G), np.hstack([sys.A_at(0) @ _dense(post.G), sys.E_at(0)]))
    assert np.allclose(prior.c, sys.A_at(0) @ post.c)
    assert np.allclose(_dense(prior.A), np.hstack([_dense(post.A), np.zeros((2, 1))]))
    assert np.allclose(prior.h, np.concatenate([post.h, [1.0]]))


def test_inconsistent_measurements_give_empty_posteriors_that_stay_empty():
    sys = example_31()
    X0 = ss.Box([-1, -1], [1, 1])
    xs, ys = ss.simulate(sys, X0, 6, np.random.default_rng(0))
    ys[3] += 100.0
    posts = ss.classical_filter(sys, X0, ys)
    assert not any(p.is_empty() for p in posts[:3])
    assert all(isinstance(p, ss.EmptySet) for p in posts[3:])
    assert posts[4].support([1.0, 0.0]) == -np.inf


def test_without_detection_an_empty_posterior_is_still_reported_empty():
    sys = example_31()
    X0 = ss.Box([-1, -1], [1, 1])
    ys = np.array([[0.0, 0.0], [50.0, 50.0]])
    posts = ss.classical_filter(sys, X0, ys, detect_empty=False)
    assert isinstance(posts[1], ss.ConstrainedZonotope) and posts[1].is_empty()
    assert posts[1].interval_hull().is_empty()


def test_filter_works_on_sets_without_a_cz_form():
    """An ellipsoidal ⟦x_0⟧ keeps the sets exact as lazy sets queried through CVXPY."""
    sys = example_31()
    X0 = ss.Ellipsoid([0.0, 0.0], np.diag([4.0, 1.0]))
    xs, ys = ss.simulate(sys, X0, 3, np.random.default_rng(2))
    posts = ss.classical_filter(sys, X0, ys)
    assert not isinstance(posts[-1], ss.ConstrainedZonotope)
    for k, post in enumerate(posts):
        values = post.support_many(DIRECTIONS_2D)
        assert np.all(DIRECTIONS_2D @ xs[k] <= values + 1e-6)


@pytest.mark.parametrize("bad, match", [
    (np.zeros((3, 3)), r"ys must have shape \(T\+1, m=2\)"),
    (np.full((3, 2), np.nan), "NaN"),
])
def test_filter_rejects_bad_measurements(bad, match):
    with pytest.raises(ValueError, match=match):
        ss.classical_filter(example_31(), ss.Box([-1, -1], [1, 1]), bad)


def test_filter_rejects_an_initial_set_of_the_wrong_dimension():
    with pytest.raises(ValueError, match="X0 must be a ConvexSet of dimension n = 2"):
        ss.classical_filter(example_31(), ss.Box([-1], [1]), np.zeros((2, 2)))


def _dense(M):
    return M.toarray() if sp.issparse(M) else np.asarray(M)


@pytest.mark.parametrize("bad_step", [None, 0, 5, 11, 12])
def test_emptiness_is_settled_by_one_program_per_data_set_with_the_per_step_answers(bad_step, monkeypatch):
    """Bisection on the monotone emptiness gives EmptySet from exactly the step the per-step checks
    find, with at most 1 + ⌈log₂(T + 1)⌉ feasibility programs (one when the data are consistent)."""
    sys = example_31()
    X0 = ss.Box([-1, -1], [1, 1])
    _, ys = ss.simulate(sys, X0, 12, np.random.default_rng(13))
    if bad_step is not None:
        ys[bad_step] += 100.0
    per_step = [P.is_empty() for P in ss.classical_filter(sys, X0, ys, detect_empty=False)]
    calls = []
    original = ss.ConstrainedZonotope._is_empty
    monkeypatch.setattr(ss.ConstrainedZonotope, "_is_empty", lambda self: calls.append(1) or original(self))
    posts = ss.classical_filter(sys, X0, ys)
    assert [isinstance(P, ss.EmptySet) for P in posts] == per_step
    first = len(ys) if bad_step is None else bad_step
    assert per_step == [k >= first for k in range(len(ys))]
    assert len(calls) == 1 if bad_step is None else len(calls) <= 1 + int(np.ceil(np.log2(len(ys))))


def test_thin_posteriors_of_precise_sensors_contain_the_true_state():
    """Noise 1e-6 beside a prior box of size 5: the posteriors are slivers 2e-6 thin across the
    measured directions. The default filter's views (free factors: the states) rejected the true
    state at k = 0 in 11 of 12 systems, at any tolerance, while their hulls held it: the membership
    program had the states in the units of the thin measurement rows (|η| ~ 1e7). Every posterior
    of every system now holds the truth, and its certified hull holds it too."""
    from setsmooth.analysis.random_systems import random_observable_system

    rng = np.random.default_rng(61)
    for _ in range(8):
        n, m = 4, 2
        plant = random_observable_system(rng, n, n, m)
        W, V = ss.Box(-1e-6 * np.ones(n), 1e-6 * np.ones(n)), ss.Box(-1e-6 * np.ones(m), 1e-6 * np.ones(m))
        system = ss.LinearSystem(plant.A, None, plant.C, W=W, V=V)
        X0 = ss.Box(-5 * np.ones(n), 5 * np.ones(n))
        xs, ys = ss.simulate(system, X0, 4, rng)
        posteriors = ss.classical_filter(system, X0, ys)
        for k, (post, x) in enumerate(zip(posteriors, xs)):
            assert post.contains(x), k
            hull = post.interval_hull(certified=True)
            assert np.all(hull.lo <= x) and np.all(x <= hull.hi), k


def test_consistent_thin_data_are_never_called_empty():
    """A 6-state ``control.drss`` system (NumPy seed 9) with one output and noise 1e-6 beside a
    prior box of size 5: the measurements pin the states to 1e-6 along a few directions, and the
    presolved rows' right-hand sides were ~5e7 where the bounded factors move them by O(1). The
    elastic phase-one program then found t* = 2.4 and called the k = 2 posterior empty, although it
    holds the true state (and k = 3 was non-empty). Posed around the free factors' nominal point
    (`setsmooth.solvers.free_factors.nominal_free_point`) every posterior is non-empty and holds the
    truth, in the default form and the recursion form alike."""
    import control

    state = np.random.get_state()
    try:
        np.random.seed(9)
        plant = control.drss(6, 1, 6)
    finally:
        np.random.set_state(state)
    n, m = 6, 1
    W, V = ss.Box(-1e-6 * np.ones(n), 1e-6 * np.ones(n)), ss.Box(-1e-6 * np.ones(m), 1e-6 * np.ones(m))
    system = ss.LinearSystem(plant.A, None, plant.C, W=W, V=V)
    X0 = ss.Box(-5 * np.ones(n), 5 * np.ones(n))
    xs, ys = ss.simulate(system, X0, 3, np.random.default_rng(9))
    for form in ("auto", "recursion"):
        posteriors = ss.classical_filter(system, X0, ys, form=form)
        assert posteriors.first_empty is None, form
        for k, (post, x) in enumerate(zip(posteriors, xs)):
            assert not post.is_empty(), (form, k)
            assert post.contains(x), (form, k)
