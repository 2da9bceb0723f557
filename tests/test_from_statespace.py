"""Plants from python-control: noise models of sampling, the input split (B, D known; E noise), sampling times, F."""

import control
import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

import setsmooth as ss
from setsmooth.models.discretization import bounded_noise_set, zoh_matrices

# A lightly damped mass-spring-damper (1 Hz): sampled at Δ = 0.5 s, half a period, the worst-case
# noise switches sign inside every sample interval.
A_MSD = np.array([[0.0, 1.0], [-4.0 * np.pi ** 2, -0.5]])
B_MSD = np.array([[0.0], [1.0]])
C_MSD = np.array([[1.0, 0.0]])
DT = 0.5


def fine_increment(A, B, w_on_grid, dt):
    """∫_0^Δ e^{A(Δ−s)} B w(s) ds for a switching w, exactly for w held on a fine grid (scipy expm).

    ``w_on_grid[i]`` is w at the midpoint of the i-th of len(w_on_grid) equal cells of [0, Δ].
    """
    h = dt / len(w_on_grid)
    Phi_h, Gamma_h = zoh_matrices(A, B, h)
    x = np.zeros(A.shape[0])
    for w in w_on_grid:
        x = Phi_h @ x + Gamma_h @ np.atleast_1d(w)
    return x


def worst_case_noise(A, B, dt, d, substeps=4000):
    """w(s) = sign(bᵀ e^{Aᵀ(Δ−s)} d) on the grid: the |w| ≤ 1 signal pushing furthest along d."""
    h = dt / substeps
    g = scipy.linalg.expm(A * (h / 2)) @ B[:, 0]  # e^{Aτ} b at τ = Δ − s for the last cell first
    step = scipy.linalg.expm(A * h)
    values = []
    for _ in range(substeps):
        values.append(np.sign(g @ d))
        g = step @ g
    return values[::-1]


def test_bounded_noise_set_encloses_the_exact_integral_and_is_tight():
    _, R = bounded_noise_set(A_MSD, B_MSD, ss.Box([-1.0], [1.0]), DT, partition=64)
    lam, vecs = np.linalg.eig(A_MSD)  # e^{Aτ} b = V e^{Λτ} V⁻¹ b, cheap inside the quadrature
    coef = np.linalg.solve(vecs, B_MSD[:, 0])
    for theta in np.linspace(0.0, np.pi, 7):
        d = np.array([np.cos(theta), np.sin(theta)])
        # h_R(d) = ∫_0^Δ |dᵀ e^{Aτ} b| dτ for W = [−1, 1], by adaptive quadrature
        exact = scipy.integrate.quad(lambda t: abs((d @ vecs @ (np.exp(lam * t) * coef)).real),
                                     0.0, DT, limit=200, epsabs=1e-13)[0]
        assert exact <= R.support(d) <= 1.05 * exact


def test_bounded_noise_remainder_shrinks_with_the_partition():
    widths = [bounded_noise_set(A_MSD, B_MSD, ss.Box([-1.0], [1.0]), DT, partition=N)[1]
              .interval_hull().hi[1] for N in (8, 16, 64)]
    assert widths[0] > widths[1] > widths[2]


def test_switching_noise_increment_lies_in_bounded_model_and_leaves_zoh_model():
    plant = control.ss(A_MSD, B_MSD, C_MSD, 0)
    W, V = ss.Box([-1.0], [1.0]), ss.Box([-0.01], [0.01])
    bounded = ss.LinearSystem.from_statespace(plant, W=W, V=V, noise_inputs=[0], dt=DT)
    held = ss.LinearSystem.from_statespace(plant, W=W, V=V, noise_inputs=[0], dt=DT, method="zoh")
    for d in ([0.0, 1.0], [1.0, 1.0], [1.0, -0.2]):
        d = np.asarray(d) / np.linalg.norm(d)
        increment = fine_increment(A_MSD, B_MSD, worst_case_noise(A_MSD, B_MSD, DT, d), DT)
        assert bounded.process_noise_image(0).contains(increment)
        assert not held.process_noise_image(0).contains(increment, tol=1e-6)


