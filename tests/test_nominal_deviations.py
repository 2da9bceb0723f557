"""The recursion about a nominal trajectory: the same sets as the original coordinates give."""

import pickle

import numpy as np

import setsmooth as ss
from setsmooth.trajectories.nominal import about_nominal
from setsmooth.sets.algebra import translate

from .estimation_helpers import time_varying_system

TRIANGLE_W = ss.ConstrainedZonotope(G=[[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], c=[0.05, -0.1],
                                    A=[[1.0, 1.0, 1.0]], b=[1.0])
OFFSET = np.array([3e5, -2e5])


def offset_system() -> ss.LinearSystem:
    """A constant system held at OFFSET by its input, CZ process noise with a nonzero centre."""
    A = np.array([[0.9, 0.4], [-0.3, 0.8]])
    return ss.LinearSystem(A, np.eye(2), [[1.0, 0.5]], W=TRIANGLE_W,
                           V=ss.Box([-0.2], [0.3]), u=np.tile((np.eye(2) - A) @ OFFSET, (12, 1)))


def data(system, X0, T, seed):
    """(states, measurements) of one seeded simulation, k = 0..T."""
    return ss.simulate(system, X0, T, np.random.default_rng(seed))


def test_deviation_form_is_the_model_about_its_nominal_trajectory():
    system = time_varying_system()
    X0 = ss.Box([-1.0, 0.5], [2.0, 1.5])
    _, ys = data(system, X0, 6, 1)
    form = about_nominal(system, X0, ys)
    c_W = system.W._flat_cz.c
    assert np.allclose(form.nominal[0], [0.5, 1.0])
    for k in range(6):
        step = system.A_at(k) @ form.nominal[k] + system.E_at(k) @ c_W + system.input_term(k)
        assert np.array_equal(form.nominal[k + 1], step)
        assert np.array_equal(form.system.A_at(k), system.A_at(k)) and np.array_equal(form.system.E_at(k), system.E_at(k))
    for k in range(7):
        assert np.allclose(form.ys[k], ys[k] - system.C_at(k) @ form.nominal[k], atol=1e-14)
    assert not form.system.has_input and system.has_input
    assert np.allclose(form.system.W._flat_cz.c, 0.0) and np.allclose(form.X0._flat_cz.c, 0.0)
    assert form.system.W is not system.W and system.W._flat_cz.c[0] == 0.05  # the original untouched


def test_recursion_posteriors_are_the_filtered_ranges_on_a_time_varying_system():
    system = time_varying_system()
    X0 = ss.Box([-1.0, 0.5], [2.0, 1.5])
    _, ys = data(system, X0, 8, 2)
    recursion = ss.classical_filter(system, X0, ys, form="recursion")
    views = ss.classical_filter(system, X0, ys, form="views")
    directions = np.random.default_rng(3).normal(size=(10, 2))
    for P, Q in zip(recursion, views):
        a, b = P.support_many(directions, certified=False), Q.support_many(directions, certified=False)
        assert np.allclose(a, b, rtol=0, atol=1e-7 * (1 + np.abs(b)))


def test_recursion_smoother_is_translation_equivariant_far_from_the_origin():
    """The same data shifted by OFFSET = (3e5, −2e5): the smoothed hulls shift by OFFSET to the
    rounding of the shift. (This small system is well conditioned; the thin set on which the
    recursion in absolute coordinates was 5e-6 off is reliability case 033,
    ``tests/reliability/test_reliability_regressions.py``.)"""
    system = offset_system()
    A = system.A_at(0)
    centred = ss.LinearSystem(A, None, [[1.0, 0.5]], W=TRIANGLE_W, V=system.V)
    X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])
    xs, ys = data(centred, X0, 12, 4)
    shifted_ys = ys + (system.C_at(0) @ OFFSET)
    near = ss.optimal_smoother(centred, X0, ys, method="recursion")
    far = ss.optimal_smoother(system, translate(X0, OFFSET), shifted_ys, method="recursion")
    for k, (P, Q) in enumerate(zip(near, far)):
        h, g = P.interval_hull(certified=False), Q.interval_hull(certified=False)
        width = float(np.max(h.hi - h.lo))
        assert np.allclose(g.lo - OFFSET, h.lo, rtol=0, atol=1e-9 * (1 + width) + 1e-15 * 3e5), k
        assert np.allclose(g.hi - OFFSET, h.hi, rtol=0, atol=1e-9 * (1 + width) + 1e-15 * 3e5), k
        assert np.all(g.lo <= xs[k] + OFFSET + 1e-9) and np.all(xs[k] + OFFSET <= g.hi + 1e-9)


def test_smoother_reads_the_deviations_of_unchanged_and_unpickled_posteriors_only():
    system = offset_system()
    X0 = translate(ss.Box([-1.0, -1.0], [1.0, 1.0]), OFFSET)
    _, ys = data(system, X0, 5, 5)
    posteriors = ss.classical_filter(system, X0, ys, form="recursion")
    kept = posteriors._recursion_deviations
    assert kept.matches(posteriors)
    restored = pickle.loads(pickle.dumps(posteriors))
    assert restored._recursion_deviations.matches(restored)
    edited = ss.classical_filter(system, X0, ys, form="recursion")
    edited[2] = posteriors[2]  # the same set, another object: the deviations are no longer its own
    assert not edited._recursion_deviations.matches(edited)
    by_deviations = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=posteriors)
    absolute = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=edited)
    for P, Q in zip(by_deviations, absolute):
        a, b = P.interval_hull(certified=True), Q.interval_hull(certified=True)
        assert np.allclose(a.lo, b.lo, rtol=0, atol=1e-6) and np.allclose(a.hi, b.hi, rtol=0, atol=1e-6)
