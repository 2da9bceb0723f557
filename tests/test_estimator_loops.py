"""The estimator loops trust what the LinearSystem validated (issue 6, "Nothing re-validated inside
estimator loops"): they call the set algebra directly, compute the constant noise images once, and
add no translation for a zero input — and produce exactly the sets the public operators give.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.filters.steps import predict
from setsmooth.trajectories.nominal import about_nominal
from setsmooth.sets.base import ConvexSet
from tests.estimation_helpers import example_31, time_varying_system


def _operator_filter(system, X0, ys):
    """The filter written with the public operators, which validate every operand (the reference)."""
    minus_V = -system.V
    posts = []
    for k, y in enumerate(ys):
        prior = X0 if k == 0 else (system.A_at(k - 1) @ posts[-1] + system.E_at(k - 1) @ system.W
                                   + system.input_term(k - 1))
        posts.append(prior.intersect_preimage(system.C_at(k), system.F_at(k) @ minus_V + y))
    return posts


def _operator_smoother(system, posteriors):
    minus_W = -system.W
    smoothed = [posteriors[-1]]
    for k in range(len(posteriors) - 2, -1, -1):
        reach = smoothed[-1] + system.E_at(k) @ minus_W - system.input_term(k)
        smoothed.append(posteriors[k].intersect_preimage(system.A_at(k), reach))
    return smoothed[::-1]


def _data(S: ss.ConstrainedZonotope):
    dense = [M.toarray() if sp.issparse(M) else np.asarray(M) for M in (S.G, S.A)]
    return dense + [S.c, S.b, S.h]


def _assert_same_cz(ours, reference):
    assert type(ours) is ss.ConstrainedZonotope and type(reference) is ss.ConstrainedZonotope
    for a, b in zip(_data(ours), _data(reference)):
        assert a.shape == b.shape and np.array_equal(a, b)


SYSTEMS = {"example_31": example_31, "time_varying_with_input": time_varying_system}


@pytest.mark.parametrize("name", SYSTEMS)
def test_filter_and_smoother_give_exactly_the_sets_of_the_public_operators(name):
    system = SYSTEMS[name]()
    X0 = ss.ConstrainedZonotope([[1.0, 0.5, 0.0], [0.0, 1.0, 0.3]], [0.2, -0.1], A=[[1.0, 1.0, 1.0]], b=[0.4])
    _, ys = ss.simulate(system, X0, 8, np.random.default_rng(3))
    posts = ss.classical_filter(system, X0, ys, detect_empty=False, form="recursion")
    # The recursion runs about the nominal trajectory (`setsmooth.trajectories.nominal`): the reference
    # is the operators' recursion on the same deviation form, translated back by the public `+`.
    form = about_nominal(system, X0, ys)
    deviations = _operator_filter(form.system, form.X0, form.ys)
    reference = [P + form.nominal[k] for k, P in enumerate(deviations)]
    for ours, theirs in zip(posts, reference, strict=True):
        _assert_same_cz(ours, theirs)
    smoothed = [S + form.nominal[k] for k, S in enumerate(_operator_smoother(form.system, deviations))]
    for ours, theirs in zip(ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=posts),
                            smoothed, strict=True):
        _assert_same_cz(ours, theirs)


def test_estimator_loops_do_not_go_through_the_validating_operators(monkeypatch):
    system = example_31()
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(system, X0, 6, np.random.default_rng(0))

    def refuse(*args, **kwargs):
        raise AssertionError("a public, validating operator was called inside the estimator loop")

    for op in ("__rmatmul__", "__add__", "__radd__", "__sub__", "__neg__", "intersect_preimage"):
        monkeypatch.setattr(ConvexSet, op, refuse)
    posts = ss.classical_filter(system, X0, ys)
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=posts)
    for k, S in enumerate(smoothed):
        assert S.is_empty() is False, k


def test_constant_noise_images_are_computed_once_per_system():
    system = example_31()
    assert system.process_noise_image(0) is system.process_noise_image(17)
    assert system.process_noise_image(0, negated=True) is system.process_noise_image(5, negated=True)
    assert system.measurement_noise_image(0) is system.measurement_noise_image(9)
    # ... and they are the sets B W, B(−W) and D(−V) of the operators.
    d = np.array([[0.3, -1.0], [1.0, 0.2]])
    for image, reference in [(system.process_noise_image(0), system.E_at(0) @ system.W),
                             (system.process_noise_image(0, negated=True), system.E_at(0) @ -system.W),
                             (system.measurement_noise_image(0), system.F_at(0) @ -system.V)]:
        assert np.array_equal(image.support_many(d), reference.support_many(d))


def test_noise_images_follow_time_varying_matrices():
    system = time_varying_system()  # E(k) alternates between I and 1.1 I
    d = np.eye(2)
    for k in range(4):
        expected = (system.E_at(k) @ system.W).support_many(d)
        assert np.array_equal(system.process_noise_image(k).support_many(d), expected)
    assert not np.array_equal(system.process_noise_image(0).support_many(d),
                              system.process_noise_image(1).support_many(d))


def test_a_zero_input_adds_no_translation():
    """A lazy prior stays a Minkowski sum: B u_k = 0 is not wrapped in a translation layer."""
    A, B, C, D = np.eye(2), np.eye(2), [[1.0, 0.0]], [[1.0]]
    W, V = ss.Box([-1, -1], [1, 1]), ss.Box([-1], [1])
    P = ss.HPolytope([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]], [1.0, 1.0, 1.0, 1.0])
    with_zero_input = ss.LinearSystem(A, np.eye(2), C, E=B, F=D, W=W, V=V, u=np.zeros((3, 2)))
    without_input = ss.LinearSystem(A, None, C, E=B, F=D, W=W, V=V)
    assert with_zero_input.nonzero_input(1) is None and without_input.nonzero_input(1) is None
    assert type(predict(with_zero_input, 1, P)) is type(predict(without_input, 1, P))
    moved = ss.LinearSystem(A, np.eye(2), C, E=B, F=D, W=W, V=V, u=[[0.0, 0.0], [2.0, 0.0]])
    d = np.array([[1.0, 0.0]])
    assert np.allclose(predict(moved, 1, P).support_many(d), predict(without_input, 1, P).support_many(d) + 2)
