"""Convex sets as CVXPY-constrained variables, with closed forms where the representation has them."""

from .base import ConvexSet
from .box import Box
from .constrained_zonotope import ConstrainedZonotope
from .ellipsoid import Ellipsoid
from .empty import EmptySet
from .hpolytope import HPolytope
from .lazy import CartesianProduct, GeneralizedIntersection, Intersection, LinearMap, MinkowskiSum
from .reals import Reals
from .zonotope import Zonotope

__all__ = [
    "ConvexSet", "Box", "Zonotope", "ConstrainedZonotope", "HPolytope", "Ellipsoid", "EmptySet",
    "Reals", "LinearMap", "MinkowskiSum", "Intersection", "GeneralizedIntersection",
    "CartesianProduct",
]
