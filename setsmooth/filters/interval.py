"""The optimal set-membership filter for scalar systems with monotone dynamics (smoothing paper (27)–(28)).

    x_{k+1} = η(x_k) + w_k,   w_k ∈ [w_lo, w_hi],        y_k = g(x_k, v_k),

with η: ℝ → ℝ continuous and strictly increasing. Every range is then an interval and Lemma 3 reduces
to interval endpoint arithmetic:

    prediction (6):  [a, b] ↦ [η(a) + w_lo, η(b) + w_hi],
    update (7):      prior ∩ {x : y_k = g(x, v) for some v ∈ ⟦v_k⟧},

where the measurement-consistent interval is supplied by the caller (for y = 2x + v, v ∈ [1, 3]:
x ∈ [(y − 3)/2, (y − 1)/2], smoothing paper (34)).

An empty range is stored as ``lo = hi = nan`` (`setsmooth.models.intervals.IntervalEstimates`); the
first one is reported as the other estimators report it (`setsmooth.filters.consistency`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import real_array
from ..models.intervals import IntervalEstimates, as_interval, eval_eta, noise_intervals
from .consistency import IntervalInconsistency, check_on_inconsistent, report_inconsistency


def interval_filter(eta: Callable[[float], float], w_interval: Any, x0_interval: Any, ys: Any,
                    measurement_interval: Callable[[int, Any], tuple[float, float]], *,
                    on_inconsistent: str = "warn") -> IntervalEstimates:
    """Posterior ranges ⟦x_k | y_{0:k}⟧ = [a_k, b_k] for k = 0..T (smoothing paper Lemma 3, (6)–(7)).

    Parameters
    ----------
    eta : callable float -> float
        The transition η of (27); must be continuous and strictly increasing on ℝ.
    w_interval : array_like, shape (2,) or (T, 2)
        Process-noise range [w_lo, w_hi], constant or one row per step k = 0..T-1.
    x0_interval : array_like, shape (2,)
        Initial prior range ⟦x_0⟧ = [lo, hi]; infinite endpoints are allowed.
    ys : array_like, shape (T+1,) or (T+1, m)
        Measurements; ``ys[k]`` is passed unchanged to ``measurement_interval``.
    measurement_interval : callable (k, y_k) -> (lo, hi)
        The interval ⋃_{v ∈ ⟦v_k⟧} g_{k,v}⁻¹({y_k}) of states consistent with y_k (7).
    on_inconsistent : {'warn', 'raise', 'ignore'}, keyword-only
        What to do when the data contradict the model (a posterior is empty): 'warn' (default)
        issues a `ModelInvalidationWarning` naming the first such k, y_k and the gap between the
        states consistent with y_k and the predicted range (an `IntervalInconsistency`, its
        ``inconsistency`` attribute); 'raise' raises `ModelInvalidatedError`; 'ignore' is silent.

    Returns
    -------
    IntervalEstimates
        The posteriors. Once a range is empty (measurements inconsistent with the model) every
        later range is empty too.

    Raises
    ------
    ValueError
        For malformed intervals, a measurement interval with lo > hi or NaN, or when η is seen not to
        be increasing (η(a) > η(b) for a < b) or returns NaN; an unknown ``on_inconsistent``;
        `ModelInvalidatedError` (a ValueError) for inconsistent data with ``on_inconsistent='raise'``.
    TypeError
        When ``eta`` or ``measurement_interval`` is not callable.

    References
    ----------
    Smoothing paper Lemma 3 (6)–(7) and §IV-B; the example (33)–(34) uses η(x) = ∛x + x.
    """
    if not callable(eta):
        raise TypeError(f"eta must be a callable float -> float, got {type(eta).__name__}")
    if not callable(measurement_interval):
        raise TypeError("measurement_interval must be a callable (k, y_k) -> (lo, hi), got "
                        f"{type(measurement_interval).__name__}")
    check_on_inconsistent(on_inconsistent)
    ys = real_array(ys, "ys", "an array of measurements")
    if ys.ndim < 1 or ys.shape[0] < 1:
        raise ValueError(f"ys must have shape (T+1,) or (T+1, m) with T >= 0, got {ys.shape}")
    if not np.isfinite(ys).all():
        raise ValueError("ys contains NaN or inf")
    steps = ys.shape[0]
    w = noise_intervals(w_interval, steps - 1)
    lo0, hi0 = as_interval(x0_interval, "x0_interval", allow_inf=True)
    estimates, found = _interval_filter(eta, w, (lo0, hi0), ys, measurement_interval)
    report_inconsistency(found, on_inconsistent)
    return estimates


def _interval_filter(eta: Callable[[float], float], w: np.ndarray, x0: tuple[float, float], ys: np.ndarray,
                     measurement_interval: Callable) -> tuple[IntervalEstimates, IntervalInconsistency | None]:
    """Lemma 3's loop on checked arguments; the first empty posterior, if any, as an inconsistency."""
    steps = ys.shape[0]
    lo = np.full(steps, np.nan)
    hi = np.full(steps, np.nan)
    prior = x0
    for k in range(steps):
        if k > 0:
            eta_lo, eta_hi = eval_eta(eta, lo[k - 1]), eval_eta(eta, hi[k - 1])
            if eta_lo > eta_hi:
                raise ValueError(f"eta must be increasing: eta({lo[k - 1]}) > eta({hi[k - 1]})")
            prior = (eta_lo + w[k - 1, 0], eta_hi + w[k - 1, 1])
        m_lo, m_hi = as_interval(measurement_interval(k, ys[k]), f"measurement_interval({k}, ys[{k}])",
                                 allow_inf=True)
        a, b = max(prior[0], m_lo), min(prior[1], m_hi)
        if a > b:  # inconsistent data: this and all later ranges stay NaN (empty)
            gap = float(max(m_lo - prior[1], prior[0] - m_hi))
            y = np.atleast_1d(np.asarray(ys[k], dtype=float)).copy()
            return IntervalEstimates(lo, hi), IntervalInconsistency(
                k, y, gap, predicted=(float(prior[0]), float(prior[1])), consistent=(m_lo, m_hi))
        lo[k], hi[k] = a, b
    return IntervalEstimates(lo, hi), None
