import numpy as np
import pytest

import setsmooth as ss
from setsmooth.smoothers.linear import smoothing_step
from setsmooth.trajectories import TrajectorySet
from tests.estimation_helpers import (DIRECTIONS_2D, contains_by_support, example_31, singular_system,
                                      time_varying_system)
from tests.smoothers.polytope_oracle import brute_force_filter_and_smoother

SYSTEMS = {"example_31": example_31, "singular": singular_system, "time_varying": time_varying_system}


@pytest.mark.parametrize("name", SYSTEMS)
def test_true_state_lies_in_every_smoothed_set_which_lies_in_the_filtered_set(name):
    sys = SYSTEMS[name]()
    X0 = ss.Box([-3, -3], [3, 3])
    for seed in range(3):
        xs, ys = ss.simulate(sys, X0, 10, np.random.default_rng(100 + seed))
        posts = ss.classical_filter(sys, X0, ys)
        smoothed = ss.optimal_smoother(sys, X0, ys, posteriors=posts)
        for k in range(len(ys)):
            assert contains_by_support(smoothed[k], xs[k], DIRECTIONS_2D), (seed, k)
            h_s = smoothed[k].support_many(DIRECTIONS_2D)
            h_f = posts[k].support_many(DIRECTIONS_2D)
            assert np.all(h_s <= h_f + 1e-7 * (1 + np.abs(h_f))), (seed, k)


def test_filtered_and_smoothed_sets_equal_brute_force_polytopes():
    sys = example_31()
    x0_lo, x0_hi = np.array([-2.0, -2.0]), np.array([2.0, 2.0])
    X0 = ss.Box(x0_lo, x0_hi)
    for seed in range(3):
        xs, ys = ss.simulate(sys, X0, 6, np.random.default_rng(seed))
        posts = ss.classical_filter(sys, X0, ys)
        smoothed = ss.optimal_smoother(sys, X0, ys, posteriors=posts)
        oracle_posts, oracle_smoothed = brute_force_filter_and_smoother(
            sys.A_at(0), sys.E_at(0), sys.C_at(0), [-1.0], [1.0], np.array([-1.0, -1.0]), np.array([1.0, 1.0]),
            x0_lo, x0_hi, ys)
        for ours, theirs in zip(posts + smoothed, oracle_posts + oracle_smoothed):
            expected = (theirs @ DIRECTIONS_2D.T).max(axis=0)
            assert np.allclose(ours.support_many(DIRECTIONS_2D), expected, atol=1e-6, rtol=1e-6)


def test_smoother_is_exact_for_singular_transition_matrices():
    """With Φ of rank 1 the smoothed set must keep ker(Φ) (smoothing (16)); compare with brute force."""
    sys = singular_system()
    X0 = ss.Box([-2, -2], [2, 2])
    xs, ys = ss.simulate(sys, X0, 5, np.random.default_rng(4))
    posts = ss.classical_filter(sys, X0, ys)
    smoothed = ss.optimal_smoother(sys, X0, ys, posteriors=posts)
    _, oracle = brute_force_filter_and_smoother(
        sys.A_at(0), sys.E_at(0), sys.C_at(0), [-0.5], [0.5], np.array([-1.0]), np.array([1.0]),
        np.array([-2.0, -2.0]), np.array([2.0, 2.0]), ys)
    for ours, theirs in zip(smoothed, oracle):
        assert np.allclose(ours.support_many(DIRECTIONS_2D), (theirs @ DIRECTIONS_2D.T).max(axis=0),
                           atol=1e-6)


