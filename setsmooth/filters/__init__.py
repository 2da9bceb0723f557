"""Set-membership filters and their stochastic baselines."""

from .classical import classical_filter, predict, update

__all__ = ["classical_filter", "predict", "update"]
