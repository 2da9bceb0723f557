"""The optimal nonlinear SMS (smoothing paper Proposition 2, Algorithm 2) on example (33)–(34)."""

from __future__ import annotations

import numpy as np
import pytest

from setsmooth.filters.interval import interval_filter
from setsmooth.models.intervals import IntervalEstimates
from setsmooth.papers.smoothing_examples import (SMOOTHING_33_V, SMOOTHING_33_W, eta_33, eta_33_inverse,
                                                 measurement_interval_34)
from setsmooth.smoothers.nonlinear import interval_smoother, invert_increasing

W = SMOOTHING_33_W
V = SMOOTHING_33_V
X0 = (-1.0, 1.0)
eta33, eta33_inverse, meas34 = eta_33, eta_33_inverse, measurement_interval_34


def simulate33(rng, T):
    x = np.empty(T + 1)
    x[0] = rng.uniform(*X0)
    w = rng.uniform(*W, size=T)
    for k in range(T):
        x[k + 1] = eta33(x[k]) + w[k]
    return x, 2.0 * x + rng.uniform(*V, size=T + 1)


def test_true_state_inside_and_smoothed_within_filtered_over_runs():
    rng = np.random.default_rng(12345)
    shrink = []
    for _ in range(50):
        x, y = simulate33(rng, 50)
        filt = interval_filter(eta33, W, X0, y, meas34)
        smooth = interval_smoother(eta33, W, filt)
        assert np.all(smooth.lo <= x) and np.all(x <= smooth.hi)
        assert np.all(filt.lo <= smooth.lo) and np.all(smooth.hi <= filt.hi)
        assert (smooth.lo[-1], smooth.hi[-1]) == (filt.lo[-1], filt.hi[-1])
        shrink.append(np.mean(filt.diameters() - smooth.diameters()))
    # Smoothing paper Fig. 6: smoothing tightens the ranges on average (modestly for (33)–(34):
    # the width-1 measurement interval already dominates the width-3 backward preimage).
    assert np.mean(shrink) > 0.0


