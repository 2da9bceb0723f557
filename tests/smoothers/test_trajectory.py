import numpy as np
import pytest

import setsmooth as ss


def _random_system(rng, n):
    m = int(rng.integers(1, n + 1))
    p = int(rng.integers(1, n + 1))
    A = rng.normal(size=(n, n))
    A *= 0.95 / max(1e-9, np.abs(np.linalg.eigvals(A)).max())
    if rng.uniform() < 0.3:  # singular Φ
        A[:, 0] = 0.0
    B = rng.normal(size=(n, p))
    C = rng.normal(size=(m, n))
    W = ss.Box(-rng.uniform(0.1, 1, p), rng.uniform(0.1, 1, p))
    V = ss.Zonotope(rng.normal(size=(m, m + 1)) * 0.5, rng.normal(size=m) * 0.1)
    return ss.LinearSystem(A, B, C, np.eye(m), W, V)


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


def test_trajectory_form_needs_cz_convertible_sets():
    sys = ss.LinearSystem(np.eye(2), np.eye(2), np.eye(2), np.eye(2),
                          ss.Ellipsoid([0, 0], np.eye(2)), ss.Box([-1, -1], [1, 1]))
    with pytest.raises(TypeError, match="Ellipsoid has no exact constrained-zonotope form"):
        ss.trajectory_set(sys, ss.Box([-1, -1], [1, 1]), np.zeros((3, 2)))
