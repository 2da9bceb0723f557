import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.filters.steps import predict, update
from setsmooth.reliability.block_assembly import block_assembly


def _random_system(rng, n, time_varying=False, with_input=False, sparse_noise=False):
    m = int(rng.integers(1, n + 1))
    p = int(rng.integers(1, n + 1))

    def stable(shape):
        A = rng.normal(size=shape)
        return A * 0.95 / max(1e-9, np.abs(np.linalg.eigvals(A)).max())

    A = stable((n, n))
    if rng.uniform() < 0.3:  # singular Φ
        A[:, 0] = 0.0
    B = rng.normal(size=(n, p))
    C = rng.normal(size=(m, n))
    W = ss.Box(-rng.uniform(0.1, 1, p), rng.uniform(0.1, 1, p))
    if sparse_noise:  # a CZ noise with sparse G and A and a constraint
        G = sp.random(m, m + 2, density=0.6, random_state=int(rng.integers(1 << 30))) + sp.eye(m, m + 2)
        V = ss.ConstrainedZonotope(sp.csc_matrix(G), np.zeros(m), sp.csc_matrix(np.ones((1, m + 2))),
                                   [0.2])
    else:
        V = ss.Zonotope(rng.normal(size=(m, m + 1)) * 0.5, rng.normal(size=m) * 0.1)
    u = None
    if time_varying:
        As = [stable((n, n)) for _ in range(40)]
        Cs = [C + 0.3 * rng.normal(size=C.shape) for _ in range(40)]
        A, C = As, Cs
        B0 = B
        B = lambda k: B0 * (1.0 + 0.1 * np.sin(k))  # noqa: E731  (a callable of k)
    if with_input:
        u = rng.normal(size=(40, n))
    return ss.LinearSystem(A, None if u is None else np.eye(n), C, E=B, W=W, V=V, u=u)


@pytest.mark.parametrize("seed,time_varying,with_input,sparse_noise",
                         [(0, False, False, False), (1, True, False, False), (2, False, True, True),
                          (3, True, True, True), (4, False, False, True)])
def test_one_step_assembly_is_the_block_assembly_about_the_nominal_trajectory(seed, time_varying,
                                                                            with_input, sparse_noise):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5))
    sys = _random_system(rng, n, time_varying, with_input, sparse_noise)
    X0 = ss.ConstrainedZonotope(rng.normal(size=(n, n + 1)), rng.normal(size=n), np.ones((1, n + 1)), [0.1])
    _, ys = ss.simulate(sys, X0, 12, rng)
    old_A, old_b = block_assembly(sys, X0, ys)
    old_A.eliminate_zeros()
    old_A.sort_indices()
    new = ss.trajectory_set(sys, X0, ys)
    assert new.A.shape == old_A.shape
    assert np.array_equal(new.A.indptr, old_A.indptr)
    assert np.array_equal(new.A.indices, old_A.indices)
    assert np.array_equal(new.A.data, old_A.data)  # exact: same floating-point products
    # The states are deviations from the nominal trajectory x̄ = c (noises at their centres):
    # x = x̄ + s, so the old rows read A(x̄ + s) = b_old, i.e. b_new = b_old − A_states x̄.
    shifted = np.zeros(new.ng)
    shifted[: new.dim] = new.c
    expected_b = old_b - old_A @ shifted
    scale = np.abs(old_b) + np.abs(old_A) @ np.abs(shifted) + 1.0
    assert np.all(np.abs(new.b - expected_b) <= 1e-13 * scale)


@pytest.mark.parametrize("seed", range(6))
def test_trajectory_form_equals_the_closed_form_recursion(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5))
    T = int(rng.integers(1, 16))
    sys = _random_system(rng, n)
    X0 = ss.Box(-np.ones(n) * 2, np.ones(n) * 2)
    xs, ys = ss.simulate(sys, X0, T, rng)
    recursion = ss.optimal_smoother(sys, X0, ys, method="recursion")
    trajectory = ss.optimal_smoother(sys, X0, ys, method="trajectory")
    D = rng.normal(size=(6, n))
    D = np.vstack([np.eye(n), -np.eye(n), D])
    for k in range(T + 1):
        a = recursion[k].support_many(D)
        b = trajectory[k].support_many(D)
        assert np.allclose(a, b, rtol=1e-6, atol=1e-6 * (1 + np.abs(a).max())), k
        assert np.all(D @ xs[k] <= b + 1e-7 * (1 + np.abs(xs[k]).max()))


def _filter_from(system, Z, ys, i, k):
    """The classical filter's recursion started at time i from the prior Z (set algebra, stability (3)–(4))."""
    posterior = update(system, i, Z, ys[i])
    for step in range(i + 1, k + 1):
        posterior = update(system, step, predict(system, step - 1, posterior), ys[step])
    return posterior


