"""Hulls along time: the windowed brackets give each posterior's own hull, at a cost that stays flat."""

import numpy as np
import pytest

import setsmooth as ss
import setsmooth.filters.hulls_along_time as along
import setsmooth.filters.window_brackets as brackets
from setsmooth.filters.hulls_along_time import GAP_TOL, filtered_hulls
from setsmooth.papers.smoothing_examples import smoothing_example_31, smoothing_example_31_x0
from setsmooth.reliability.random_systems import base_case, in_regime


@pytest.fixture(autouse=True, params=["fixed", "trajectory"])
def windows_from_the_first_steps(monkeypatch, request):
    """Windows of 4 steps from k = 8 on (the default waits until they are cheaper than the
    posterior's own program): these short runs then test the brackets, not the crossover. Every
    test runs twice: with the windows a time-invariant system gets (`FixedWindows`) and with the
    trajectory windows of any system."""
    monkeypatch.setattr(along, "FIRST_WINDOW", 4)
    monkeypatch.setattr(along, "WINDOW_FACTOR", 2)
    monkeypatch.setattr(along, "FIXED_WINDOW_FACTOR", 2)
    if request.param == "trajectory":
        monkeypatch.setattr(along, "windows_for", brackets.TrajectoryWindows)
    return request.param


def _bounds(hulls):
    return np.array([h.lo for h in hulls]), np.array([h.hi for h in hulls])


def _own_hulls(system, X0, ys):
    """{certified: hulls} of each posterior's own program (plain and certified from one set of solves)."""
    posteriors = ss.classical_filter(system, X0, ys)
    return {flag: [P.interval_hull(certified=flag) for P in posteriors] for flag in (False, True)}


def _assert_same_hulls(system, X0, ys, xs):
    own = _own_hulls(system, X0, ys)
    plain_lo, plain_hi = _bounds(own[False])
    for certified in (True, False):
        lo, hi = _bounds(filtered_hulls(system, X0, ys, certified=certified, progress=False))
        own_lo, own_hi = _bounds(own[certified])
        width = own_hi - own_lo
        assert np.all(np.abs(lo - own_lo) <= 1e-6 * width), certified
        assert np.all(np.abs(hi - own_hi) <= 1e-6 * width), certified
        if certified:  # sound: the truth inside, and nothing inside the posterior's plain hull
            assert np.all(lo <= plain_lo + 1e-9 * width) and np.all(hi >= plain_hi - 1e-9 * width)
            assert np.all((lo <= xs) & (xs <= hi))


def test_windowed_hulls_equal_each_posteriors_own_hull_on_example_31():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    xs, ys = ss.simulate(system, X0, 16, np.random.default_rng(4))
    _assert_same_hulls(system, X0, ys, xs)


@pytest.mark.parametrize("index, regime", [(3, "scale1"), (5, "scale1e-06"), (1, "offset1e+06"),
                                           (8, "scale1e+03")])
def test_windowed_hulls_equal_own_hulls_on_random_systems_in_every_regime(index, regime):
    """CZ and box noises (indices 5..9 have CZ noises), thin, offset and large data."""
    case = in_regime(base_case(2026, index, T_range=(14, 14)), regime)
    _assert_same_hulls(case.system, case.X0, case.ys, case.xs)


def test_windows_stay_short_on_a_detectable_system(monkeypatch):
    """The cost per step is flat because the bracket closes in a window of bounded length."""
    closed = []
    bracketed = along._Run._bracketed

    def spy(run, k):
        step = bracketed(run, k)
        if isinstance(step, along._Step):
            closed.append(k)
        return step

    monkeypatch.setattr(along._Run, "_bracketed", spy)
    monkeypatch.setattr(along, "FIRST_WINDOW", 8)  # the default
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 60, np.random.default_rng(5))
    filtered_hulls(system, X0, ys, progress=False)
    # from k = 32 on, where a window of 16 steps may be tried, nearly every step is a bracket
    assert sum(k >= 32 for k in closed) >= 0.9 * (60 - 31)


def test_an_unclosable_bracket_falls_back_to_the_posteriors_own_program(monkeypatch):
    """A bracket that never closes (tolerance 0 and below) ends at window start 0: the exact program."""
    monkeypatch.setattr(along, "GAP_TOL", -1.0)
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    xs, ys = ss.simulate(system, X0, 12, np.random.default_rng(6))
    lo, hi = _bounds(filtered_hulls(system, X0, ys, certified=True, progress=False))
    own_lo, own_hi = _bounds(_own_hulls(system, X0, ys)[True])
    width = own_hi - own_lo
    assert np.all(np.abs(lo - own_lo) <= 1e-9 * width) and np.all(np.abs(hi - own_hi) <= 1e-9 * width)