def test_filter_keeps_the_true_state_under_noise_switching_inside_intervals():
    rng = np.random.default_rng(3)
    plant = control.ss(A_MSD, B_MSD, C_MSD, 0)
    W, V, X0 = ss.Box([-1.0], [1.0]), ss.Box([-0.02], [0.02]), ss.Box([-1, -1], [1, 1])
    system = ss.LinearSystem.from_statespace(plant, W=W, V=V, noise_inputs=[0], dt=DT)
    T = 12
    Phi = scipy.linalg.expm(A_MSD * DT)
    xs, increments = [np.array([0.3, -0.5])], []
    for _ in range(T):
        flips = np.sort(rng.uniform(0.0, DT, 3))   # three sign changes inside the interval
        midpoints = (np.arange(1000) + 0.5) * DT / 1000
        w = rng.choice([-1.0, 1.0]) * (-1.0) ** np.searchsorted(flips, midpoints)
        increments.append(fine_increment(A_MSD, B_MSD, w, DT))
        xs.append(Phi @ xs[-1] + increments[-1])
    xs = np.array(xs)
    simulated, ys = ss.simulate(system, X0, T, rng, x0=xs[0], ws=np.array(increments))
    assert np.allclose(simulated, xs)  # the given noises drive the simulation exactly
    posteriors = ss.classical_filter(system, X0, ys)
    assert all(P.contains(x) for P, x in zip(posteriors, xs))
    # the same data leave the zero-order-hold model: its filter loses the true state
    held = ss.LinearSystem.from_statespace(plant, W=W, V=V, noise_inputs=[0], dt=DT, method="zoh")
    assert not all(P.contains(x) for P, x in zip(ss.classical_filter(held, X0, ys), xs))


def test_known_and_noise_inputs_are_split_by_index_and_match_python_control():
    # inputs [u, w]: u known (held), w noise held too, so 'zoh' is exact and must match c2d + lsim
    plant = control.ss(A_MSD, np.array([[0.0, 0.0], [1.0, 0.5]]), C_MSD, 0)
    T, dt = 8, 0.1
    rng = np.random.default_rng(0)
    u, w = rng.uniform(-1, 1, (T, 1)), rng.uniform(-1, 1, (T, 1))
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-0.1], [0.1]),
                                             noise_inputs=[1], u=u, dt=dt, method="zoh")
    xs, _ = ss.simulate(system, ss.Box([0, 0], [0, 0]), T, None, x0=[0.0, 0.0], ws=w,
                        vs=np.zeros((T + 1, 1)))
    sampled = control.c2d(plant, dt, method="zoh")
    ref = control.forced_response(sampled, T=np.arange(T + 1) * dt,
                                  U=np.vstack([np.hstack([u, w]), [[0.0, 0.0]]]).T,
                                  X0=[0.0, 0.0], return_x=True)
    assert np.allclose(xs, ref.states.T, atol=1e-12)
    assert np.allclose(system.E_at(0), sampled.B[:, [1]])


def test_bounded_mode_with_known_inputs_adds_their_held_response():
    plant = control.ss(A_MSD, np.array([[0.0, 0.0], [1.0, 1.0]]), C_MSD, 0)
    u = np.full((3, 1), 2.0)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-0.1], [0.1]),
                                             noise_inputs=[1], u=u, dt=0.1)
    assert np.allclose(system.input_term(1), zoh_matrices(A_MSD, B_MSD, 0.1)[1] @ [2.0])
    assert system.W.dim == 2 and np.array_equal(system.E_at(0), np.eye(2))


def test_callable_known_inputs_are_multiplied_out_per_step():
    plant = control.ss(A_MSD, np.array([[0.0, 0.0], [1.0, 1.0]]), C_MSD, 0, 0.1)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-0.1], [0.1]),
                                             noise_inputs=[1], u=lambda k: [float(k)])
    assert np.allclose(system.input_term(3), [0.0, 3.0])


