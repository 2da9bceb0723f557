"""Fast-path solver instances: per thread, bounded, never stored on the set (threads, pickling)."""

from __future__ import annotations

import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import setsmooth as ss
from setsmooth.solvers import instances


def random_cz(seed: int = 3) -> ss.ConstrainedZonotope:
    rng = np.random.default_rng(seed)
    G, A = rng.standard_normal((3, 12)), rng.standard_normal((4, 12))
    return ss.ConstrainedZonotope(G, rng.standard_normal(3), A=A, b=A @ rng.uniform(-0.5, 0.5, 12))


def test_one_cz_queried_from_four_threads_gives_the_serial_values():
    D = np.random.default_rng(0).standard_normal((20, 3))
    serial = random_cz().support_many(D)
    Z = random_cz()
    Z.support_many(D[:1])  # an instance exists in the main thread before the others start

    def query(i):
        return [Z.support(d) for d in np.roll(D, 5 * i, axis=0)]

    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(query, range(4)))
    for i, values in enumerate(results):
        np.testing.assert_allclose(values, np.roll(serial, 5 * i), rtol=0, atol=1e-9)


def test_a_queried_cz_pickles_and_answers_the_same_after():
    Z = random_cz()
    d = np.array([1.0, -2.0, 0.5])
    value = Z.support(d)
    Z.is_empty()
    again = pickle.loads(pickle.dumps(Z))
    assert again.support(d) == value


def test_solver_instances_stay_bounded_over_a_400_step_filter():
    system = ss.LinearSystem([[0.9]], None, [[1.0]], W=ss.Box([-0.1], [0.1]), V=ss.Box([-0.5], [0.5]))
    rng = np.random.default_rng(1)
    x, ys = 0.0, []
    for _ in range(400):
        ys.append([x + rng.uniform(-0.5, 0.5)])
        x = 0.9 * x + rng.uniform(-0.1, 0.1)
    instances.clear()
    # Emptiness is not checked per step (closed-form steps); the queries below touch 20 posteriors
    # along the run, more than MAX_INSTANCES, each one building its own instance.
    posteriors = ss.classical_filter(system, ss.Box([-1.0], [1.0]), np.array(ys), detect_empty=False)
    sizes = []
    for P in posteriors[::20]:
        P.interval_hull()
        sizes.append(len(instances._cache()))
    assert max(sizes) <= instances.MAX_INSTANCES and sizes[-1] == instances.MAX_INSTANCES
    # No Clarabel instance is kept on the sets themselves.
    factors = posteriors[-1].to_constrained_zonotope().factors
    assert not any("clarabel" in str(type(v).__module__).lower() for v in vars(factors).values())
