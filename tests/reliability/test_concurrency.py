"""Threads, pickling and process pools: same answers from four threads, picklable sets and systems,
and ``montecarlo.run`` raising (never hanging) on an unpicklable trial."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import setsmooth as ss

from setsmooth.reliability.concurrency import montecarlo_lambda_probe, set_factories, threaded_support

FACTORIES = set_factories()


@pytest.mark.parametrize("path", ["auto", "generic"])
@pytest.mark.parametrize("name", list(FACTORIES))
def test_one_set_queried_from_four_threads_gives_the_serial_answers(name, path):
    out = threaded_support(name, FACTORIES[name], path)
    assert out.hung == 0, f"{out.hung} threads still running after the timeout"
    assert not out.errors, f"{len(out.errors)} threads raised: {out.errors[:3]}"
    assert out.queries == 4 * 20
    assert out.wrong == 0, f"{out.wrong} of {out.queries} threaded answers differ (worst {out.worst:.2e})"


@pytest.mark.parametrize("name", list(FACTORIES))
def test_set_pickles_after_a_generic_and_a_fast_query(name):
    S = FACTORIES[name]()
    d = np.linspace(-1.0, 1.0, S.dim) + 0.3
    generic = S.support(d, path="generic")
    fast = S.support(d)
    T = pickle.loads(pickle.dumps(S))
    assert T.support(d) == pytest.approx(fast, rel=1e-9, abs=1e-9)
    assert T.support(d, path="generic") == pytest.approx(generic, rel=1e-7, abs=1e-7)


def test_linear_system_with_an_input_sequence_and_its_estimates_pickle():
    system = ss.LinearSystem([[0.9, 0.2], [0.0, 0.8]], np.eye(2), [[1.0, 0.0]], E=[[1.0], [0.5]],
                             W=ss.Box([-0.1], [0.1]), V=ss.Box([-0.2], [0.2]),
                             u=np.column_stack([np.linspace(0, 1, 6), np.zeros(6)]))
    X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])
    _, ys = ss.simulate(system, X0, 6, np.random.default_rng(0))
    copy = pickle.loads(pickle.dumps(system))
    for k in range(6):
        np.testing.assert_array_equal(copy.input_term(k), system.input_term(k))
    smoothed = ss.optimal_smoother(system, X0, ys)
    hulls = [S.interval_hull() for S in smoothed]  # queried, so solver caches exist
    back = pickle.loads(pickle.dumps(smoothed))
    for S, hull in zip(back, hulls):
        np.testing.assert_allclose(S.interval_hull().lo, hull.lo, atol=1e-9)


def test_montecarlo_run_with_a_lambda_trial_raises_rather_than_hangs():
    outcomes = montecarlo_lambda_probe(attempts=3, timeout=15.0)
    assert outcomes and all(o.startswith("raised") for o in outcomes), outcomes
