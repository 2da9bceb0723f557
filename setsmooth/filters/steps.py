"""The classical filter's two steps, as set algebra (stability paper Algorithm 1):

    prior_k     = A_{k-1} posterior_{k-1} ⊕ E_{k-1} W ⊕ {B_{k-1} u_{k-1}}   stability (3), CZ form (20)
    posterior_k = { x ∈ prior_k : C_k x ∈ y_k ⊕ F_k(−V) }                   stability (4), CZ form (21)

`classical_filter` loops over them; the OIT filters run them on their windows, and the model-invalidation
report (`setsmooth.filters.consistency`) predicts the output set a measurement missed with them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_vector, check_system, given_instead_of_set
from ..sets.algebra import generalized_intersection, linear_map, minkowski_sum, translate
from ..sets.base import ConvexSet

__all__ = ["predict", "update"]


def predict(system, k: int, posterior: ConvexSet) -> ConvexSet:
    """⟦x_{k+1} | y_{0:k}⟧ = A_k ⟦x_k | y_{0:k}⟧ ⊕ E_k W ⊕ {B_k u_k} (stability (3), CZ form (20)).

    Parameters
    ----------
    system : LinearSystem
    k : int
        Time step of ``posterior``.
    posterior : ConvexSet
        ⟦x_k | y_{0:k}⟧, of dimension n.

    Returns
    -------
    ConvexSet
        The prior ⟦x_{k+1} | y_{0:k}⟧; E_k W is the system's cached image when E is constant, and a
        zero B_k u_k adds no translation.

    Raises
    ------
    ValueError
        When ``posterior`` is not a set of dimension n.
    """
    _check_state_set(posterior, "posterior", check_system(system).n)
    return _predict(system, k, posterior)


def update(system, k: int, prior: ConvexSet, y: Any) -> ConvexSet:
    """⟦x_k | y_{0:k}⟧ = prior ∩_{C_k} (y_k − D_k u_k ⊕ F_k(−V)) (stability (4), CZ form (21)).

    Parameters
    ----------
    system : LinearSystem
    k : int
        Time step of the measurement.
    prior : ConvexSet
        ⟦x_k | y_{0:k−1}⟧, of dimension n.
    y : array_like, shape (m,)
        The measurement y_k (as measured: the feedthrough D_k u_k is subtracted here).

    Returns
    -------
    ConvexSet
        The posterior; F_k(−V) is the system's cached image when F is constant.

    Raises
    ------
    ValueError, TypeError
        When ``prior`` is not a set of dimension n, or ``y`` is not a finite real vector of length m.
    """
    _check_state_set(prior, "prior", check_system(system).n)
    y = as_vector(y, "y", system.m)
    return _update(system, k, prior, y - system.feedthrough_term(k) if system.has_feedthrough else y)


# The loop's steps trust their operands: the matrices were validated by the LinearSystem (a callable's
# value at each call), the sets and measurements by the public door above, so they go straight to the
# set algebra instead of through the operators, which would validate every matrix again every step.
def _predict(system, k: int, posterior: ConvexSet) -> ConvexSet:
    prior = minkowski_sum(linear_map(system.A_at(k), posterior), system.process_noise_image(k))
    u = system.nonzero_input(k)
    return prior if u is None else translate(prior, u)


def _update(system, k: int, prior: ConvexSet, y: np.ndarray) -> ConvexSet:
    return generalized_intersection(prior, system.C_at(k), translate(system.measurement_noise_image(k), y))


def _check_state_set(S: Any, name: str, n: int) -> None:
    """A ValueError naming ``name``, n and what was given, unless S is a `ConvexSet` of dimension n."""
    if not isinstance(S, ConvexSet):
        raise ValueError(f"{name} must be a ConvexSet of dimension n = {n}, {given_instead_of_set(S, name)}")
    if S.dim != n:
        raise ValueError(f"{name} must be a ConvexSet of dimension n = {n}, got one of dimension {S.dim}")
