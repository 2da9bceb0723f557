"""Hulls along time: the windowed brackets give each posterior's own hull, at a cost that stays flat."""

import numpy as np
import pytest

import setsmooth as ss
import setsmooth.filters.hulls_along_time as along
import setsmooth.filters.window_brackets as brackets
from setsmooth.filters.hulls_along_time import GAP_TOL, filtered_hulls
from setsmooth.papers.smoothing_examples import smoothing_example_31, smoothing_example_31_x0
from setsmooth.reliability.random_systems import base_case, in_regime


@pytest.fixture(autouse=True)
def windows_from_the_first_steps(monkeypatch):
    """Windows of 4 steps from k = 8 on (the default waits until they are cheaper than the
    posterior's own program): these short runs then test the brackets, not the crossover."""
    monkeypatch.setattr(along, "FIRST_WINDOW", 4)
    monkeypatch.setattr(along, "WINDOW_FACTOR", 2)


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


@pytest.mark.parametrize("case", ["example 31", "non-normal"])
def test_windows_stay_short_on_a_detectable_system(monkeypatch, case):
    """The cost per step is flat because the bracket closes in a window of bounded length; also on a
    non-normal system whose window matrices, with the states eliminated, would carry rounding bounds
    growing like |A|^L (reliability system 4: relative 3e-5 at 8 steps, 1e7 at 16), which no bracket
    survives: the windows keep the states."""
    closed = []
    bracketed = along._Run._bracketed

    def spy(run, k):
        step = bracketed(run, k)
        if isinstance(step, along._Step):
            closed.append(k)
        return step

    monkeypatch.setattr(along._Run, "_bracketed", spy)
    monkeypatch.setattr(along, "FIRST_WINDOW", 8)  # the default
    if case == "example 31":
        system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    else:
        drawn = base_case(2026, 4, T_range=(14, 14))
        system, X0 = drawn.system, drawn.X0
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


def test_a_known_input_and_a_time_varying_system_give_each_posteriors_own_hull():
    """The windows' engines are kept while their matrices repeat (a known input only moves b) and
    made anew when they differ (matrices varying with k)."""
    base, X0 = smoothing_example_31(), smoothing_example_31_x0()
    A, C = np.asarray(base.A_at(0)), np.asarray(base.C_at(0))
    E, F = np.asarray(base.E_at(0)), np.asarray(base.F_at(0))
    T = 14
    u = 0.3 * np.sin(np.arange(T + 1))[:, None]
    with_input = ss.LinearSystem(A, np.eye(2)[:, :1], C, E=E, F=F, W=base.W, V=base.V, u=u)
    varying = ss.LinearSystem([A * (1.0 + 0.01 * np.cos(k)) for k in range(T + 1)], None, C, E=E, F=F,
                              W=base.W, V=base.V)
    for system in (with_input, varying):
        xs, ys = ss.simulate(system, X0, T, np.random.default_rng(10))
        _assert_same_hulls(system, X0, ys, xs)


def test_kept_engines_bracket_like_fresh_ones():
    """A window's bracket from engines kept along the run equals the one from engines made for it
    alone (certified upper ends and inner values within 1e-9 of the width)."""
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 30, np.random.default_rng(11))
    D = np.vstack([np.eye(2), -np.eye(2)])
    run = along._Run(system, X0, ys, D)
    for k in range(25):
        run.settle(k)
    kept = run.windows.bracket(run.settled[16], ys, 16, 24)
    fresh = brackets.Windows(system, run.forms, D).bracket(run.settled[16], ys, 16, 24)
    width = kept[1][:2] + kept[1][2:]
    scale = np.concatenate([width, width])
    assert np.all(np.abs(kept[0] - fresh[0]) <= 1e-9 * scale)
    assert np.all(np.abs(kept[1] - fresh[1]) <= 1e-9 * scale)
    assert np.all(kept[0] >= kept[1])
    assert len(run.windows._outer) >= 1  # the run kept engines
