"""One result protocol: every estimator's result has lo, hi, centers, diameters, first_empty,
contains_trajectory, plot_tubes and len, whatever else it carries."""

from __future__ import annotations

import inspect

import control
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.papers.rethinking_examples import (rethinking_example_27,  # noqa: E402
                                                  rethinking_example_30_joint_range)
from setsmooth.papers.smoothing_examples import eta_33, measurement_interval_34  # noqa: E402

T = 8
A = np.array([[1.0, 0.1], [-0.2, 0.95]])


def _linear():
    plant = control.ss(A, 0.1 * np.eye(2), [[1.0, 0.0]], 0, dt=True)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-0.1], [0.1]),
                                             noise_inputs=[0, 1])
    X0 = ss.Box([-1, -1], [1, 1])
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(2))
    return system, X0, xs, ys


def _lsu(run):
    model = ss.LSUModel(A=A, B=np.zeros((2, 1)), C=[[1.0, 0.0]], omega=[0.1, 0.1], v=[0.1],
                        x1_lo=[-1, -1], x1_hi=[1, 1])
    us = np.zeros((T + 1, 1))
    xs, ys = model.simulate(us, np.random.default_rng(2))
    return run(model, ys, us), xs


def _intervals(smooth: bool):
    system = ss.paper_examples.smoothing_example_33()
    xs, ys = ss.simulate(system, ss.Box([-5.0], [5.0]), T, np.random.default_rng(2))
    filtered = ss.interval_filter(eta_33, (-1, 1), (-5, 5), ys[:, 0], measurement_interval_34)
    result = ss.interval_smoother(eta_33, (-1, 1), filtered) if smooth else filtered
    return result, xs[:, 0]


def _rethinking(sampled: bool):
    system = rethinking_example_27()
    xs, ys = system.simulate(T, np.random.default_rng(2))
    if sampled:
        result = ss.sampled_optimal_filter(system, ys, np.random.default_rng(3), n_samples=200)
        return result, result.centers  # inner approximations: the truth may lie outside, the centres not
    return ss.classical_interval_filter(system, ys[0]), xs[0]


def _joint(smoother: bool):
    system = ss.rethinking_examples.rethinking_example_30()
    X0 = ss.rethinking_examples.rethinking_example_30_x0()
    joint = rethinking_example_30_joint_range(T)
    # identical process noise (the joint range): one w for every step
    w = system.W.sample(np.random.default_rng(3), 1)[0]
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(2), ws=np.tile(w, (T, 1)))
    run = ss.optimal_joint_smoother if smoother else ss.optimal_filter
    return run(system, joint, ys), xs


def _on_linear(run):
    system, X0, xs, ys = _linear()
    return run(system, X0, ys), xs


def _kalman(run):
    # the uniform noises' covariances: w ~ U[−1, 1]² (variance 1/3), v ~ U[−0.1, 0.1], x_0 ~ U[−1, 1]²
    system, _, xs, ys = _linear()
    return run(system, ys, np.zeros(2), np.eye(2) / 3, 1 / 3, 0.01 / 3), xs


CASES = {
    "classical_filter": lambda: _on_linear(ss.classical_filter),
    "classical_filter reduced": lambda: _on_linear(
        lambda s, X0, ys: ss.classical_filter(s, X0, ys, reduce=ss.CORA_GIRARD)),
    "optimal_smoother": lambda: _on_linear(ss.optimal_smoother),
    "optimal_smoother recursion": lambda: _on_linear(
        lambda s, X0, ys: ss.optimal_smoother(s, X0, ys, method="recursion")),
    "oit_inspired_filter": lambda: _on_linear(ss.oit_inspired_filter),
    "oit_cz_filter": lambda: _on_linear(ss.oit_cz_filter),
    "oit_cz_filter hulls": lambda: _on_linear(lambda s, X0, ys: ss.oit_cz_filter(s, X0, ys, hulls=True)),
    "optimal_filter": lambda: _joint(False),
    "optimal_joint_smoother": lambda: _joint(True),
    "lsu_cz_filter": lambda: _lsu(ss.lsu_cz_filter),
    "lsuo_filter": lambda: _lsu(ss.lsuo_filter),
    "lsup_filter": lambda: _lsu(ss.lsup_filter),
    "interval_filter": lambda: _intervals(False),
    "interval_smoother": lambda: _intervals(True),
    "classical_interval_filter": lambda: _rethinking(False),
    "sampled_optimal_filter": lambda: _rethinking(True),
    "kalman_filter": lambda: _kalman(ss.kalman_filter),
    "rts_smoother": lambda: _kalman(ss.rts_smoother),
}


