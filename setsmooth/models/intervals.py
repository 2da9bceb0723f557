"""Interval ranges of scalar monotone systems, shared by the interval filter and smoother.

Smoothing paper (27)–(30): for x_{k+1} = η(x_k) + w_k with η continuous and strictly increasing, every
filtered and smoothed range is an interval. `IntervalEstimates` holds them (NaN marks an empty range:
NaN can never pass as a real bound in a comparison); `eval_eta`, `noise_intervals` and `as_interval`
check the user's η and intervals the same way for `setsmooth.filters.interval` and
`setsmooth.smoothers.nonlinear`. (`IntervalEstimates` is defined in `setsmooth.results`, with the
other results, and importable from here as before.)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import _FLOATS, real_array, real_number
from ..results import IntervalEstimates  # noqa: F401  (its old home: importable from here)

__all__ = ["eval_eta", "noise_intervals", "as_interval"]


def noise_intervals(w_interval: Any, T: int) -> np.ndarray:
    """The process-noise ranges as a (T, 2) array of finite [w_lo, w_hi] rows, one per step k < T.

    Parameters
    ----------
    w_interval : array_like, shape (2,) or (T, 2)
        One constant range, or one per step.
    T : int
        The number of transitions.

    Raises
    ------
    ValueError
        On a wrong shape, infinite endpoints or w_lo > w_hi.

    Examples
    --------
    >>> noise_intervals([-1, 1], 3).tolist()
    [[-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]]
    """
    arr = real_array(w_interval, "w_interval", "an array of intervals [w_lo, w_hi]")
    if arr.shape == (2,):
        arr = np.broadcast_to(arr, (T, 2))
    if arr.shape != (T, 2):
        raise ValueError(f"w_interval must have shape (2,) or (T, 2) = ({T}, 2), got {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError("w_interval must have finite endpoints")
    if np.any(arr[:, 0] > arr[:, 1]):
        raise ValueError("w_interval must satisfy w_lo <= w_hi")
    return arr


def eval_eta(eta: Callable[[float], float], x: float) -> float:
    """η(x) as a float, raising ValueError when η returns NaN (η must be defined on all of ℝ).

    Examples
    --------
    >>> eval_eta(lambda x: x ** 3, 2)
    8.0
    """
    x = float(x)
    value = eta(x)
    # Called at every step: a float is taken as it is, anything else checked naming the call.
    value = float(value) if type(value) in _FLOATS else real_number(value, f"eta({x!r})")
    if value != value:
        raise ValueError(f"eta({x!r}) returned NaN; eta must be defined on all of R")
    return value


def as_interval(value: Any, name: str, allow_inf: bool) -> tuple[float, float]:
    """``value`` as a pair (lo, hi) of floats with lo ≤ hi, or an error naming ``name``.

    Parameters
    ----------
    value : array_like, shape (2,)
    name : str
        The argument's name, for the error message.
    allow_inf : bool
        Whether infinite endpoints are accepted (NaN never is).

    Raises
    ------
    TypeError, ValueError
        When ``value`` is not a pair of numbers, or has NaN, forbidden infinities or lo > hi.

    Examples
    --------
    >>> as_interval([-1, 2], "w", allow_inf=False)
    (-1.0, 2.0)
    """
    if type(value) is tuple and len(value) == 2 and type(value[0]) in _FLOATS and type(value[1]) in _FLOATS:
        # A callback's pair at every step: returned when every check below passes (NaN fails lo <= hi),
        # else checked below for the message.
        lo, hi = float(value[0]), float(value[1])
        if lo <= hi and (allow_inf or (-np.inf < lo and hi < np.inf)):
            return lo, hi
    arr = real_array(value, name, "a pair of numbers (lo, hi)").reshape(-1)
    if arr.shape != (2,):
        raise ValueError(f"{name} must be a pair (lo, hi) of shape (2,), got shape {np.shape(value)}")
    if np.isnan(arr).any() or (not allow_inf and np.isinf(arr).any()):
        raise ValueError(f"{name} must have {'non-NaN' if allow_inf else 'finite'} endpoints, got {arr}")
    if arr[0] > arr[1]:
        raise ValueError(f"{name} must satisfy lo <= hi, got {arr}")
    return float(arr[0]), float(arr[1])
