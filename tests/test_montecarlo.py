"""Seeded Monte Carlo runs: reproducible, independent, and identical in every executor."""

from __future__ import annotations

import functools
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from setsmooth.runs.montecarlo import run


def draw(rng):
    return rng.standard_normal(4)


def slow_draw(rng):
    # Random sleeps make later runs finish first in a thread pool.
    value = rng.standard_normal(2)
    time.sleep(rng.uniform(0.0, 0.01))
    return value


def smoothing_trial(rng, T):
    """A realistic picklable trial: mean filtered and smoothed diameters on smoothing paper (33)–(34)."""
    from setsmooth.filters.interval import interval_filter
    from setsmooth.smoothers.nonlinear import interval_smoother

    eta = lambda x: np.cbrt(x) + x  # noqa: E731  (built inside the worker: lambdas don't pickle)
    x = np.empty(T + 1)
    x[0] = rng.uniform(-1, 1)
    for k in range(T):
        x[k + 1] = eta(x[k]) + rng.uniform(-1, 1)
    y = 2 * x + rng.uniform(1, 3, T + 1)
    filt = interval_filter(eta, (-1, 1), (-1, 1), y, lambda k, yk: ((yk - 3) / 2, (yk - 1) / 2))
    smooth = interval_smoother(eta, (-1, 1), filt)
    return filt.diameters().mean(), smooth.diameters().mean()


def fail_on_negative(rng):
    if rng.standard_normal() < 0:
        raise RuntimeError("boom")
    return 1


def test_same_seed_reproduces_and_other_seed_differs():
    a = run(draw, 8, seed=5, executor="serial", progress=False)
    b = run(draw, 8, seed=5, executor="serial", progress=False)
    c = run(draw, 8, seed=6, executor="serial", progress=False)
    assert len(a) == 8
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    assert not any(np.array_equal(x, z) for x, z in zip(a, c))


def test_runs_use_spawned_children_and_are_independent():
    results = run(draw, 50, seed=123, executor="serial", progress=False)
    children = np.random.SeedSequence(123).spawn(50)
    for res, child in zip(results, children):
        np.testing.assert_array_equal(res, np.random.default_rng(child).standard_normal(4))
    first = np.array([r[0] for r in results])
    assert len(np.unique(first)) == 50
    # Fifty standard normals: their sample mean is far from any single shared value.
    assert abs(first.mean()) < 0.6 and first.std() > 0.5


def test_process_pool_is_bit_identical_to_serial():
    trial = functools.partial(smoothing_trial, T=20)
    serial = run(trial, 12, seed=2024, executor="serial", progress=False)
    pooled = run(trial, 12, seed=2024, executor=None, progress=False, workers=2)
    assert serial == pooled  # tuples of floats: exact equality, not closeness
    assert all(s <= f for f, s in serial)


def test_user_thread_pool_is_used_kept_open_and_ordered():
    serial = run(slow_draw, 16, seed=9, executor="serial", progress=False)
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = run(slow_draw, 16, seed=9, executor=pool, progress=False)
        # Not shut down by run(): still accepts work.
        assert pool.submit(lambda: 42).result() == 42
    for x, y in zip(serial, threaded):
        np.testing.assert_array_equal(x, y)


def test_single_run_and_progress_bar(capsys):
    out = run(draw, 1, seed=0, progress=True)
    np.testing.assert_array_equal(out[0], np.random.default_rng(np.random.SeedSequence(0).spawn(1)[0])
                                  .standard_normal(4))
    assert "Monte Carlo" in capsys.readouterr().err


def test_trial_errors_propagate():
    with pytest.raises(RuntimeError, match="boom"):
        run(fail_on_negative, 10, seed=1, executor="serial", progress=False)


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(n_runs=0), ValueError, "n_runs"),
    (dict(n_runs=-3), ValueError, "n_runs"),
    (dict(n_runs=2.5), TypeError, "n_runs"),
    (dict(n_runs=True), TypeError, "n_runs"),
    (dict(trial="draw"), TypeError, "trial"),
    (dict(seed=-1), ValueError, "seed"),
    (dict(seed="0"), TypeError, "seed"),
    (dict(executor="threads"), TypeError, "executor"),
    (dict(workers=0), ValueError, "workers"),
])
def test_validation(kwargs, exc, match):
    args = dict(trial=draw, n_runs=3, seed=0, executor="serial", progress=False) | kwargs
    with pytest.raises(exc, match=match):
        run(**args)


def _run_with_deadline(target, seconds):
    """Run ``target()`` in a daemon thread; a hang fails the test instead of blocking the suite."""
    import threading

    outcome = {}

    def body():
        try:
            outcome["value"] = target()
        except BaseException as exc:  # handed to the test thread
            outcome["error"] = exc

    worker = threading.Thread(target=body, daemon=True)
    worker.start()
    worker.join(seconds)
    assert not worker.is_alive(), f"montecarlo.run did not return within {seconds} s"
    return outcome


def test_an_unpicklable_trial_is_refused_before_a_process_pool_starts_never_a_hang():
    for attempt in range(10):  # the pool used to hang in shutdown in 2 runs of 10
        outcome = _run_with_deadline(
            lambda: run(lambda rng: rng.standard_normal(), 8, seed=attempt, progress=False,
                        workers=2), 30)
        error = outcome.get("error")
        assert isinstance(error, TypeError), outcome
        assert "trial" in str(error) and "module-level function" in str(error)


def test_an_unpicklable_partial_argument_is_named():
    trial = functools.partial(smoothing_trial, T=lambda: 20)
    with ProcessPoolExecutor(max_workers=1) as pool:
        with pytest.raises(TypeError, match="trial's keyword argument 'T'"):
            run(trial, 4, seed=0, executor=pool, progress=False)


def test_an_unpicklable_trial_still_runs_serially_and_in_threads():
    trial = lambda rng: rng.standard_normal()  # noqa: E731
    serial = run(trial, 4, seed=3, executor="serial", progress=False)
    with ThreadPoolExecutor(max_workers=2) as pool:
        assert run(trial, 4, seed=3, executor=pool, progress=False) == serial
