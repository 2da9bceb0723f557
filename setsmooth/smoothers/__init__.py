"""Set-membership smoothers: the optimal linear smoother (recursion or trajectory form) and the
interval smoother for scalar monotone systems. The trajectory set they share lives in
`setsmooth.trajectories`."""

from .linear import optimal_smoother, smooth, smoothing_step
from .nonlinear import interval_smoother

__all__ = ["optimal_smoother", "smooth", "smoothing_step", "interval_smoother"]