@pytest.mark.parametrize("seed,time_varying,with_input", [(0, False, False), (1, True, False),
                                                          (2, True, True), (3, False, True)])
def test_filtering_map_equals_the_filter_recursion_started_at_i(seed, time_varying, with_input):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 4))
    sys = _random_system(rng, n, time_varying, with_input)
    X0 = ss.Box(-np.ones(n), np.ones(n))
    xs, ys = ss.simulate(sys, X0, 14, rng)
    D = np.vstack([np.eye(n), -np.eye(n), rng.normal(size=(6, n))])
    for i, k in [(0, 0), (3, 3), (4, 9), (6, 14)]:
        # A prior at time i that contains the true state but is not the exact prior.
        Z = ss.Zonotope(rng.normal(size=(n, n + 2)) * 0.3 + np.eye(n, n + 2), xs[i])
        F = ss.filtering_map(sys, Z, ys, i, k)
        assert F.dim == n
        expected = _filter_from(sys, Z, ys, i, k).support_many(D)
        got = F.support_many(D)
        assert np.allclose(got, expected, rtol=1e-6, atol=1e-6 * (1 + np.abs(expected).max())), (i, k)
        assert np.all(D @ xs[k] <= got + 1e-7 * (1 + np.abs(xs[k]).max()))


def test_filtering_map_from_zero_with_the_exact_prior_is_the_classical_posterior():
    rng = np.random.default_rng(8)
    sys = _random_system(rng, 3)
    X0 = ss.Box(-np.ones(3), np.ones(3))
    _, ys = ss.simulate(sys, X0, 8, rng)
    posteriors = ss.classical_filter(sys, X0, ys)
    D = np.vstack([np.eye(3), -np.eye(3)])
    for k in (0, 4, 8):
        assert np.allclose(ss.filtering_map(sys, X0, ys, 0, k).support_many(D),
                           posteriors[k].support_many(D), atol=1e-6)


def test_trajectory_window_projects_to_the_filtering_map_and_ends_where_asked():
    rng = np.random.default_rng(9)
    sys = _random_system(rng, 2, time_varying=True)
    X0 = ss.Box(-np.ones(2), np.ones(2))
    _, ys = ss.simulate(sys, X0, 10, rng)
    window = ss.trajectory_set(sys, X0, ys, start=3, stop=7)
    assert window.dim == 2 * 5
    D = np.vstack([np.eye(2), -np.eye(2)])
    assert np.allclose(window.project([8, 9]).support_many(D),
                       _filter_from(sys, X0, ys, 3, 7).support_many(D), atol=1e-6)


def test_last_projection_of_the_trajectory_set_is_the_last_posterior():
    rng = np.random.default_rng(11)
    sys = _random_system(rng, 3)
    X0 = ss.Box(-np.ones(3), np.ones(3))
    _, ys = ss.simulate(sys, X0, 8, rng)
    last = ss.classical_filter(sys, X0, ys)[-1]
    traj = ss.trajectory_set(sys, X0, ys)
    D = np.vstack([np.eye(3), -np.eye(3)])
    assert np.allclose(traj.project(range(24, 27)).support_many(D), last.support_many(D), atol=1e-6)


def test_trajectory_projections_share_one_factor_set():
    rng = np.random.default_rng(5)
    sys = _random_system(rng, 2)
    X0 = ss.Box(-np.ones(2), np.ones(2))
    _, ys = ss.simulate(sys, X0, 5, rng)
    smoothed = ss.optimal_smoother(sys, X0, ys, method="trajectory")
    assert len({id(S.factors) for S in smoothed}) == 1


@pytest.mark.parametrize("start,stop,match", [(-1, None, "start"), (2, 1, "start <= stop"),
                                              (0, 3, "T = 2"), (1.0, None, "integer")])
def test_trajectory_window_outside_the_measurements_is_refused(start, stop, match):
    sys = ss.LinearSystem(np.eye(1), None, np.eye(1), W=ss.Box([-1], [1]), V=ss.Box([-1], [1]))
    with pytest.raises((ValueError, TypeError), match=match):
        ss.trajectory_set(sys, ss.Box([-1], [1]), np.zeros((3, 1)), start, stop)


def test_filtering_map_refuses_a_prior_of_the_wrong_dimension():
    sys = ss.LinearSystem(np.eye(2), None, np.eye(2), W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-1, -1], [1, 1]))
    with pytest.raises(ValueError, match="prior must be a ConvexSet of dimension n = 2"):
        ss.filtering_map(sys, ss.Box([-1], [1]), np.zeros((3, 2)), 0, 2)
