"""Kalman filter and Rauch–Tung–Striebel smoother: the stochastic baseline of smoothing paper §IV-C.

For the linear time-varying model of smoothing paper (13)–(14), with a known input,

    x_{k+1} = A_k x_k + B_k u_k + E_k w_k,      w_k ~ N(0, Q)   (p-dimensional),
    y_k     = C_k x_k + D_k u_k + F_k v_k,      v_k ~ N(0, R)   (q-dimensional),

with x_0 ~ N(x0_mean, P0). The set-membership model gives no noise statistics, so Q and R are tuning
parameters; the paper uses Q = q, R = r·I (32). Measurement y_0 is taken at k = 0: step 0 updates the
prior with y_0 and does not predict.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validation import as_matrix, as_measurements, as_vector, check_dim, real_number
from ..results import Tubes


@dataclass(frozen=True)
class KalmanResult(Tubes):
    """Gaussian estimates N(means[k], covariances[k]) of x_k for k = 0..T, with σ-boxes as tubes.

    It follows the `Estimates` protocol with the box means[k] ± sigmas·σ_k as the k-th tube, σ_k the
    marginal standard deviations (the square roots of the diagonal of covariances[k]): ``lo``,
    ``hi``, ``centers`` (the means), ``diameters()``, ``contains_trajectory`` (whether x_k lies in
    the box), ``plot_tubes`` and ``len``, so that it can be plotted and scored beside the
    set-membership results. The box is a confidence region, not a bound: under the Gaussian model
    each coordinate lies in its 3σ interval with probability 99.7 %, and nothing holds for bounded
    noises that are not Gaussian (Q, R are tuning parameters here). ``first_empty`` is always None:
    a Gaussian estimate is never empty, so the Kalman filter does not detect data that contradict
    the model (`first_inconsistency` does, on the set-membership model).
    ``dataclasses.replace(result, sigmas=2.0)`` gives other boxes from the same estimates.

    Attributes
    ----------
    means : ndarray, shape (T+1, n)
        Filtered E[x_k | y_{0:k}] or smoothed E[x_k | y_{0:T}] means.
    covariances : ndarray, shape (T+1, n, n)
        The matching covariances.
    predicted_means : ndarray, shape (T+1, n), or None
        Filter only: E[x_k | y_{0:k-1}]; entry 0 is the prior mean x0_mean.
    predicted_covariances : ndarray, shape (T+1, n, n), or None
        Filter only: the matching covariances; entry 0 is P0.
    sigmas : float
        The half-width of the tubes in standard deviations (3 by default), positive and finite.
    kind : str
        The tubes' label: 'Kalman filter' or 'RTS smoother'.
    system : LinearSystem or None
        The system the estimates were computed for (its sampling time ``dt`` scales the time axis
        of ``plot_tubes``).

    Raises
    ------
    ValueError
        When ``sigmas`` is not positive and finite.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> kalman = ss.kalman_filter(system, [[0.0], [0.5]], [0.0], [[1.0]], 1.0, 1.0)
    >>> kalman.lo.round(3).tolist(), kalman.first_empty
    ([[-2.121], [-2.024]], None)
    """

    means: np.ndarray
    covariances: np.ndarray
    predicted_means: np.ndarray | None = None
    predicted_covariances: np.ndarray | None = None
    sigmas: float = 3.0
    kind: str = ""
    system: Any = field(default=None, repr=False)

    def __post_init__(self) -> None:
        sigmas = real_number(self.sigmas, "sigmas")
        if not (np.isfinite(sigmas) and sigmas > 0):
            raise ValueError(f"sigmas must be a positive finite number of standard deviations, got "
                             f"{self.sigmas!r}")
        object.__setattr__(self, "sigmas", sigmas)

    @property
    def std(self) -> np.ndarray:
        """σ_k: the marginal standard deviations, shape (T+1, n)."""
        variances = np.diagonal(self.covariances, axis1=1, axis2=2)
        return np.sqrt(np.maximum(variances, 0.0))   # a rounding-negative zero variance is zero

    @property
    def lo(self) -> np.ndarray:
        """means − sigmas·σ, shape (T+1, n)."""
        return self.means - self.sigmas * self.std

    @property
    def hi(self) -> np.ndarray:
        """means + sigmas·σ, shape (T+1, n)."""
        return self.means + self.sigmas * self.std

    @property
    def centers(self) -> np.ndarray:
        """The means, shape (T+1, n): the centres of the boxes."""
        return self.means

    def __len__(self) -> int:
        return len(self.means)


def kalman_filter(system: Any, ys: Any, x0_mean: Any, P0: Any, Q: Any, R: Any) -> KalmanResult:
    """Filtered Gaussian estimates of x_k given y_{0:k}, for k = 0..T.

    Parameters
    ----------
    system : object
        Provides ``n`` (state dimension) and methods ``A_at(k)`` (n×n), ``E_at(k)`` (n×p, the
        process-noise matrix), ``C_at(k)`` (m×n), ``F_at(k)`` (m×q, the measurement-noise matrix)
        and ``input_term(k)`` (the known term B_k u_k of x_{k+1}, length n), as
        `setsmooth.models.linear_system.LinearSystem` does (whose feedthrough D_k u_k is subtracted from
        the measurements first).
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T (a 1-D array is accepted when m = 1).
    x0_mean : array_like, shape (n,)
        Prior mean of x_0.
    P0 : array_like, shape (n, n)
        Prior covariance of x_0 (symmetric positive semidefinite).
    Q : float or array_like, shape (p, p)
        Covariance of w_k; a scalar q means q·I_p (smoothing paper (32)).
    R : float or array_like, shape (q, q)
        Covariance of v_k; a scalar r means r·I_q (smoothing paper (32)).

    Returns
    -------
    KalmanResult
        ``means``/``covariances`` are the posteriors given y_{0:k}; ``predicted_means``/
        ``predicted_covariances`` the priors given y_{0:k-1}; its tubes are the 3σ boxes.

    Raises
    ------
    ValueError
        When shapes disagree, a covariance is not symmetric positive semidefinite, or an innovation
        covariance C_k P C_kᵀ + F_k R F_kᵀ is singular.
    TypeError
        When ``system`` lacks the required interface.

    References
    ----------
    Smoothing paper §IV-C (RTS baseline, [6], [22]); R. E. Kalman (1960).
    """
    system, n, ys, m0, P = _validate(system, ys, x0_mean, P0)
    Q, R = _noise_covariances(system, n, ys, Q, R)
    return KalmanResult(*_filter(system, ys, m0, P, Q, R), kind="Kalman filter", system=system)


def rts_smoother(system: Any, ys: Any, x0_mean: Any, P0: Any, Q: Any, R: Any) -> KalmanResult:
    """Smoothed Gaussian estimates of x_k given y_{0:T} (Rauch–Tung–Striebel), for k = 0..T.

    Runs `kalman_filter`, then the backward pass

        G_k  = P_{k|k} A_kᵀ P_{k+1|k}⁻¹,
        m_k^s = m_{k|k} + G_k (m_{k+1}^s − m_{k+1|k}),
        P_k^s = P_{k|k} + G_k (P_{k+1}^s − P_{k+1|k}) G_kᵀ.

    Parameters
    ----------
    system, ys, x0_mean, P0, Q, R
        As for `kalman_filter`.

    Returns
    -------
    KalmanResult
        ``means``/``covariances`` are E[x_k | y_{0:T}] and its covariance; the ``predicted_*``
        fields are None.

    Raises
    ------
    ValueError, TypeError
        As for `kalman_filter`.

    References
    ----------
    Smoothing paper §IV-C and (32); H. E. Rauch, F. Tung, C. T. Striebel, AIAA J. 3(8), 1965.
    """
    system, n, ys, m0, P = _validate(system, ys, x0_mean, P0)
    Q, R = _noise_covariances(system, n, ys, Q, R)
    return KalmanResult(*_smooth(system, *_filter(system, ys, m0, P, Q, R)), kind="RTS smoother",
                        system=system)


def rts_smoothers(system: Any, ys: Any, x0_mean: Any, P0: Any, noise_covariances: Any) -> list[KalmanResult]:
    """`rts_smoother` for each (Q, R) of ``noise_covariances``, all pairs run as one recursion.

    The smoothing paper's tuning (Fig. 4) runs the smoother on one record for a grid of (q, r) (32);
    the recursion is the same for every pair, so it runs once on stacks of covariances, each stacked
    product and solve the very operation `rts_smoother` does on that pair: every result is bit for bit
    `rts_smoother(system, ys, x0_mean, P0, Q, R)`.

    Parameters
    ----------
    system, ys, x0_mean, P0
        As for `kalman_filter`.
    noise_covariances : sequence of (Q, R)
        Each Q and R as for `kalman_filter`.

    Returns
    -------
    list of KalmanResult
        One per pair, in order, as `rts_smoother` returns it.

    Raises
    ------
    ValueError, TypeError
        As for `kalman_filter`, and when ``noise_covariances`` is empty.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> from setsmooth.filters.kalman import rts_smoothers
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> ys = [[0.0], [0.5]]
    >>> grid = rts_smoothers(system, ys, [0.0], [[1.0]], [(1.0, 1.0), (1.0, 2.0)])
    >>> [r.means.ravel().round(3).tolist() for r in grid]
    [[0.1, 0.3], [0.091, 0.227]]
    >>> bool((grid[1].means == ss.rts_smoother(system, ys, [0.0], [[1.0]], 1.0, 2.0).means).all())
    True
    """
    system, n, ys, m0, P = _validate(system, ys, x0_mean, P0)
    pairs = [_noise_covariances(system, n, ys, Q, R) for Q, R in noise_covariances]
    if not pairs:
        raise ValueError("noise_covariances must hold at least one (Q, R) pair")
    Q, R = (np.stack(stack) for stack in zip(*pairs))
    means, covs = _smooth(system, *_filter(system, ys, m0, P, Q, R))
    # Pair i's arrays made contiguous, as `rts_smoother` returns them.
    return [KalmanResult(np.ascontiguousarray(means[:, i]), np.ascontiguousarray(covs[:, i]),
                         kind="RTS smoother", system=system) for i in range(len(pairs))]


def _noise_covariances(system: Any, n: int, ys: np.ndarray, Q: Any, R: Any) -> tuple[np.ndarray, np.ndarray]:
    # Validated once here; the loops below trust them (system matrices are validated by the system).
    return (_noise_covariance(Q, "Q", _mat(system.E_at(0), "E(0)", n, None).shape[1]),
            _noise_covariance(R, "R", _mat(system.F_at(0), "F(0)", ys.shape[1], None).shape[1]))


def _filter(system: Any, ys: np.ndarray, m0: np.ndarray, P0: np.ndarray, Q: np.ndarray,
            R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The Kalman recursion: means, covariances, predicted means, predicted covariances.

    Q (…, p, p) and R (…, q, q) may be stacks, one filter per stacked pair: the arrays are then
    (T+1, …, n) and (T+1, …, n, n), and every stacked product is the one of that filter alone.
    """
    steps, n = ys.shape[0], m0.shape[0]
    batch = np.broadcast_shapes(Q.shape[:-2], R.shape[:-2])
    means = np.empty((steps, *batch, n))
    covs = np.empty((steps, *batch, n, n))
    pred_means = np.empty((steps, *batch, n))
    pred_covs = np.empty((steps, *batch, n, n))
    mean, P = m0, P0
    for k in range(steps):
        if k > 0:
            mean, P = _predict(system, k - 1, means[k - 1], covs[k - 1], Q)
        pred_means[k], pred_covs[k] = mean, P
        means[k], covs[k] = _update(system, k, mean, P, ys[k], R, n)
    return means, covs, pred_means, pred_covs