def test_contradicting_data_give_empty_hulls_from_the_first_empty_posterior():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    xs, ys = ss.simulate(system, X0, 20, np.random.default_rng(7))
    ys = ys.copy()
    ys[15] += 50.0  # far outside every predicted output
    hulls = filtered_hulls(system, X0, ys, progress=False)
    first = next(k for k, h in enumerate(hulls) if h.is_empty())
    assert first == 15 and all(h.is_empty() for h in hulls[15:])
    with pytest.warns(ss.ModelInvalidationWarning):
        own = _own_hulls(system, X0, ys)[True]
    assert next(k for k, h in enumerate(own) if h.is_empty()) == 15


def test_gap_tolerance_is_below_the_accuracy_the_hulls_are_held_to():
    assert 0 < GAP_TOL <= 1e-7


def test_a_filter_results_tubes_come_along_time_and_agree_with_each_sets_own_hull():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    xs, ys = ss.simulate(system, X0, 14, np.random.default_rng(8))
    posteriors = ss.classical_filter(system, X0, ys)
    lo, hi = posteriors.lo, posteriors.hi
    assert set(posteriors._along_hulls) == {True}  # the tubes were computed along time
    own_lo, own_hi = _bounds(_own_hulls(system, X0, ys)[True])
    width = own_hi - own_lo
    assert np.all(np.abs(lo - own_lo) <= 1e-6 * width) and np.all(np.abs(hi - own_hi) <= 1e-6 * width)
    assert posteriors.contains_trajectory(xs).all() and np.all((lo <= xs) & (xs <= hi))


def test_a_result_whose_sets_were_replaced_takes_each_sets_own_hull():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 10, np.random.default_rng(9))
    posteriors = ss.classical_filter(system, X0, ys)
    posteriors[4] = ss.Box([-1.0, -1.0], [1.0, 1.0])
    assert posteriors.interval_hulls(progress=False)[4].hi.tolist() == [1.0, 1.0]
    assert "_along_hulls" not in posteriors.__dict__ or not posteriors._along_hulls


def test_a_time_varying_system_gets_trajectory_windows_and_a_known_input_fixed_ones(
        windows_from_the_first_steps):
    """The fixed windows need constant A, C, E, F (a known input is allowed); a system whose matrices
    vary gets the trajectory windows. Both give each posterior's own hull."""
    base, X0 = smoothing_example_31(), smoothing_example_31_x0()
    A, C = np.asarray(base.A_at(0)), np.asarray(base.C_at(0))
    E, F = np.asarray(base.E_at(0)), np.asarray(base.F_at(0))
    T = 14
    u = 0.3 * np.sin(np.arange(T + 1))[:, None]
    with_input = ss.LinearSystem(A, np.eye(2)[:, :1], C, E=E, F=F, W=base.W, V=base.V, u=u)
    varying = ss.LinearSystem([A * (1.0 + 0.01 * np.cos(k)) for k in range(T + 1)], None, C, E=E, F=F,
                              W=base.W, V=base.V)
    kinds = {"fixed": brackets.FixedWindows, "trajectory": brackets.TrajectoryWindows}
    for system, default in ((with_input, kinds[windows_from_the_first_steps]),
                            (varying, brackets.TrajectoryWindows)):
        assert isinstance(along.windows_for(system, (None, None, None), np.eye(2)), default)
        xs, ys = ss.simulate(system, X0, T, np.random.default_rng(10))
        _assert_same_hulls(system, X0, ys, xs)


def test_fixed_windows_bracket_like_trajectory_windows():
    """The two set-ups of the same window programs: certified upper ends within 1e-9 of the width of
    each other, both above the inner values, and the inner values equal."""
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 30, np.random.default_rng(11))
    D = np.vstack([np.eye(2), -np.eye(2)])
    run = along._Run(system, X0, ys, D)
    for k in range(12):
        run.settle(k)
    prior = run.settled[4]
    fixed = brackets.FixedWindows(system, D).bracket(prior, ys, 4, 11)
    trajectory = brackets.TrajectoryWindows(system, run.forms, D).bracket(prior, ys, 4, 11)
    width = fixed[1][:2] + fixed[1][2:]
    scale = np.concatenate([width, width])
    assert np.all(np.abs(fixed[0] - trajectory[0]) <= 1e-9 * scale)
    assert np.all(np.abs(fixed[1] - trajectory[1]) <= 1e-9 * scale)
    assert np.all(fixed[0] >= fixed[1]) and np.all(trajectory[0] >= trajectory[1])
