"""Set algebra with widening: each operation returns the most specific type closed under it.

Order of preference, for every binary operation:

1. the empty set absorbs (an operation with an empty operand is empty);
2. a closed form one of the operands knows for the other (Box + Box is a Box, Zonotope + Box a
   Zonotope, HPolytope ∩ Box an HPolytope, ...), through the hooks declared on `ConvexSet`
   (``_closed_*``), called directly. Both operands are asked for the commutative operations and for
   the generalized intersection (Y's ``_closed_reflected_generalized_intersection``), so the widened
   type does not depend on the order: Box ∩_R HPolytope is an HPolytope like HPolytope ∩_R Box (and
   the product asks the right operand too: Box × HPolytope is an HPolytope like HPolytope × Box);
3. the constrained-zonotope closed form, when both operands flatten exactly to CZs (smoothing paper
   (35)–(37)); Box ∩ Zonotope is a CZ;
4. otherwise a lazy set (`setsmooth.sets.lazy`), exact and queried through CVXPY.

Operands are validated by the public operators in `ConvexSet`; these functions trust them.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .base import ConvexSet
from .empty import EmptySet
from .lazy import CartesianProduct, GeneralizedIntersection, Intersection, LinearMap, MinkowskiSum


def linear_map(M, S: ConvexSet) -> ConvexSet:
    """{M s : s ∈ S} (smoothing paper (35) for CZs)."""
    if isinstance(S, EmptySet):
        return EmptySet(M.shape[0])
    result = S._closed_linear_map(M)
    if result is not NotImplemented:
        return result
    cz = S._flat_cz
    if cz is not None:
        return cz._linear_map(M)
    if isinstance(S, LinearMap):
        return LinearMap(M @ S.M, S.S, np.asarray(M @ S.offset).reshape(-1))
    return LinearMap(M, S)


def translate(S: ConvexSet, v: np.ndarray) -> ConvexSet:
    """S + v."""
    if isinstance(S, EmptySet):
        return S
    result = S._closed_translate(v)
    if result is not NotImplemented:
        return result
    if isinstance(S, LinearMap):
        return LinearMap(S.M, S.S, S.offset + v)
    return LinearMap(sp.identity(S.dim, format="csc"), S, v)


def minkowski_sum(S: ConvexSet, T: ConvexSet) -> ConvexSet:
    """S ⊕ T (smoothing paper (36) for CZs)."""
    if isinstance(S, EmptySet) or isinstance(T, EmptySet):
        return EmptySet(S.dim)
    result = S._closed_sum(T)
    if result is NotImplemented:
        result = T._closed_sum(S)
    if result is not NotImplemented:
        return result
    a, b = S._flat_cz, T._flat_cz
    if a is not None and b is not None:
        return a._minkowski_sum(b)
    return MinkowskiSum(S, T)


def intersection(S: ConvexSet, T: ConvexSet) -> ConvexSet:
    """S ∩ T (the generalized intersection with R = I for CZs)."""
    if isinstance(S, EmptySet) or isinstance(T, EmptySet):
        return EmptySet(S.dim)
    result = S._closed_intersection(T)
    if result is NotImplemented:
        result = T._closed_intersection(S)
    if result is not NotImplemented:
        return result
    a, b = S._flat_cz, T._flat_cz
    if a is not None and b is not None:
        return a._generalized_intersection(np.eye(S.dim), b)
    return Intersection(S, T)


def generalized_intersection(S: ConvexSet, R, Y: ConvexSet) -> ConvexSet:
    """{s ∈ S : R s ∈ Y} (smoothing paper (37), stability (21))."""
    if isinstance(S, EmptySet) or isinstance(Y, EmptySet):
        return EmptySet(S.dim)
    result = S._closed_generalized_intersection(R, Y)
    if result is NotImplemented:  # the closed form Y knows: widening does not depend on the order
        result = Y._closed_reflected_generalized_intersection(S, R)
    if result is not NotImplemented:
        return result
    a, b = S._flat_cz, Y._flat_cz
    if a is not None and b is not None:
        return a._generalized_intersection(R, b)
    return GeneralizedIntersection(S, R, Y)


def cartesian_product(S: ConvexSet, T: ConvexSet) -> ConvexSet:
    """S × T."""
    if isinstance(S, EmptySet) or isinstance(T, EmptySet):
        return EmptySet(S.dim + T.dim)
    result = S._closed_product(T)
    if result is NotImplemented:  # the closed form T knows: Box × HPolytope is an HPolytope too
        result = T._closed_reflected_product(S)
    if result is not NotImplemented:
        return result
    a, b = S._flat_cz, T._flat_cz
    if a is not None and b is not None:
        return a._cartesian_product(b)
    return CartesianProduct(S, T)
