"""setsmooth: set-membership filtering and smoothing with sets as CVXPY-constrained variables."""

from .sets import (Box, CartesianProduct, ConstrainedZonotope, ConvexSet, Ellipsoid, EmptySet,
                   GeneralizedIntersection, HPolytope, Intersection, LinearMap, MinkowskiSum, Reals,
                   Zonotope)
from .sets import (CORA_COMBASTEL, CORA_GIRARD, Combastel, DropDependentConstraints, DropZeros,
                   EliminateConstraints, Girard, IntervalHull, MergeParallelGenerators, ReductionMethod,
                   Rescale, reduce)
from . import montecarlo, paper_examples
from .filters import KalmanResult, classical_filter, interval_filter, kalman_filter, rts_smoother
from .intervals import IntervalEstimates
from .smoothers import interval_smoother, optimal_smoother
from .solvers import SolverError
from .systems import LinearSystem, NonlinearSystem, simulate
from .trajectories import filtering_map, trajectory_set

__version__ = "0.1.0"

__all__ = [
    "ConvexSet", "Box", "Zonotope", "ConstrainedZonotope", "HPolytope", "Ellipsoid", "EmptySet",
    "Reals", "LinearMap", "MinkowskiSum", "Intersection", "GeneralizedIntersection",
    "CartesianProduct", "SolverError", "LinearSystem", "NonlinearSystem", "simulate",
    "classical_filter", "optimal_smoother", "trajectory_set", "filtering_map", "interval_filter",
    "interval_smoother",
    "IntervalEstimates", "kalman_filter", "rts_smoother", "KalmanResult", "montecarlo", "paper_examples",
    "reduce", "ReductionMethod", "DropZeros", "DropDependentConstraints", "MergeParallelGenerators",
    "Rescale", "EliminateConstraints", "Girard", "Combastel", "IntervalHull", "CORA_GIRARD",
    "CORA_COMBASTEL",
]
