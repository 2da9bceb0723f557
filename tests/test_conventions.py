"""python-control's A, B, C, D and CORA's E, F: x⁺ = A x + B u + E w, y = C x + D u + F v (issue 28)."""

import numpy as np
import pytest

import setsmooth as ss

A = np.array([[0.9, 0.3], [-0.2, 0.8]])
B = np.array([[0.0], [1.0]])          # the known input's matrix
C = np.array([[1.0, 0.0]])
D = np.array([[0.5]])                 # its feedthrough
E = np.array([[0.5], [1.0]])          # the process-noise matrix (the smoothing paper's Γ)
W, V = ss.Box([-0.2], [0.2]), ss.Box([-0.1], [0.1])
X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])
T = 12
U = np.sin(0.7 * np.arange(T + 1))[:, None] + 1.0


def _system(**over):
    args = dict(A=A, B=B, C=C, D=D, E=E, W=W, V=V, u=U) | over
    return ss.LinearSystem(**args)


def test_an_old_style_call_with_gamma_and_psi_is_refused_with_the_way_to_e_and_f():
    with pytest.raises(ValueError, match=r"B is python-control's known-input matrix .* u=.* "
                                         r"process-noise matrix .* goes in E=.* measurement-noise .* F="):
        ss.LinearSystem(A, E, C, [[1.0]], W=W, V=V)
    with pytest.raises(ValueError, match=r"D is python-control's feedthrough .* goes in F="):
        ss.LinearSystem(A, None, C, [[0.3]], E=E, W=W, V=V)
    with pytest.raises(TypeError):
        ss.LinearSystem(A, None, C, None, W, V)   # the noise sets are keyword-only


def test_the_python_control_habit_of_no_feedthrough_means_no_feedthrough():
    system = ss.LinearSystem(A, None, C, 0, E=E, W=W, V=V)
    assert system.n_u == 0 and system.D.shape == (1, 0) and np.array_equal(system.F, [[1.0]])
    assert not system.has_input and not system.has_feedthrough


def test_an_input_without_a_matrix_to_act_through_is_refused():
    with pytest.raises(ValueError, match="u= was given without B or D"):
        ss.LinearSystem(A, None, C, E=E, W=W, V=V, u=U)


def test_identity_noise_matrices_need_noises_of_the_state_and_output_dimensions():
    with pytest.raises(ValueError, match=r"E=None means E = I, which needs W.dim = n = 2.* give the "
                                         r"process-noise matrix E="):
        ss.LinearSystem(A, None, C, W=W, V=V)
    system = ss.LinearSystem(A, None, C, W=ss.Box([-1, -1], [1, 1]), V=V)
    assert np.array_equal(system.E, np.eye(2)) and np.array_equal(system.F, np.eye(1))


def test_matrices_read_as_arrays_when_constant_and_point_to_the_accessor_when_not():
    system = _system()
    for name, value in dict(A=A, B=B, C=C, D=D, E=E, F=np.eye(1)).items():
        M = getattr(system, name)
        assert isinstance(M, np.ndarray) and np.array_equal(M, value) and not M.flags.writeable
        assert np.array_equal(getattr(system, f"{name}_at")(3), value)
    varying = _system(A=lambda k: A * (1.0 + 0.01 * k))
    assert np.allclose(varying.A_at(2), 1.02 * A) and varying.time_varying == ("A",)
    with pytest.raises(ValueError, match=r"A is time-varying \(a callable of k\).*system\.A_at\(k\)"):
        varying.A
    text = repr(varying)
    assert "n_u=1" in text and "time-varying A: callable of k" in text and "input u: 13 steps" in text


def test_simulate_adds_the_known_input_to_the_state_and_its_feedthrough_to_the_measurement():
    system = _system()
    xs, ys = ss.simulate(system, X0, T, 4)
    for k in range(T):
        w = xs[k + 1] - A @ xs[k] - B @ U[k]
        assert np.allclose(w, E[:, 0] * w[1]) and W.contains(w[1:])   # w = E w_k, E = [0.5, 1]ᵀ
    v = ys - xs @ C.T - U @ D.T
    assert np.all(np.abs(v) <= 0.1 + 1e-12)


