import functools
import pickle

import control
import numpy as np
import pytest

import setsmooth as ss
from tests.estimation_helpers import example_31, time_varying_system


def test_simulated_noises_lie_in_their_sets():
    sys = example_31()
    xs, ys = ss.simulate(sys, ss.Box([-5, -5], [5, 5]), 30, np.random.default_rng(1))
    assert xs.shape == (31, 2) and ys.shape == (31, 2)
    for k in range(30):
        w = np.linalg.lstsq(sys.E_at(k), xs[k + 1] - sys.A_at(k) @ xs[k], rcond=None)[0]
        assert np.allclose(sys.E_at(k) @ w, xs[k + 1] - sys.A_at(k) @ xs[k])
        assert -1 - 1e-12 <= w[0] <= 1 + 1e-12
    v = ys - xs @ sys.C_at(0).T
    assert np.all(np.abs(v) <= 1 + 1e-12)


def test_simulation_is_reproducible_from_the_seed():
    sys = example_31()
    a = ss.simulate(sys, ss.Box([-5, -5], [5, 5]), 10, np.random.default_rng(7))
    b = ss.simulate(sys, ss.Box([-5, -5], [5, 5]), 10, np.random.default_rng(7))
    c = ss.simulate(sys, ss.Box([-5, -5], [5, 5]), 10, np.random.default_rng(8))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert not np.array_equal(a[0], c[0])


def test_time_varying_matrices_and_known_input_drive_the_simulation():
    sys = time_varying_system()
    xs, _ = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 5, np.random.default_rng(0))
    for k in range(5):
        w = np.linalg.solve(sys.E_at(k), xs[k + 1] - sys.A_at(k) @ xs[k] - sys.input_term(k))
        assert sys.W.contains(w)


def test_sequence_of_matrices_is_indexed_by_k():
    A = [np.eye(2) * (k + 1) for k in range(3)]
    sys = ss.LinearSystem(A, None, np.eye(2), W=ss.Box([0, 0], [0, 0]), V=ss.Box([0, 0], [0, 0]))
    assert np.array_equal(sys.A_at(2), 3 * np.eye(2))
    with pytest.raises(IndexError, match="A is given for k in"):
        sys.A_at(3)


def test_from_statespace_keeps_a_discrete_model():
    ssd = control.StateSpace([[0.9, 0.1], [0.0, 0.8]], [[1.0], [0.5]], [[1.0, 0.0]], [[0.0]], 1)
    sys = ss.LinearSystem.from_statespace(ssd, W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0])
    assert np.allclose(sys.A, [[0.9, 0.1], [0.0, 0.8]]) and np.allclose(sys.E, [[1.0], [0.5]])
    assert np.allclose(sys.F, [[1.0]]) and sys.n_u == 0


def test_from_statespace_zoh_mode_matches_c2d():
    ssc = control.StateSpace([[0.0, 1.0], [-1.0, -0.5]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]])
    sys = ss.LinearSystem.from_statespace(ssc, W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), dt=0.1,
                                          method="zoh", noise_inputs=[0])
    expected = control.c2d(ssc, 0.1, method="zoh")
    assert np.allclose(sys.A, expected.A) and np.allclose(sys.E, expected.B)
    with pytest.raises(ValueError, match="dt"):
        ss.LinearSystem.from_statespace(ssc, W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0])


def test_from_statespace_rejects_feedthrough_from_a_noise_input():
    ssd = control.StateSpace([[0.5]], [[1.0]], [[1.0]], [[0.3]], 1)
    with pytest.raises(ValueError, match="feedthrough D from the noise inputs"):
        ss.LinearSystem.from_statespace(ssd, W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0])


@pytest.mark.parametrize("kwargs, match", [
    (dict(A=np.ones((2, 3))), "A must be square"),
    (dict(B=np.ones((3, 1))), r"B must have shape \(2, any\)"),
    (dict(D=np.ones((1, 2))), r"D must have shape \(1, 1\)"),
    (dict(W=ss.Box([-1, -1], [1, 1])), r"E must have W.dim = 2 columns .* check E and W"),
    (dict(E=None), r"E=None means E = I, which needs W.dim = n = 2, got W.dim = 1"),
    (dict(C=np.ones((1, 3))), r"C must have shape \(any, 2\)"),
    (dict(F=np.ones((1, 2))), r"F must have V.dim = 1 columns .* check F and V"),
    (dict(V=ss.Box([-1, -1], [1, 1]), F=None), r"F=None means F = I, which needs V.dim = m = 1"),
    (dict(A=[np.eye(2), np.eye(3)]), r"A\[1\] has shape \(3, 3\) but A\[0\] has shape \(2, 2\)"),
    (dict(W="box"), "W must be a ConvexSet"),
    (dict(u=np.ones((5, 3))), r"u must have shape \(T\+1, n_u=1\)"),
])
def test_linear_system_rejects_inconsistent_dimensions(kwargs, match):
    args = dict(A=np.eye(2), B=np.ones((2, 1)), C=np.ones((1, 2)), D=np.ones((1, 1)), E=np.ones((2, 1)),
                F=[[1.0]], W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), u=np.ones((5, 1)))
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=match):
        ss.LinearSystem(**args)


