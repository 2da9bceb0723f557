"""The scalar interval set-membership filter (smoothing paper Lemma 3 on (27)–(28), example (33)–(34))."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.filters.interval import interval_filter
from setsmooth.models.intervals import IntervalEstimates

W = (-1.0, 1.0)
V = (1.0, 3.0)


def eta33(x):
    """Smoothing paper (33): η(x) = ∛x + x (real cube root)."""
    return np.cbrt(x) + x


def meas34(k, y):
    """Smoothing paper (34): y = 2x + v with v ∈ [1, 3] gives x ∈ [(y − 3)/2, (y − 1)/2]."""
    return (y - V[1]) / 2.0, (y - V[0]) / 2.0


def simulate33(rng, T, x0_interval=(-1.0, 1.0)):
    x = np.empty(T + 1)
    x[0] = rng.uniform(*x0_interval)
    w = rng.uniform(*W, size=T)
    for k in range(T):
        x[k + 1] = eta33(x[k]) + w[k]
    y = 2.0 * x + rng.uniform(*V, size=T + 1)
    return x, y


def test_true_state_inside_posterior_ranges_over_runs():
    rng = np.random.default_rng(20240601)
    for _ in range(50):
        x, y = simulate33(rng, 50)
        est = interval_filter(eta33, W, (-1.0, 1.0), y, meas34)
        assert not est.empty.any()
        assert np.all(est.lo <= x) and np.all(x <= est.hi)
        # The update never widens the measurement interval, whose width is 1 for (34).
        assert np.all(est.diameters() <= 1.0 + 1e-12)


def test_hand_computed_linear_example():
    # η(x) = 2x + 1, w ∈ [-1, 1], prior [0, 4], y = 2x + v with v ∈ [1, 3].
    eta = lambda x: 2.0 * x + 1.0  # noqa: E731
    ys = np.array([5.0, 9.0, 21.0])
    est = interval_filter(eta, W, (0.0, 4.0), ys, meas34)
    # k=0: [0,4] ∩ [1,2] = [1,2]; k=1: [2·1+1−1, 2·2+1+1] = [2,6] ∩ [3,4] = [3,4];
    # k=2: [6, 10] ∩ [9, 10] = [9, 10].
    np.testing.assert_array_equal(est.lo, [1.0, 3.0, 9.0])
    np.testing.assert_array_equal(est.hi, [2.0, 4.0, 10.0])
    np.testing.assert_array_equal(est.diameters(), [1.0, 1.0, 1.0])


def test_time_varying_noise_interval():
    eta = lambda x: x  # noqa: E731
    wide = lambda k, y: (-np.inf, np.inf)  # noqa: E731
    est = interval_filter(eta, [[0.0, 1.0], [-2.0, 0.5]], (0.0, 0.0), np.zeros(3), wide)
    np.testing.assert_array_equal(est.lo, [0.0, 0.0, -2.0])
    np.testing.assert_array_equal(est.hi, [0.0, 1.0, 1.5])


def test_unbounded_prior_is_cut_by_first_measurement():
    est = interval_filter(eta33, W, (-np.inf, np.inf), np.array([4.0, 7.0]), meas34)
    assert (est.lo[0], est.hi[0]) == (0.5, 1.5)
    assert np.isfinite(est.lo).all() and np.isfinite(est.hi).all()


def test_inconsistent_measurement_gives_empty_from_then_on():
    rng = np.random.default_rng(3)
    x, y = simulate33(rng, 6)
    y = y.copy()
    y[3] = 2.0 * x[3] + 1000.0  # no v ∈ [1, 3] explains this
    with pytest.warns(ss.ModelInvalidationWarning, match=r"k = 3\b"):
        est = interval_filter(eta33, W, (-1.0, 1.0), y, meas34)
    np.testing.assert_array_equal(est.empty, [False, False, False, True, True, True, True])
    assert np.isnan(est.lo[3:]).all() and np.isnan(est.hi[3:]).all()
    assert np.isnan(est.diameters()[3:]).all() and np.isfinite(est.diameters()[:3]).all()


def test_estimates_are_immutable_and_validated():
    est = IntervalEstimates([0.0, np.nan], [1.0, np.nan])
    assert len(est) == 2
    with pytest.raises(ValueError):
        est.lo[0] = 5.0
    with pytest.raises(AttributeError):
        est.lo = np.zeros(2)
    with pytest.raises(ValueError, match="NaN"):
        IntervalEstimates([0.0, np.nan], [1.0, 2.0])
    with pytest.raises(ValueError, match="lo must not exceed hi"):
        IntervalEstimates([0.0, 3.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="one length"):
        IntervalEstimates([0.0], [1.0, 2.0])


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(eta=lambda x: -x), ValueError, "increasing"),
    (dict(eta=lambda x: np.nan), ValueError, "NaN"),
    (dict(eta="cbrt"), TypeError, "eta"),
    (dict(measurement_interval=None), TypeError, "measurement_interval"),
    (dict(measurement_interval=lambda k, y: (1.0, 0.0)), ValueError, "lo <= hi"),
    (dict(measurement_interval=lambda k, y: (0.0,)), ValueError, r"shape \(2,\)"),
    (dict(w_interval=(1.0, -1.0)), ValueError, "w_lo <= w_hi"),
    (dict(w_interval=np.zeros((5, 2))), ValueError, r"\(T, 2\) = \(3, 2\)"),
    (dict(w_interval=(-np.inf, 1.0)), ValueError, "finite"),
    (dict(x0_interval=(2.0, 1.0)), ValueError, "x0_interval"),
    (dict(ys=np.zeros(0)), ValueError, "ys"),
])
def test_validation(kwargs, exc, match):
    args = dict(eta=eta33, w_interval=W, x0_interval=(-1.0, 1.0), ys=np.array([1.0, 2.0, 3.0, 4.0]),
                measurement_interval=lambda k, y: (-10.0, 10.0)) | kwargs
    with pytest.raises(exc, match=match):
        interval_filter(**args)