def test_numerical_inverse_matches_closed_form_on_example_33():
    rng = np.random.default_rng(7)
    x, y = simulate33(rng, 40)
    filt = interval_filter(eta33, W, X0, y, meas34)
    numeric = interval_smoother(eta33, W, filt)
    closed = interval_smoother(eta33, W, filt, eta_inverse=eta33_inverse)
    np.testing.assert_allclose(numeric.lo, closed.lo, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(numeric.hi, closed.hi, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("value", [-1e6, -37.25, -1.0, 0.0, 0.5, 3.0, 1e3, 1e8])
@pytest.mark.parametrize("bracket", [None, (0.0, 1.0), (-50.0, -40.0), (1e5, 1e5 + 1), (-np.inf, 2.0)])
def test_invert_increasing_matches_analytic_inverse(value, bracket):
    eta = lambda x: 2.0 * x + 1.0  # noqa: E731
    got = invert_increasing(eta, value, bracket)
    assert got == pytest.approx((value - 1.0) / 2.0, rel=1e-13, abs=1e-13)


def test_invert_increasing_on_example_33_and_infinities():
    for t in np.linspace(-30.0, 30.0, 61):
        assert invert_increasing(eta33, t) == pytest.approx(eta33_inverse(t), rel=1e-10, abs=1e-12)
    assert invert_increasing(eta33, np.inf) == np.inf
    assert invert_increasing(eta33, -np.inf) == -np.inf


def test_smoother_with_and_without_inverse_on_linear_eta():
    eta = lambda x: 2.0 * x + 1.0  # noqa: E731
    inv = lambda t: (t - 1.0) / 2.0  # noqa: E731
    rng = np.random.default_rng(11)
    x = [rng.uniform(-1, 1)]
    for _ in range(15):
        x.append(eta(x[-1]) + rng.uniform(*W))
    y = 2.0 * np.array(x) + rng.uniform(*V, size=len(x))
    filt = interval_filter(eta, W, X0, y, meas34)
    a = interval_smoother(eta, W, filt)
    b = interval_smoother(eta, W, filt, eta_inverse=inv)
    np.testing.assert_allclose(a.lo, b.lo, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a.hi, b.hi, rtol=1e-12, atol=1e-12)
    assert np.all(a.lo <= x) and np.all(np.array(x) <= a.hi)


def test_invert_increasing_rejects_bad_eta():
    with pytest.raises(ValueError, match="increasing"):
        invert_increasing(lambda x: -x, 3.0, (0.0, 1.0))
    with pytest.raises(ValueError, match="increasing"):
        invert_increasing(lambda x: -x, 3.0)  # detected while expanding the bracket
    with pytest.raises(ValueError, match="onto R"):
        invert_increasing(np.arctan, 5.0)
    with pytest.raises(ValueError, match="NaN"):
        invert_increasing(eta33, np.nan)


# --- an independent oracle: forward–backward reachability on a fine state grid -----------------

def _grid_oracle(eta, w, x0, y, meas, n_cells):
    """Inner and outer bounds on the filtered and smoothed ranges from a state-space grid.

    At each k the measurement interval (∩ ⟦x_0⟧ at k = 0) is cut into ``n_cells`` cells. Inner: a
    path of cell centres whose increments x' − η(x) all lie in ⟦w⟧ is a genuine trajectory consistent
    with every measurement, so its states lie in the true ranges. Outer: a cell pair is kept when
    *some* points of the two cells are linked by some w ∈ ⟦w⟧ (η monotone, so the reachable w-range
    is an interval computed from cell ends); every true trajectory runs through kept cells, so the
    kept cells cover the true ranges. Neither bound uses interval propagation or η⁻¹.
    """
    T = len(y) - 1
    centres, half = [], []
    for k in range(T + 1):
        lo, hi = meas(k, y[k])
        if k == 0:
            lo, hi = max(lo, x0[0]), min(hi, x0[1])
        h = (hi - lo) / n_cells
        centres.append(lo + h * (np.arange(n_cells) + 0.5))
        half.append(h / 2.0)
    strict, relaxed = [], []
    for k in range(T):
        c, c1, h, h1 = centres[k], centres[k + 1], half[k], half[k + 1]
        inc = c1[None, :] - eta(c)[:, None]
        strict.append((inc >= w[0] - 1e-12) & (inc <= w[1] + 1e-12))
        inc_lo = (c1 - h1)[None, :] - eta(c + h)[:, None]
        inc_hi = (c1 + h1)[None, :] - eta(c - h)[:, None]
        relaxed.append((inc_hi >= w[0]) & (inc_lo <= w[1]))

    def reach(trans):
        fwd = [np.ones(n_cells, bool)]
        for M in trans:
            fwd.append((fwd[-1][:, None] & M).any(axis=0))
        bwd = [np.ones(n_cells, bool)]
        for M in reversed(trans):
            bwd.insert(0, (M & bwd[0][None, :]).any(axis=1))
        return fwd, [f & b for f, b in zip(fwd, bwd)]

    def bounds(masks, pad):
        return [(centres[k][m].min() - pad[k], centres[k][m].max() + pad[k]) for k, m in enumerate(masks)]

    s_fwd, s_both = reach(strict)
    r_fwd, r_both = reach(relaxed)
    zero = [0.0] * (T + 1)
    return dict(filt_inner=bounds(s_fwd, zero), filt_outer=bounds(r_fwd, half),
                smooth_inner=bounds(s_both, zero), smooth_outer=bounds(r_both, half), h=2 * max(half))


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_filter_and_smoother_match_grid_oracle(seed):
    rng = np.random.default_rng(seed)
    x, y = simulate33(rng, 4)
    filt = interval_filter(eta33, W, X0, y, meas34)
    smooth = interval_smoother(eta33, W, filt)
    oracle = _grid_oracle(eta33, W, X0, y, meas34, n_cells=1500)
    eps = 1e-9
    for est, name in ((filt, "filt"), (smooth, "smooth")):
        for k in range(len(y)):
            (in_lo, in_hi), (out_lo, out_hi) = oracle[f"{name}_inner"][k], oracle[f"{name}_outer"][k]
            # outer ⊇ true range ⊇ inner, endpoint by endpoint.
            assert out_lo - eps <= est.lo[k] <= in_lo + eps, (name, k)
            assert in_hi - eps <= est.hi[k] <= out_hi + eps, (name, k)
            # The oracle is tight to a few cells, so these checks have teeth.
            assert in_lo - out_lo < 10 * oracle["h"] and out_hi - in_hi < 10 * oracle["h"]


def test_empty_posterior_gives_all_empty_smoothed():
    filt = IntervalEstimates([0.0, 1.0, np.nan], [1.0, 2.0, np.nan])
    smooth = interval_smoother(eta33, W, filt)
    assert smooth.empty.all() and len(smooth) == 3


def test_single_step_horizon_returns_posterior():
    filt = IntervalEstimates([0.25], [0.75])
    smooth = interval_smoother(eta33, np.zeros((0, 2)), filt)
    np.testing.assert_array_equal(smooth.lo, [0.25])
    np.testing.assert_array_equal(smooth.hi, [0.75])


def test_time_varying_noise_intervals():
    eta = lambda x: x  # noqa: E731
    # x_2 ∈ [1, 1.5] and w_1 ∈ [-2, 0.5] pin x_1 ≥ 0.5; w_0 ∈ [0, 1] leaves x_0 = 0 as it is.
    filt = IntervalEstimates([0.0, 0.0, 1.0], [0.0, 1.0, 1.5])
    smooth = interval_smoother(eta, [[0.0, 1.0], [-2.0, 0.5]], filt)
    np.testing.assert_allclose(smooth.lo, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(smooth.hi, [0.0, 1.0, 1.5])


def test_validation():
    filt = IntervalEstimates([0.0, 1.0], [1.0, 2.0])
    with pytest.raises(TypeError, match="filtered"):
        interval_smoother(eta33, W, (np.zeros(2), np.ones(2)))
    with pytest.raises(TypeError, match="eta_inverse"):
        interval_smoother(eta33, W, filt, eta_inverse=3.0)
    with pytest.raises(TypeError, match="eta"):
        interval_smoother(None, W, filt)
    with pytest.raises(ValueError, match="w_interval"):
        interval_smoother(eta33, np.zeros((3, 2)), filt)
    with pytest.raises(ValueError, match="NaN"):
        interval_smoother(eta33, W, filt, eta_inverse=lambda t: np.nan)