def test_simulate_validates_its_arguments():
    sys = example_31()
    with pytest.raises(TypeError, match="rng"):
        ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 3, "42")
    with pytest.raises(ValueError, match="T must be"):
        ss.simulate(sys, ss.Box([-1, -1], [1, 1]), -1, np.random.default_rng())
    with pytest.raises(ValueError, match="x0_set"):
        ss.simulate(sys, ss.Box([-1], [1]), 3, np.random.default_rng())


def test_nonlinear_system_simulates_the_cube_root_example():
    sys = ss.NonlinearSystem(lambda k, x, w: np.cbrt(x) + x + w, lambda k, x, v: 2 * x + v,
                             ss.Box([-1], [1]), ss.Box([1], [3]), n=1)
    xs, ys = ss.simulate(sys, ss.Box([-5], [5]), 20, np.random.default_rng(3))
    v = ys[:, 0] - 2 * xs[:, 0]
    assert np.all((v >= 1) & (v <= 3))


# -- pickling (a system goes to a process pool with its inputs) -------------------------------------
def rotation(k):
    a = 0.1 * k
    return 0.95 * np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])


def drift(k, scale=0.1):
    return np.array([scale * k, -scale])


def _systems_to_pickle():
    W, V = ss.Box([-1.0], [1.0]), ss.Box([-1.0, -1.0], [1.0, 1.0])
    B, C, D = [[0.5], [1.0]], [[0.5, 0.5], [1.0, 0.3]], np.eye(2)
    A = rotation(0)
    return {
        "u sequence": ss.LinearSystem(A, np.eye(2), C, E=B, F=D, W=W, V=V, u=np.arange(12.0).reshape(6, 2) / 10),
        "u callable": ss.LinearSystem(A, np.eye(2), C, E=B, F=D, W=W, V=V, u=drift),
        "u partial": ss.LinearSystem(A, np.eye(2), C, [[0.1, 0.0], [0.0, 0.2]], E=B, F=D, W=W, V=V,
                                     u=functools.partial(drift, scale=0.3)),
        "A callable": ss.LinearSystem(rotation, None, C, E=B, F=D, W=W, V=V),
        "A sequence": ss.LinearSystem([rotation(k) for k in range(6)], None, C, E=B, F=D, W=W, V=V),
        "B sequence": ss.LinearSystem(A, None, C, E=np.array([B] * 6) * 0.5, F=D, W=W, V=V),
    }


@pytest.mark.parametrize("name", list(_systems_to_pickle()))
def test_linear_system_pickles_with_its_inputs_and_time_varying_matrices(name):
    sys = _systems_to_pickle()[name]
    sys.process_noise_image(0)  # a cached image must not stop (or bloat) the pickle
    copy = pickle.loads(pickle.dumps(sys))
    for k in range(5):
        for M in ("A_at", "B_at", "C_at", "D_at", "E_at", "F_at"):
            assert np.array_equal(getattr(copy, M)(k), getattr(sys, M)(k))
        assert np.array_equal(copy.feedthrough_term(k), sys.feedthrough_term(k))
        assert np.array_equal(copy.input_term(k), sys.input_term(k))
    X0 = ss.Box([-5, -5], [5, 5])
    _, ys = ss.simulate(sys, X0, 5, np.random.default_rng(0))
    d = np.eye(2)
    ours, theirs = ss.classical_filter(copy, X0, ys)[-1], ss.classical_filter(sys, X0, ys)[-1]
    assert np.allclose(ours.support_many(d), theirs.support_many(d), rtol=0, atol=1e-9)


def test_a_callable_matrix_is_checked_at_every_call_and_never_reshaped():
    sys = ss.LinearSystem(lambda k: np.eye(2) if k < 3 else np.ones(4), None, np.eye(2),
                          W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-1, -1], [1, 1]))
    assert np.array_equal(sys.A_at(2), np.eye(2))
    with pytest.raises(ValueError, match=r"A\(3\) must have shape \(2, 2\), got \(1, 4\)"):
        sys.A_at(3)


def test_input_sequence_names_the_step_it_lacks():
    sys = ss.LinearSystem(np.eye(2), np.eye(2), np.eye(2), W=ss.Box([-1, -1], [1, 1]),
                          V=ss.Box([-1, -1], [1, 1]), u=np.zeros((3, 2)))
    with pytest.raises(IndexError, match=r"u is given for k in \[0, 3\), asked for k = 3"):
        sys.input_term(3)


def test_simulate_refuses_an_initial_state_outside_x0_set():
    with pytest.raises(ValueError, match=r"x0 = \[1.5, 0.0\] does not lie in x0_set"):
        ss.simulate(example_31(), ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(), x0=[1.5, 0.0])
    xs, _ = ss.simulate(example_31(), ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(), x0=[1.0, 0.0])
    assert np.array_equal(xs[0], [1.0, 0.0])


def test_the_system_keeps_private_copies_of_its_matrices_and_inputs():
    B, u = np.array([[0.5], [1.0]]), np.zeros((4, 2))
    sys = ss.LinearSystem(np.eye(2), np.eye(2), np.eye(2), E=B, W=ss.Box([-1], [1]), V=ss.Box([-1, -1], [1, 1]),
                          u=u)
    image = sys.process_noise_image(0).support([1.0, 0.0])
    B[0, 0], u[1, 0] = 7.0, 3.0
    assert sys.E_at(0)[0, 0] == 0.5 and sys.input_term(1)[0] == 0.0
    assert sys.process_noise_image(0).support([1.0, 0.0]) == image