def test_smoothing_step_on_czs_is_proposition_1():
    """Eq. (24) with ⟦−w⟧ = Z(−G_w, −c_w, …): the smoothed CZ's data are the stacked blocks."""
    sys = example_31()
    post = ss.Zonotope([[1.0, 0.2], [0.0, 0.7]], [0.1, 0.0]).to_constrained_zonotope()
    nxt = ss.ConstrainedZonotope([[0.5, 0.1, 0.0], [0.0, 0.3, 0.4]], [0.2, 0.1], A=[[1.0, 1.0, 0.5]], b=[0.3])
    S = smoothing_step(sys, 0, post, nxt)
    Phi, Gamma = sys.A_at(0), sys.E_at(0)
    Gw = np.array([[1.0]])
    assert np.allclose(np.asarray(S.G), np.hstack([post.G, np.zeros((2, 4))]))
    expected_A = np.zeros((3, 6))
    expected_A[0, 3:5] = nxt.A[0, :2]
    expected_A[0, 2:5] = nxt.A[0]
    expected_A[1:, :2] = Phi @ post.G
    expected_A[1:, 2:5] = -nxt.G
    expected_A[1:, 5:] = Gamma @ Gw  # −(Γ(−G_w)) : the generator of −w enters with a minus sign
    assert np.allclose(np.asarray(S.A.todense() if hasattr(S.A, "todense") else S.A), expected_A)
    assert np.allclose(S.b, np.concatenate([nxt.b, nxt.c - Phi @ post.c]))


def test_empty_data_give_empty_smoothed_sets():
    sys = example_31()
    X0 = ss.Box([-1, -1], [1, 1])
    ys = np.array([[0.0, 0.0], [0.0, 0.0], [80.0, 80.0]])
    smoothed = ss.optimal_smoother(sys, X0, ys)
    assert all(S.is_empty() for S in smoothed)


def test_smoother_rejects_an_unknown_method():
    with pytest.raises(ValueError, match="method must be one of"):
        ss.optimal_smoother(example_31(), ss.Box([-1, -1], [1, 1]), np.zeros((2, 2)), method="rts")


def test_auto_takes_the_trajectory_form_for_cz_sets_and_gives_the_recursion_sets():
    sys = example_31()
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, X0, 6, np.random.default_rng(21))
    auto = ss.optimal_smoother(sys, X0, ys)
    # The trajectory form's signature: every smoothed set is a projection of one shared factor set.
    assert len({id(S.factors) for S in auto}) == 1
    recursion = ss.optimal_smoother(sys, X0, ys, method="recursion")
    for a, r in zip(auto, recursion):
        assert np.allclose(a.support_many(DIRECTIONS_2D), r.support_many(DIRECTIONS_2D), atol=1e-6)


def test_auto_takes_the_trajectory_form_when_a_noise_has_no_cz_form():
    base = example_31()
    sys = ss.LinearSystem(base.A_at(0), None, base.C_at(0), E=base.E_at(0), F=base.F_at(0),
                          W=ss.Ellipsoid([0.0], [[1.0]]), V=base.V)
    X0 = ss.Box([-3, -3], [3, 3])
    xs, ys = ss.simulate(sys, X0, 3, np.random.default_rng(2))
    auto = ss.optimal_smoother(sys, X0, ys)
    # Projections of one lazy trajectory set (one compiled problem), not the recursion's lazy sets.
    assert len({id(S.S) for S in auto}) == 1
    assert isinstance(auto[0].S, TrajectorySet)
    for k, S in enumerate(auto):
        assert S.contains(xs[k], tol=1e-6)


def test_auto_with_given_posteriors_uses_them_in_the_recursion():
    sys = example_31()
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, X0, 4, np.random.default_rng(3))
    posts = ss.classical_filter(sys, X0, ys)
    smoothed = ss.optimal_smoother(sys, X0, ys, posteriors=posts)
    assert smoothed[-1] is posts[-1]


def test_posteriors_with_the_trajectory_form_are_refused():
    sys = example_31()
    X0 = ss.Box([-3, -3], [3, 3])
    ys = np.zeros((3, 2))
    posts = ss.classical_filter(sys, X0, ys)
    with pytest.raises(ValueError, match="posteriors= is only used by method='recursion'"):
        ss.optimal_smoother(sys, X0, ys, method="trajectory", posteriors=posts)
