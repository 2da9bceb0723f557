"""setsmooth: set-membership filtering and smoothing with sets as CVXPY-constrained variables."""

from .sets import (Box, CartesianProduct, ConstrainedZonotope, ConvexSet, Ellipsoid, EmptySet,
                   GeneralizedIntersection, HPolytope, Intersection, LinearMap, MinkowskiSum, Reals,
                   Zonotope)
from .solvers import SolverError

__version__ = "0.1.0"

__all__ = [
    "ConvexSet", "Box", "Zonotope", "ConstrainedZonotope", "HPolytope", "Ellipsoid", "EmptySet",
    "Reals", "LinearMap", "MinkowskiSum", "Intersection", "GeneralizedIntersection",
    "CartesianProduct", "SolverError",
]