def test_a_feedthrough_needs_the_input_at_every_measurement_and_a_short_u_is_named_at_the_door():
    # y_T = C x_T + D u_T: with D the input has T+1 rows; without, u_T is not used and T rows suffice
    short = _system(u=U[:T])
    expected = (rf"^u must have shape \(T\+1, n_u\) = \({T + 1}, 1\) for the measurements y_0..y_{T} "
                rf"\(the feedthrough .*\), got \({T}, 1\)$")
    ys = np.zeros((T + 1, 1))
    for call in (lambda: ss.simulate(short, X0, T, 0), lambda: ss.classical_filter(short, X0, ys),
                 lambda: ss.optimal_smoother(short, X0, ys), lambda: ss.oit_cz_filter(short, X0, ys),
                 lambda: ss.kalman_filter(short, ys, np.zeros(2), np.eye(2), 0.01, 0.01)):
        with pytest.raises(ValueError, match=expected):
            call()
    no_feedthrough = _system(D=None, u=U[:T])
    xs, ys = ss.simulate(no_feedthrough, X0, T, 3)
    assert ss.classical_filter(no_feedthrough, X0, ys).contains_trajectory(xs).all()
    with pytest.raises(ValueError, match=rf"^u must have shape .*\({T + 1}, 1\).* {T} rows suffice\), "
                                         rf"got \({T - 1}, 1\)$"):
        ss.classical_filter(_system(D=None, u=U[:T - 1]), X0, ys)


def _hulls(estimates):
    return np.array([S.interval_hull().lo for S in estimates]), np.array([S.interval_hull().hi for S in estimates])


def test_the_estimators_subtract_the_feedthrough_once_at_their_door():
    system = _system()
    xs, ys = ss.simulate(system, X0, T, 7)
    # the same model by hand: B u_k as a state offset (B = I), D u_k taken off the measurements
    offset = ss.LinearSystem(A, np.eye(2), C, E=E, W=W, V=V, u=U[:T] @ B.T)
    moved = ys - U @ D.T
    filtered, by_hand = ss.classical_filter(system, X0, ys), ss.classical_filter(offset, X0, moved)
    assert filtered.contains_trajectory(xs).all()
    for ours, theirs in zip(_hulls(filtered), _hulls(by_hand)):
        assert np.allclose(ours, theirs, rtol=0.0, atol=1e-9)
    smoothed = ss.optimal_smoother(system, X0, ys)
    assert smoothed.contains_trajectory(xs).all()
    for ours, theirs in zip(_hulls(smoothed), _hulls(ss.optimal_smoother(offset, X0, moved))):
        assert np.allclose(ours, theirs, rtol=0.0, atol=1e-9)
    # the filter's results feed the recursion smoother: the door gives the same system both times
    recursion = ss.classical_filter(system, X0, ys, form="recursion")
    again = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=recursion)
    for ours, theirs in zip(_hulls(again), _hulls(smoothed)):
        assert np.allclose(ours, theirs, rtol=0.0, atol=1e-7)
    window = ss.filtering_map(system, X0, ys, 0, 5)
    assert np.allclose(window.interval_hull().hi, filtered[5].interval_hull().hi, atol=1e-9)
    kalman = ss.kalman_filter(system, ys, np.zeros(2), np.eye(2), 0.01, 0.01)
    assert np.allclose(kalman.means, ss.kalman_filter(offset, moved, np.zeros(2), np.eye(2), 0.01, 0.01).means)


