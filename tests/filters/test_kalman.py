"""Kalman filter / RTS smoother against Gaussian conditioning of the whole stacked trajectory."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from setsmooth.filters.kalman import KalmanResult, kalman_filter, rts_smoother, rts_smoothers


class _Stub:
    """A time-varying linear model exposing only the duck-typed interface the filter uses."""

    def __init__(self, rng: np.random.Generator, n: int, m: int, p: int, q: int, T: int):
        self.n = n
        self._A = [np.eye(n) + 0.4 * rng.standard_normal((n, n)) for _ in range(T)]
        self._B = [rng.standard_normal((n, p)) for _ in range(T)]
        self._C = [rng.standard_normal((m, n)) for _ in range(T + 1)]
        self._D = [rng.standard_normal((m, q)) for _ in range(T + 1)]
        self._u = [rng.standard_normal(n) for _ in range(T)]

    def A_at(self, k):
        return self._A[k]

    def E_at(self, k):
        return self._B[k]

    def C_at(self, k):
        return self._C[k]

    def F_at(self, k):
        return self._D[k]

    def input_term(self, k):
        return self._u[k]


def _problem(seed: int, n=3, m=2, p=2, q=3, T=6):
    rng = np.random.default_rng(seed)
    sys = _Stub(rng, n, m, p, q, T)
    x0_mean = rng.standard_normal(n)
    L = rng.standard_normal((n, n))
    P0 = L @ L.T + 0.1 * np.eye(n)
    Lq = rng.standard_normal((p, p))
    Q = Lq @ Lq.T + 0.05 * np.eye(p)
    Lr = rng.standard_normal((q, q))
    R = Lr @ Lr.T + 0.05 * np.eye(q)
    ys = rng.standard_normal((T + 1, m)) * 3.0
    return sys, ys, x0_mean, P0, Q, R


def _batch(sys, ys, x0_mean, P0, Q, R):
    """Joint Gaussian of (x_0..x_T, y_0..y_T) as affine maps of z = (x_0, w_{0:T-1}, v_{0:T})."""
    T = ys.shape[0] - 1
    n, m = sys.n, ys.shape[1]
    p, q = Q.shape[0], R.shape[0]
    nz = n + T * p + (T + 1) * q
    Fx = np.zeros((T + 1, n, nz))
    cx = np.zeros((T + 1, n))
    Fx[0][:, :n] = np.eye(n)
    for k in range(T):
        Fx[k + 1] = sys.A_at(k) @ Fx[k]
        Fx[k + 1][:, n + k * p:n + (k + 1) * p] += sys.E_at(k)
        cx[k + 1] = sys.A_at(k) @ cx[k] + sys.input_term(k)
    Fy = np.zeros((T + 1, m, nz))
    for k in range(T + 1):
        Fy[k] = sys.C_at(k) @ Fx[k]
        off = n + T * p + k * q
        Fy[k][:, off:off + q] += sys.F_at(k)
    mu_z = np.zeros(nz)
    mu_z[:n] = x0_mean
    Sz = sla.block_diag(P0, *([Q] * T), *([R] * (T + 1)))
    X = Fx.reshape(-1, nz)
    mu_x = X @ mu_z + cx.reshape(-1)
    Ys = Fy.reshape(-1, nz)
    mu_y = Ys @ mu_z + np.array([sys.C_at(k) @ cx[k] for k in range(T + 1)]).reshape(-1)
    return X, mu_x, Ys, mu_y, Sz


def _condition(batch, ys, upto: int):
    """Mean and covariance of the stacked states given y_0..y_upto."""
    X, mu_x, Ys, mu_y, Sz = batch
    m = ys.shape[1]
    rows = slice(0, (upto + 1) * m)
    Yk = Ys[rows]
    Sxy = X @ Sz @ Yk.T
    Syy = Yk @ Sz @ Yk.T
    gain = np.linalg.solve(Syy, Sxy.T).T
    mean = mu_x + gain @ (ys[:upto + 1].reshape(-1) - mu_y[rows])
    cov = X @ Sz @ X.T - gain @ Sxy.T
    return mean, cov


def _block(mean, cov, k, n):
    s = slice(k * n, (k + 1) * n)
    return mean[s], cov[s, s]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rts_matches_batch_conditioning(seed):
    sys, ys, x0_mean, P0, Q, R = _problem(seed)
    res = rts_smoother(sys, ys, x0_mean, P0, Q, R)
    mean, cov = _condition(_batch(sys, ys, x0_mean, P0, Q, R), ys, ys.shape[0] - 1)
    for k in range(ys.shape[0]):
        mk, Pk = _block(mean, cov, k, sys.n)
        np.testing.assert_allclose(res.means[k], mk, rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(res.covariances[k], Pk, rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("seed", [0, 3])
def test_filter_matches_batch_conditioning_on_past(seed):
    sys, ys, x0_mean, P0, Q, R = _problem(seed)
    res = kalman_filter(sys, ys, x0_mean, P0, Q, R)
    batch = _batch(sys, ys, x0_mean, P0, Q, R)
    for k in range(ys.shape[0]):
        mean, cov = _condition(batch, ys, k)
        mk, Pk = _block(mean, cov, k, sys.n)
        np.testing.assert_allclose(res.means[k], mk, rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(res.covariances[k], Pk, rtol=1e-8, atol=1e-8)
        if k > 0:
            # The one-step prediction is the same conditioning, one measurement earlier.
            mean, cov = _condition(batch, ys, k - 1)
            mk, Pk = _block(mean, cov, k, sys.n)
            np.testing.assert_allclose(res.predicted_means[k], mk, rtol=1e-8, atol=1e-8)
            np.testing.assert_allclose(res.predicted_covariances[k], Pk, rtol=1e-8, atol=1e-8)
    np.testing.assert_array_equal(res.predicted_means[0], x0_mean)
    np.testing.assert_allclose(res.predicted_covariances[0], P0)


def test_result_shapes_and_symmetry():
    sys, ys, x0_mean, P0, Q, R = _problem(4, T=5)
    res = rts_smoother(sys, ys, x0_mean, P0, Q, R)
    assert isinstance(res, KalmanResult)
    assert res.means.shape == (6, 3) and res.covariances.shape == (6, 3, 3)
    assert res.predicted_means is None and res.predicted_covariances is None
    for P in res.covariances:
        np.testing.assert_array_equal(P, P.T)
        assert np.linalg.eigvalsh(P).min() > 0
    filt = kalman_filter(sys, ys, x0_mean, P0, Q, R)
    # Smoothing uses more data, so it never increases the variance.
    for Ps, Pf in zip(res.covariances, filt.covariances):
        assert np.linalg.eigvalsh(Pf - Ps).min() > -1e-10
    np.testing.assert_allclose(res.means[-1], filt.means[-1])


def test_scalar_noise_covariances_mean_scaled_identity():
    sys, ys, x0_mean, P0, _, _ = _problem(5)
    a = rts_smoother(sys, ys, x0_mean, P0, 0.076, 0.036)
    b = rts_smoother(sys, ys, x0_mean, P0, 0.076 * np.eye(2), 0.036 * np.eye(3))
    np.testing.assert_allclose(a.means, b.means, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a.covariances, b.covariances, rtol=1e-12, atol=1e-12)


def test_paper_example_31_32_runs():
    # Smoothing paper (31)–(32): rotation-like Φ, Γ = [0.5, 1]ᵀ, Ψ = I, Q = q, R = r I.
    class Paper:
        n = 2

        def A_at(self, k):
            return np.array([[np.sin(1), np.cos(1)], [-np.cos(1), np.sin(1)]])

        def E_at(self, k):
            return np.array([[0.5], [1.0]])

        def C_at(self, k):
            return np.array([[0.5, 0.5], [1.0, 0.3]])

        def F_at(self, k):
            return np.eye(2)

        def input_term(self, k):
            return np.zeros(2)

    rng = np.random.default_rng(7)
    sysp = Paper()
    T = 50
    x = rng.uniform(-1, 1, 2)
    xs, ys = [], []
    for k in range(T + 1):
        xs.append(x)
        ys.append(sysp.C_at(k) @ x + rng.uniform(-1, 1, 2))
        x = sysp.A_at(k) @ x + sysp.E_at(k)[:, 0] * rng.uniform(-1, 1)
    xs, ys = np.array(xs), np.array(ys)
    filt = kalman_filter(sysp, ys, np.zeros(2), np.eye(2), 0.076, 0.036)
    smooth = rts_smoother(sysp, ys, np.zeros(2), np.eye(2), 0.076, 0.036)
    mse_f = np.mean((filt.means - xs) ** 2)
    mse_s = np.mean((smooth.means - xs) ** 2)
    assert mse_s < mse_f


def test_singular_predicted_covariance_uses_pseudo_inverse():
    # Q = 0 and a rank-one P0 make every P_{k+1|k} singular; the means must still be finite and
    # match the batch solution computed with a tiny regularization.
    sys, ys, x0_mean, _, _, R = _problem(6, T=3)
    v = np.array([1.0, 2.0, -1.0])
    P0 = np.outer(v, v)
    res = rts_smoother(sys, ys, x0_mean, P0, 0.0, R)
    assert np.isfinite(res.means).all()
    ref = rts_smoother(sys, ys, x0_mean, P0 + 1e-9 * np.eye(3), 1e-9, R)
    np.testing.assert_allclose(res.means, ref.means, atol=1e-5)


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(ys=np.zeros((4, 3))), ValueError, "ys must have shape"),
    (dict(ys=np.full((4, 2), np.nan)), ValueError, "ys contains"),
    (dict(x0_mean=np.zeros(2)), ValueError, "x0_mean"),
    (dict(P0=np.eye(2)), ValueError, "P0"),
    (dict(P0=np.diag([1.0, -1.0, 1.0])), ValueError, "positive semidefinite"),
    (dict(P0=np.triu(np.ones((3, 3)))), ValueError, "symmetric"),
    (dict(Q=np.eye(3)), ValueError, "Q"),
    (dict(Q=-1.0), ValueError, "Q"),
    (dict(R=np.eye(2)), ValueError, "R"),
])
def test_validation(kwargs, exc, match):
    sys, ys, x0_mean, P0, Q, R = _problem(8, T=3)
    args = dict(ys=ys, x0_mean=x0_mean, P0=P0, Q=Q, R=R) | kwargs
    with pytest.raises(exc, match=match):
        kalman_filter(sys, **args)


def test_singular_innovation_covariance_is_reported():
    sys, ys, x0_mean, _, Q, _ = _problem(8, T=3)
    # Exact prior and noise-free measurements: C P Cᵀ + D R Dᵀ = 0 cannot be inverted.
    with pytest.raises(ValueError, match="singular"):
        kalman_filter(sys, ys, x0_mean, np.zeros((3, 3)), Q, 0.0)


def test_system_without_interface_is_rejected():
    with pytest.raises(TypeError, match="system"):
        kalman_filter(object(), np.zeros((2, 1)), [0.0], [[1.0]], 1.0, 1.0)


def _rts_one_pair(sys, ys, x0_mean, P0, Q, R):
    """The per-pair recursion `rts_smoother` ran before its loops took stacks (matrix Q and R)."""
    sym = lambda M: 0.5 * (M + M.T)
    n, steps = sys.n, ys.shape[0]
    means, covs = np.empty((steps, n)), np.empty((steps, n, n))
    pred_means, pred_covs = np.empty((steps, n)), np.empty((steps, n, n))
    mean, P = x0_mean, sym(P0)
    for k in range(steps):
        if k > 0:
            A, E = sys.A_at(k - 1), sys.E_at(k - 1)
            mean, P = A @ means[k - 1] + sys.input_term(k - 1), sym(A @ covs[k - 1] @ A.T + E @ Q @ E.T)
        pred_means[k], pred_covs[k] = mean, P
        C, F = sys.C_at(k), sys.F_at(k)
        FRF = F @ R @ F.T
        K = np.linalg.solve(sym(C @ P @ C.T + FRF), C @ P).T
        I_KC = np.eye(n) - K @ C
        means[k], covs[k] = mean + K @ (ys[k] - C @ mean), sym(I_KC @ P @ I_KC.T + K @ FRF @ K.T)
    s_means, s_covs = means.copy(), covs.copy()
    for k in range(steps - 2, -1, -1):
        G = np.linalg.solve(pred_covs[k + 1], sys.A_at(k) @ covs[k]).T
        s_means[k] = means[k] + G @ (s_means[k + 1] - pred_means[k + 1])
        s_covs[k] = sym(covs[k] + G @ (s_covs[k + 1] - pred_covs[k + 1]) @ G.T)
    return s_means, s_covs


@pytest.mark.parametrize("seed, n, m, p, q", [(0, 3, 2, 2, 3), (1, 2, 2, 1, 2), (2, 5, 3, 2, 1), (3, 1, 1, 1, 1)])
def test_smoother_is_bitwise_the_per_matrix_recursion(seed, n, m, p, q):
    # The loops run on stacks now; one pair must still be the very products of the per-matrix loop.
    sys, ys, x0_mean, P0, Q, R = _problem(seed, n, m, p, q, T=12)
    means, covs = _rts_one_pair(sys, ys, x0_mean, P0, Q, R)
    res = rts_smoother(sys, ys, x0_mean, P0, Q, R)
    np.testing.assert_array_equal(res.means, means)
    np.testing.assert_array_equal(res.covariances, covs)


@pytest.mark.parametrize("seed, n, m, p, q", [(0, 3, 2, 2, 3), (1, 2, 2, 1, 2), (2, 5, 3, 2, 1), (3, 1, 1, 1, 1)])
def test_smoothers_over_a_grid_are_bitwise_each_smoother(seed, n, m, p, q):
    sys, ys, x0_mean, P0, Q, R = _problem(seed, n, m, p, q, T=12)
    pairs = [(qq, rr) for qq in (0.01, 0.3, 1.0) for rr in (0.036, 2.0)] + [(Q, R), (2 * Q, 0.5)]
    for (Qi, Ri), res in zip(pairs, rts_smoothers(sys, ys, x0_mean, P0, pairs), strict=True):
        one = rts_smoother(sys, ys, x0_mean, P0, Qi, Ri)
        np.testing.assert_array_equal(res.means, one.means)
        np.testing.assert_array_equal(res.covariances, one.covariances)
        assert res.means.flags.c_contiguous and res.kind == one.kind


def test_smoothers_with_singular_predictions_fall_back_per_pair():
    sys, ys, x0_mean, _, _, R = _problem(6, T=3)
    v = np.array([1.0, 2.0, -1.0])
    P0 = np.outer(v, v)
    pairs = [(0.0, R), (1e-3, R), (0.0, 2 * R)]
    for (Qi, Ri), res in zip(pairs, rts_smoothers(sys, ys, x0_mean, P0, pairs), strict=True):
        np.testing.assert_array_equal(res.means, rts_smoother(sys, ys, x0_mean, P0, Qi, Ri).means)


def test_smoothers_need_a_pair():
    sys, ys, x0_mean, P0, _, _ = _problem(8, T=3)
    with pytest.raises(ValueError, match="at least one"):
        rts_smoothers(sys, ys, x0_mean, P0, [])
