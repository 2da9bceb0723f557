"""Set-membership filters and their stochastic baselines."""

from .classical import classical_filter, predict, update
from .interval import interval_filter
from .kalman import KalmanResult, kalman_filter, rts_smoother

__all__ = ["classical_filter", "predict", "update", "interval_filter", "kalman_filter", "rts_smoother",
           "KalmanResult"]