def test_sampling_time_of_a_discrete_statespace_is_respected():
    plant = control.ss([[0.9]], [[1.0]], [[1.0]], 0, 0.2)
    box = ss.Box([-1.0], [1.0])
    assert ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0]).dt == 0.2
    assert ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0], dt=0.2).dt == 0.2
    with pytest.raises(ValueError, match=r"dt = 0.1 disagrees .* \(0.2\)"):
        ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0], dt=0.1)
    unspecified = control.ss([[0.9]], [[1.0]], [[1.0]], 0, True)
    assert ss.LinearSystem.from_statespace(unspecified, W=box, V=box, noise_inputs=[0], dt=0.3).dt == 0.3
    assert ss.LinearSystem.from_statespace(unspecified, W=box, V=box, noise_inputs=[0]).dt is None
    with pytest.raises(ValueError, match="applies to continuous models"):
        ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0], method="zoh")


@pytest.mark.parametrize("method", ["foh", "tustin", "impulse"])
def test_unsound_or_unknown_discretizations_are_not_offered(method):
    plant = control.ss(A_MSD, B_MSD, C_MSD, 0)
    with pytest.raises(ValueError, match="'tustin' is not offered"):
        ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]), dt=0.1,
                                        noise_inputs=[0], method=method)


def test_f_is_the_noise_matrix_and_statespace_d_the_feedthrough():
    box = ss.Box([-1.0], [1.0])
    plant = control.ss([[0.5]], [[1.0]], [[1.0]], 0, 1)
    system = ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0], F=[[0.25]])
    assert np.array_equal(system.F, [[0.25]])
    with pytest.raises(TypeError, match="'Psi'"):
        ss.LinearSystem.from_statespace(plant, W=box, V=box, noise_inputs=[0], Psi=[[0.25]])
    with pytest.raises(ValueError, match="feedthrough D from the noise inputs"):
        ss.LinearSystem.from_statespace(control.ss([[0.5]], [[1.0]], [[1.0]], [[0.3]], 1), W=box, V=box,
                                        noise_inputs=[0])
    with_feedthrough = control.ss([[0.5]], [[1.0, 1.0]], [[1.0]], [[0.3, 0.0]], 1)
    system = ss.LinearSystem.from_statespace(with_feedthrough, W=box, V=box, noise_inputs=[1],
                                             u=np.ones((2, 1)))
    assert np.array_equal(system.B, [[1.0]]) and np.array_equal(system.D, [[0.3]])
    assert np.array_equal(system.E, [[1.0]]) and system.has_feedthrough


@pytest.mark.parametrize("kwargs, match", [
    (dict(noise_inputs=[2]), r"noise_inputs must be .* in \[0, 2\)"),
    (dict(noise_inputs=[1, 1]), "must not repeat"),
    (dict(noise_inputs=[1]), r"inputs \[0\] are known inputs .* pass their samples as u="),
    (dict(), r"inputs \[0, 1\] are known inputs .* or select the noise inputs with noise_inputs="),
    (dict(noise_inputs=[0, 1]), "W must have one coordinate per noise input"),
    (dict(noise_inputs=[0, 1], u=np.zeros((3, 1))), "every statespace input is a noise input"),
    (dict(noise_inputs=[1], u=np.zeros((3, 2))), r"u must have shape \(T\+1, n_u=1\)"),
    (dict(noise_inputs=[1], u=np.zeros((1, 3))), r"u has shape \(1, 3\), python-control's orientation"),
    (dict(noise_inputs=[1], u=[[0.0], [np.nan]]), r"u\[1\]"),
    (dict(noise_inputs=[1], E=[[1.0]], u=np.zeros((3, 1))), "E= and noise_inputs= both"),
])
def test_input_split_errors_name_the_argument(kwargs, match):
    plant = control.ss([[0.5]], [[1.0, 1.0]], [[1.0]], 0, 1)
    with pytest.raises(ValueError, match=match):
        ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]), **kwargs)


def test_bounded_mode_refuses_an_unbounded_noise_range():
    plant = control.ss(A_MSD, B_MSD, C_MSD, 0)
    with pytest.raises(ValueError, match="W must be bounded"):
        ss.LinearSystem.from_statespace(plant, W=ss.Reals(1), V=ss.Box([-1.0], [1.0]), noise_inputs=[0], dt=0.1)