def _smooth(system: Any, f_means: np.ndarray, f_covs: np.ndarray, pred_means: np.ndarray,
            pred_covs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The RTS backward pass over `_filter`'s arrays (stacked or not): smoothed means and covariances."""
    means = f_means.copy()
    covs = f_covs.copy()
    for k in range(means.shape[0] - 2, -1, -1):
        A = np.asarray(system.A_at(k))
        P_pred = pred_covs[k + 1]
        # Gᵀ = P_pred⁻¹ A P_filt since both covariances are symmetric.
        G = _transpose(_solve_psd(P_pred, A @ f_covs[k]))
        means[k] = f_means[k] + _times_vector(G, means[k + 1] - pred_means[k + 1])
        covs[k] = _symmetrize(f_covs[k] + G @ (covs[k + 1] - P_pred) @ _transpose(G))
    return means, covs


def _predict(system: Any, k: int, mean: np.ndarray, P: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    A, E = np.asarray(system.A_at(k)), np.asarray(system.E_at(k))
    return _times_vector(A, mean) + system.input_term(k), _symmetrize(A @ P @ _transpose(A) + E @ Q @ E.T)


def _update(system: Any, k: int, mean: np.ndarray, P: np.ndarray, y: np.ndarray, R: np.ndarray,
            n: int) -> tuple[np.ndarray, np.ndarray]:
    C, F = np.asarray(system.C_at(k)), np.asarray(system.F_at(k))
    FRF = F @ R @ F.T
    S = _symmetrize(C @ P @ C.T + FRF)
    try:
        # numpy's solve: scipy's argument checks cost more than the solve for these small matrices
        K = _transpose(np.linalg.solve(S, C @ P))
    except np.linalg.LinAlgError as exc:
        raise ValueError(f"innovation covariance C P Cᵀ + F R Fᵀ at k = {k} is singular; "
                         "make R (or P0) positive definite") from exc
    # Joseph form: stays symmetric PSD under rounding, unlike P − K S Kᵀ.
    I_KC = np.eye(n) - K @ C
    P_post = _symmetrize(I_KC @ P @ _transpose(I_KC) + K @ FRF @ _transpose(K))
    return mean + _times_vector(K, y - _times_vector(C, mean)), P_post


def _solve_psd(P: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """P⁻¹ rhs for a PSD P (or a stack of them); the least-squares (pseudo-inverse) solution when P is
    singular."""
    try:
        return np.linalg.solve(P, rhs)
    except np.linalg.LinAlgError:
        # Singular P_{k+1|k} (e.g. Q = 0 with a degenerate P0): the pseudo-inverse gain is the
        # limit of the regularized one and still yields the correct conditional mean.
        if P.ndim > 2:
            return np.stack([_solve_psd(P_i, rhs_i) for P_i, rhs_i in zip(*np.broadcast_arrays(P, rhs))])
        return np.linalg.lstsq(P, rhs, rcond=None)[0]


def _validate(system: Any, ys: Any, x0_mean: Any,
              P0: Any) -> tuple[Any, int, np.ndarray, np.ndarray, np.ndarray]:
    for attr in ("A_at", "E_at", "C_at", "F_at", "input_term"):
        if not callable(getattr(system, attr, None)):
            raise TypeError(f"system must provide a method {attr}(k); got {type(system).__name__}")
    n = check_dim(getattr(system, "n", None), "system.n")
    m = _mat(system.C_at(0), "C(0)", None, n).shape[0]
    arr = as_measurements(ys, m)
    if callable(getattr(system, "check_input", None)):
        system.check_input(len(arr) - 1)
    if getattr(system, "has_feedthrough", False):
        system, arr = system.without_feedthrough(arr)
    mean = as_vector(x0_mean, "x0_mean", n)
    P = _covariance(P0, "P0", n)
    return system, n, arr, mean, P


def _noise_covariance(value: Any, name: str, dim: int) -> np.ndarray:
    if np.ndim(value) == 0:
        scale = real_number(value, name)
        if not np.isfinite(scale) or scale < 0:
            raise ValueError(f"{name} must be a non-negative scalar or a ({dim}, {dim}) matrix, got {value}")
        return scale * np.eye(dim)
    return _covariance(value, name, dim)


def _covariance(value: Any, name: str, dim: int) -> np.ndarray:
    M = as_matrix(value, name, dim, dim)
    scale = max(1.0, float(np.abs(M).max()))
    if not np.allclose(M, M.T, rtol=0.0, atol=1e-10 * scale):
        raise ValueError(f"{name} must be symmetric, got a ({dim}, {dim}) matrix that is not")
    if np.linalg.eigvalsh(M).min() < -1e-10 * scale:
        raise ValueError(f"{name} must be positive semidefinite")
    return _symmetrize(M)


def _mat(value: Any, name: str, rows: int | None, cols: int | None) -> np.ndarray:
    return as_matrix(value, f"system.{name}", rows, cols)


def _symmetrize(M: np.ndarray) -> np.ndarray:
    return 0.5 * (M + _transpose(M))


def _transpose(M: np.ndarray) -> np.ndarray:
    """Mᵀ of a matrix or of each matrix of a stack (for a matrix the view M.T)."""
    return np.swapaxes(M, -1, -2)


def _times_vector(M: np.ndarray, v: np.ndarray) -> np.ndarray:
    """M v for a vector or a stack of vectors v (…, n), M a matrix or a stack: the same gemv per vector as
    M @ v on one vector."""
    return (M @ v[..., None])[..., 0]
