"""The optimal set-membership smoother for x_{k+1} = η(x_k) + w_k (smoothing paper Prop. 2, Algorithm 2).

Backward from ⟦x_T | y_{0:T}⟧ = [a_T, b_T], for k = T−1, …, 0:

    ā_k = η⁻¹(ã_{k+1} − w_hi),   b̄_k = η⁻¹(b̃_{k+1} − w_lo),                        (30)
    ⟦x_k | y_{0:T}⟧ = [ã_k, b̃_k] = [max(ā_k, a_k), min(b̄_k, b_k)].                   (29)

(30) writes the bracket of x_{k+1} as [ā_{k+1}, b̄_{k+1}]; it is the smoothed range [ã_{k+1}, b̃_{k+1}],
as the proof of Proposition 2 and Algorithm 2 state. Because η is increasing, η⁻¹(x_{k+1} − w_k) is
increasing in x_{k+1} and decreasing in w_k, so the min and max of (30) sit at those endpoints.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .._validation import real_number
from ..models.intervals import IntervalEstimates, eval_eta, noise_intervals

# brentq stops when the bracket is below _XTOL + _RTOL·|x|, i.e. at about machine precision.
_XTOL = 1e-14
_RTOL = 4 * np.finfo(float).eps
_MAX_ITER = 500


def interval_smoother(eta: Callable[[float], float], w_interval: Any, filtered: IntervalEstimates,
                      eta_inverse: Callable[[float], float] | None = None) -> IntervalEstimates:
    """Smoothed ranges ⟦x_k | y_{0:T}⟧ for k = 0..T (smoothing paper Proposition 2, Algorithm 2).

    Parameters
    ----------
    eta : callable float -> float
        The transition η of (27): continuous and strictly increasing, mapping ℝ onto ℝ.
    w_interval : array_like, shape (2,) or (T, 2)
        Process-noise range [w_lo, w_hi], constant or one row per step k = 0..T-1.
    filtered : IntervalEstimates
        Posterior ranges [a_k, b_k] = ⟦x_k | y_{0:k}⟧ from `setsmooth.filters.interval.interval_filter`.
    eta_inverse : callable float -> float, optional
        η⁻¹ in closed form. Without it η is inverted numerically (`invert_increasing`), using the
        filtered interval as the first bracket.

    Returns
    -------
    IntervalEstimates
        ``[lo[k], hi[k]]`` = ⟦x_k | y_{0:T}⟧; entry T equals the last posterior. When any posterior
        is empty no trajectory is consistent with y_{0:T}, and every smoothed range is empty (NaN).

    Raises
    ------
    TypeError
        When ``filtered`` is not an `IntervalEstimates` or ``eta``/``eta_inverse`` is not callable.
    ValueError
        When ``w_interval`` has the wrong shape, or η is detected not to be increasing or not to
        reach a required value.

    References
    ----------
    Smoothing paper Theorem 1 (8), Proposition 2 (29)–(30), Algorithm 2; example (33)–(34).
    """
    if not callable(eta):
        raise TypeError(f"eta must be a callable float -> float, got {type(eta).__name__}")
    if eta_inverse is not None and not callable(eta_inverse):
        raise TypeError(f"eta_inverse must be callable or None, got {type(eta_inverse).__name__}")
    if not isinstance(filtered, IntervalEstimates):
        raise TypeError(f"filtered must be IntervalEstimates (from interval_filter), got "
                        f"{type(filtered).__name__}")
    T = len(filtered) - 1
    w = noise_intervals(w_interval, T)
    all_empty = IntervalEstimates(np.full(T + 1, np.nan), np.full(T + 1, np.nan))
    if filtered.empty.any():
        return all_empty
    lo = filtered.lo.copy()
    hi = filtered.hi.copy()
    for k in range(T - 1, -1, -1):
        a, b = filtered.lo[k], filtered.hi[k]
        lo[k] = _smoothed_lower(eta, eta_inverse, lo[k + 1] - w[k, 1], a, b)
        hi[k] = _smoothed_upper(eta, eta_inverse, hi[k + 1] - w[k, 0], a, b)
        if lo[k] > hi[k]:
            # Only rounding can get here from consistent posteriors; an empty range at one step
            # means no consistent trajectory, hence empty everywhere.
            return all_empty
    return IntervalEstimates(lo, hi)


def invert_increasing(eta: Callable[[float], float], value: float,
                      bracket: tuple[float, float] | None = None) -> float:
    """Solve η(x) = value for a continuous, strictly increasing η: ℝ → ℝ (brentq, expanding bracket).

    Parameters
    ----------
    eta : callable float -> float
        Continuous, strictly increasing, onto ℝ.
    value : float
        Target; ±inf returns ±inf (an increasing bijection of ℝ sends ±∞ to ±∞).
    bracket : (float, float), optional
        A first guess [lo, hi] for the solution; expanded geometrically until η(lo) ≤ value ≤ η(hi).
        Infinite ends are ignored. Defaults to [value, value].

    Returns
    -------
    float
        x with η(x) = value, to about machine precision.

    Raises
    ------
    ValueError
        When η is seen to decrease between two evaluated points, returns NaN, or does not reach
        ``value`` before the bracket overflows (η not onto ℝ).
    """
    value = float(value)
    if np.isnan(value):
        raise ValueError("value must not be NaN")
    if np.isinf(value):
        return value
    finite = [float(x) for x in (bracket or ()) if np.isfinite(x)]
    lo, hi = (min(finite), max(finite)) if finite else (value, value)

    def f(x: float) -> float:
        return eval_eta(eta, x) - value

    f_lo, f_hi = f(lo), f(hi)
    if f_lo > f_hi:
        raise ValueError(f"eta must be increasing: eta({lo!r}) > eta({hi!r})")
    step = max(1.0, hi - lo)
    # Expand only in the direction of the root, keeping the last point as the other bracket end.
    while f_lo > 0:
        new = lo - step
        if not np.isfinite(new):
            raise ValueError(f"eta never reaches {value!r} from above; eta must map R onto R")
        f_new = f(new)
        if f_new > f_lo:
            raise ValueError(f"eta must be increasing: eta({new!r}) > eta({lo!r})")
        hi, f_hi, lo, f_lo, step = lo, f_lo, new, f_new, 2.0 * step
    while f_hi < 0:
        new = hi + step
        if not np.isfinite(new):
            raise ValueError(f"eta never reaches {value!r} from below; eta must map R onto R")
        f_new = f(new)
        if f_new < f_hi:
            raise ValueError(f"eta must be increasing: eta({hi!r}) > eta({new!r})")
        lo, f_lo, hi, f_hi, step = hi, f_hi, new, f_new, 2.0 * step
    if f_lo == 0:
        return lo
    if f_hi == 0:
        return hi
    return float(brentq(f, lo, hi, xtol=_XTOL, rtol=_RTOL, maxiter=_MAX_ITER))


def _smoothed_lower(eta, eta_inverse, target: float, a: float, b: float) -> float:
    """ã_k = max(η⁻¹(target), a) with target = ã_{k+1} − w_hi (29)–(30)."""
    if eta_inverse is not None:
        return max(_checked(eta_inverse, target), a)
    # η(a) ≥ target already means η⁻¹(target) ≤ a: the max is a, no root to find.
    if np.isfinite(a) and eval_eta(eta, a) >= target:
        return a
    return max(invert_increasing(eta, target, (a, b)), a)


def _smoothed_upper(eta, eta_inverse, target: float, a: float, b: float) -> float:
    """b̃_k = min(η⁻¹(target), b) with target = b̃_{k+1} − w_lo (29)–(30)."""
    if eta_inverse is not None:
        return min(_checked(eta_inverse, target), b)
    if np.isfinite(b) and eval_eta(eta, b) <= target:
        return b
    return min(invert_increasing(eta, target, (a, b)), b)


def _checked(eta_inverse: Callable[[float], float], value: float) -> float:
    out = real_number(eta_inverse(float(value)), f"eta_inverse({float(value)!r})")
    if np.isnan(out):
        raise ValueError(f"eta_inverse({value!r}) returned NaN")
    return out