def test_simulate_uses_given_noise_sequences_and_checks_their_shape():
    system = ss.LinearSystem([[0.5]], None, [[2.0]], W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    xs, ys = ss.simulate(system, ss.Box([-1.0], [1.0]), 2, None, x0=[1.0], ws=[[3.0], [0.0]],
                         vs=[0.1, 0.2, 0.3])
    assert np.allclose(xs[:, 0], [1.0, 3.5, 1.75]) and np.allclose(ys[:, 0], [2.1, 7.2, 3.8])
    with pytest.raises(ValueError, match=r"ws must have shape \(2, 1\)"):
        ss.simulate(system, ss.Box([-1.0], [1.0]), 2, None, x0=[1.0], ws=[[0.0]], vs=[0, 0, 0])
    with pytest.raises(ValueError, match=r"vs\[1\]"):
        ss.simulate(system, ss.Box([-1.0], [1.0]), 2, None, x0=[1.0], ws=[0, 0], vs=[0, np.inf, 0])
    xs, ys = ss.simulate(system, ss.Box([-1.0], [1.0]), 2, None, x0=[1.0], ws=[0, 0])  # vs: fresh entropy
    assert np.allclose(xs[:, 0], [1.0, 0.5, 0.25]) and np.all(np.abs(ys[:, 0] - 2 * xs[:, 0]) <= 1.0)
    with pytest.raises(TypeError, match="rng"):
        ss.simulate(system, ss.Box([-1.0], [1.0]), 2, "0", x0=[1.0], ws=[0, 0])


def test_sampling_time_is_validated_and_sets_the_tube_plot_time_axis():
    box = ss.Box([-1.0], [1.0])
    with pytest.raises(ValueError, match="dt must be a positive finite sampling time or None"):
        ss.LinearSystem([[0.5]], None, [[1.0]], W=box, V=box, dt=-0.1)
    system = ss.LinearSystem.from_statespace(control.ss([[0.5]], [[1.0]], [[1.0]], 0, 0.25), W=box, V=box,
                                             noise_inputs=[0])
    filtered = ss.classical_filter(system, ss.Box([-2.0], [2.0]), [[0.0], [0.5], [1.0]])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    (ax,) = filtered.plot_tubes()
    tube = ax.collections[-1]
    assert np.allclose(np.unique(tube.get_paths()[0].vertices[:, 0]), [0.0, 0.25, 0.5])
    assert tube.axes.get_xlabel() == "t"
    plt.close("all")


@pytest.mark.parametrize("partition", [3, 32])
def test_remainder_keeps_even_a_coarse_partition_sound(partition):
    # with three pieces the zonotope part alone misses the switching increments: only the
    # certified remainder box can hold them
    _, R = bounded_noise_set(A_MSD, B_MSD, ss.Box([-1.0], [1.0]), DT, partition=partition)
    without_remainder = ss.Zonotope(R.G[:, :-2], R.c)   # the last n generators are the box
    missed = 0
    for theta in np.linspace(0.0, np.pi, 6, endpoint=False):
        d = np.array([np.cos(theta), np.sin(theta)])
        increment = fine_increment(A_MSD, B_MSD, worst_case_noise(A_MSD, B_MSD, DT, d, 2000), DT)
        assert R.contains(increment, tol=0.0)
        missed += not without_remainder.contains(increment)
    assert missed > 0 or partition > 3


def test_noise_range_away_from_zero_is_enclosed_without_its_mirror_image():
    A, B = np.array([[0.0, 1.0], [-4.0, -0.4]]), np.array([[0.0], [1.0]])
    _, R = bounded_noise_set(A, B, ss.Box([0.5], [1.0]), 0.5, partition=8)
    midpoints = (np.arange(400) + 0.5) / 400 * 0.5
    switching = np.where(np.sin(40.0 * midpoints) > 0, 1.0, 0.5)   # w(t) ∈ [0.5, 1], switching
    assert R.contains(fine_increment(A, B, switching, 0.5), tol=0.0)
    Gamma = zoh_matrices(A, B, 0.5)[1]
    assert R.contains(Gamma @ [0.5], tol=0.0) and R.contains(Gamma @ [1.0], tol=0.0)
    assert not R.contains(Gamma @ [0.0]) and not R.contains(Gamma @ [-0.5])