@pytest.mark.parametrize("name", CASES)
def test_every_estimator_returns_the_one_protocol(name):
    result, xs = CASES[name]()
    for member in ("lo", "hi", "centers", "diameters", "first_empty", "contains_trajectory", "plot_tubes",
                   "__len__"):
        assert member in dir(ss.Estimates)
        inspect.getattr_static(result, member)  # present, without computing it
    batch = name == "sampled_optimal_filter"  # runs first, then k
    scalar = name in ("interval_filter", "interval_smoother", "classical_interval_filter")
    steps = result.lo.shape[-1] if batch else len(result)
    assert steps == T + 1
    shape = (1, T + 1) if batch else (T + 1,) if scalar else (T + 1, xs.shape[1])
    assert result.lo.shape == result.hi.shape == result.centers.shape == shape
    assert np.all(result.lo <= result.hi) and np.all(np.isfinite(result.lo))
    assert np.allclose(result.centers, (result.lo + result.hi) / 2)
    widths = result.diameters()
    assert widths.shape == ((1, T + 1) if batch else (T + 1,))
    assert np.allclose(widths, (result.hi - result.lo).reshape(widths.shape + (-1,)).max(axis=-1))
    assert result.first_empty == ([None] if batch else None)
    inside = result.contains_trajectory(xs)
    assert inside.dtype == bool and inside.all()
    if not (batch or scalar or name in ("kalman_filter", "rts_smoother")):   # results holding sets
        assert result[T].contains(xs[T]) and len(list(iter(result))) == T + 1
    fig, ax = plt.subplots()
    axes = result.plot_tubes(ax, [0])
    assert list(axes) == [ax] and len(ax.collections) >= 1
    plt.close(fig)


def test_slices_and_copies_keep_the_type_and_the_data():
    (filtered, xs) = _on_linear(ss.classical_filter)
    part, copy = filtered[2:5], filtered.copy()
    for result in (part, copy):
        assert isinstance(result, ss.SetEstimates)
        assert result.kind == "filtered" and result.system is filtered.system
        assert np.array_equal(result.ys, filtered.ys)
    assert np.array_equal(part.lo, filtered.lo[2:5]) and np.array_equal(copy.hi, filtered.hi)
    assert part.contains_trajectory(xs[2:5]).all()
    fig, ax = plt.subplots()
    part.plot_tubes(ax, [0])
    assert ax.collections[0].get_paths()[0].vertices[:, 0].min() == 2.0  # the slice keeps its own k
    plt.close(fig)
    assert type(filtered[3]) is type(list.__getitem__(filtered, 3))


def test_oit_hulls_are_the_protocols_tubes_with_or_without_hulls_true():
    system, X0, xs, ys = _linear()
    eager = ss.oit_cz_filter(system, X0, ys, hulls=True)
    lazy = ss.oit_cz_filter(system, X0, ys)
    assert lazy.hulls is None and eager.lo is eager.hulls[0] and eager.hi is eager.hulls[1]
    assert np.allclose(lazy.lo, eager.lo, atol=1e-7) and np.allclose(lazy.hi, eager.hi, atol=1e-7)
    assert lazy.estimates.outer and lazy.kind == "OIT-CZ"


def test_interval_estimates_live_with_the_other_results():
    from setsmooth.models.intervals import IntervalEstimates

    assert IntervalEstimates is ss.IntervalEstimates and IntervalEstimates.__module__ == "setsmooth.results"


def test_kalman_tubes_are_sigma_boxes_about_the_means():
    import dataclasses

    result, xs = _kalman(ss.rts_smoother)
    sigma = np.sqrt(np.diagonal(result.covariances, axis1=1, axis2=2))
    assert np.allclose(result.lo, result.means - 3 * sigma) and np.allclose(result.hi, result.means + 3 * sigma)
    assert result.centers is result.means and result.first_empty is None and result.kind == "RTS smoother"
    narrow = dataclasses.replace(result, sigmas=1e-6)   # a box that is almost the mean: the truth is out
    assert np.allclose(narrow.diameters(), 2e-6 * sigma.max(axis=1)) and not narrow.contains_trajectory(xs).any()
    with pytest.raises(ValueError, match="sigmas must be a positive finite"):
        dataclasses.replace(result, sigmas=0.0)
