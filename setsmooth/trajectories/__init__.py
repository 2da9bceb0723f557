"""Trajectory sets: all state trajectories consistent with the data, one floor below filters and smoothers.

`sparse_cz` builds the sparse trajectory CZ (`trajectory_set`, `filtering_map`); `generic_program` the
compiled program for sets without a CZ form (`TrajectorySet`, `FilteredState`); `free_factor_bound` the
bound on the free factors (the states) that certifies their support values; `posterior_views` the exact
filter's posteriors as views of one trajectory CZ; `recursion_certificates` the certification of the
recursion's sets against the model data; `nominal` the nominal trajectory the recursion runs about.
"""

from .generic_program import TrajectorySet
from .sparse_cz import filtering_map, trajectory_set

__all__ = ["trajectory_set", "filtering_map", "TrajectorySet"]