def test_an_inconsistency_names_the_measurement_as_given():
    system = _system()
    _, ys = ss.simulate(system, X0, T, 2)
    ys[6] += 3.0
    found = ss.first_inconsistency(system, X0, ys)
    assert found.step == 6 and np.array_equal(found.measurement, ys[6])
    quoted = np.array2string(ys[6], precision=4)
    for estimator in (ss.classical_filter, ss.optimal_smoother, ss.oit_cz_filter, ss.oit_inspired_filter,
                      lambda *args: ss.optimal_smoother(*args, method="recursion")):
        with pytest.warns(ss.ModelInvalidationWarning) as caught:
            estimator(system, X0, ys)
        found = [w.message for w in caught if isinstance(w.message, ss.ModelInvalidationWarning)]
        assert len(found) == 1 and found[0].inconsistency.step == 6
        # y_6 as given, not y_6 − D u_6 (0.5 u_6 apart here)
        assert np.array_equal(found[0].inconsistency.measurement, ys[6]) and f"y_6 = {quoted}" in str(found[0])


def test_python_control_orientation_is_refused_not_transposed():
    system = _system()
    _, ys = ss.simulate(system, X0, T, 1)
    two = ss.LinearSystem(A, None, np.eye(2), E=E, W=W, V=ss.Box([-1, -1], [1, 1]))
    with pytest.raises(ValueError, match=r"ys has shape \(2, 13\), python-control's orientation .* pass ys\.T"):
        ss.classical_filter(two, X0, np.zeros((2, T + 1)))
    with pytest.raises(ValueError, match=r"u has shape \(1, 13\), python-control's orientation .* pass u\.T"):
        _system(u=U.T)
    assert ss.classical_filter(system, X0, ys[:, 0]).contains_trajectory is not None   # m = 1: 1-D is time


def test_from_statespace_maps_b_and_d_to_the_known_input_and_matches_python_control():
    control = pytest.importorskip("control")
    # inputs [u, w] of a discrete plant with a feedthrough from u: python-control's own simulation
    plant = control.ss(A, np.hstack([B, E]), C, np.hstack([D, [[0.0]]]), 0.1)
    system = ss.LinearSystem.from_statespace(plant, W=W, V=V, noise_inputs=[1], u=U)
    assert np.array_equal(system.B, B) and np.array_equal(system.D, D) and np.array_equal(system.E, E)
    rng = np.random.default_rng(0)
    ws = rng.uniform(-0.2, 0.2, (T, 1))
    xs, ys = ss.simulate(system, X0, T, None, x0=[0.5, -0.5], ws=ws, vs=np.zeros((T + 1, 1)))
    ref = control.forced_response(plant, U=np.hstack([U, np.vstack([ws, [[0.0]]])]).T, X0=[0.5, -0.5],
                                  return_x=True)
    assert np.allclose(xs, ref.states.T, atol=1e-12) and np.allclose(ys[:, 0], np.ravel(ref.outputs), atol=1e-12)
    # a continuous plant: B sampled with a zero-order hold, D kept, E from the noise columns
    continuous = control.ss(A - np.eye(2), np.hstack([B, E]), C, np.hstack([D, [[0.0]]]))
    sampled = ss.LinearSystem.from_statespace(continuous, W=W, V=V, noise_inputs=[1], u=U, dt=0.1,
                                              method="zoh")
    c2d = control.c2d(continuous, 0.1, method="zoh")
    assert np.allclose(sampled.A, c2d.A) and np.allclose(sampled.B, c2d.B[:, :1])
    assert np.allclose(sampled.E, c2d.B[:, 1:]) and np.array_equal(sampled.D, D)
    with pytest.raises(ValueError, match=r"inputs \[0, 1\] are known inputs .* u=.*noise_inputs="):
        ss.LinearSystem.from_statespace(plant, W=W, V=V)


@pytest.mark.parametrize("call", [
    lambda P: ss.classical_filter(P, X0, np.zeros((3, 1))),
    lambda P: ss.simulate(P, X0, 3, 0),
])
def test_a_statespace_given_as_a_system_points_to_from_statespace(call):
    control = pytest.importorskip("control")
    with pytest.raises(TypeError, match=r"control\.StateSpace.*LinearSystem\.from_statespace\(plant, W=.*u="):
        call(control.ss(A, B, C, D, 0.1))
