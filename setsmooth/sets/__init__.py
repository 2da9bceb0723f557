"""Convex sets as CVXPY-constrained variables, with closed forms where the representation has them."""

from .base import ConvexSet
from .chebyshev import ChebyshevBall
from .containment import Containment, is_subset
from .difference import pontryagin_difference
from .box import Box
from .constrained_zonotope import ConstrainedZonotope
from .polygon import Polygon
from .ellipsoid import Ellipsoid
from .empty import EmptySet
from .hpolytope import HPolytope
from .lazy import CartesianProduct, GeneralizedIntersection, Intersection, LinearMap, MinkowskiSum
from .reals import Reals
from .reduction import (CORA_COMBASTEL, CORA_GIRARD, Combastel, DropDependentConstraints, DropZeros,
                        EliminateConstraints, Girard, IntervalHull, MergeParallelGenerators,
                        ReductionMethod, Rescale, reduce)
from .vpolytope import VPolytope
from .zonotope import Zonotope

__all__ = [
    "ConvexSet", "Box", "Zonotope", "ConstrainedZonotope", "HPolytope", "Ellipsoid", "EmptySet",
    "Reals", "LinearMap", "MinkowskiSum", "Intersection", "GeneralizedIntersection",
    "CartesianProduct", "reduce", "ReductionMethod", "DropZeros", "DropDependentConstraints",
    "MergeParallelGenerators", "Rescale", "EliminateConstraints", "Girard", "Combastel", "IntervalHull",
    "CORA_GIRARD", "CORA_COMBASTEL", "VPolytope", "Containment", "is_subset", "pontryagin_difference",
    "ChebyshevBall", "Polygon",
]
