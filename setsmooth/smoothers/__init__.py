"""Set-membership smoothers."""

from .linear import optimal_smoother, smooth, smoothing_step
from .nonlinear import interval_smoother
from .trajectory import trajectory_set

__all__ = ["optimal_smoother", "smooth", "smoothing_step", "trajectory_set", "interval_smoother"]
