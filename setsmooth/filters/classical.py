"""The classical linear set-membership filter (stability paper Algorithm 1), as set algebra.

    prior_k     = A_{k-1} posterior_{k-1} ⊕ B_{k-1} W ⊕ {u_{k-1}}          stability (3)
    posterior_k = { x ∈ prior_k : C_k x ∈ y_k ⊕ D_k(−V) }                   stability (4)

Under unrelated noises this is the optimal SMF (rethinking paper Corollary 1; smoothing paper Lemma 3).
With constrained-zonotope inputs the set algebra produces exactly the CZs of stability (20)–(21); with
other representations the sets stay exact, as lazy sets.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_measurements
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet
from ..sets.reduction import apply_methods, as_methods


def classical_filter(system, X0: ConvexSet, ys: Any, *, reduce: Any = None,
                     detect_empty: bool = True) -> list[ConvexSet]:
    """Posterior ranges ⟦x_k | y_{0:k}⟧ for k = 0..T (stability paper Algorithm 1).

    With ``reduce`` it is a bounded filter: the reduction is applied to every posterior before the next
    prediction (CORA's reduced constrained-zonotope observer is Algorithm 1 plus this one line, e.g.
    ``reduce=ss.CORA_GIRARD``). The estimates are then **outer bounds** of the exact posteriors,
    ⟦x_k | y_{0:k}⟧ ⊆ posteriors[k], not the posteriors themselves; their complexity stays bounded.

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
        Initial prior range ⟦x_0⟧.
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T.
    reduce : ReductionMethod or sequence of ReductionMethod, optional
        Order reduction applied to every posterior (see `setsmooth.reduce`), e.g. ``ss.CORA_GIRARD``
        or ``(ss.Rescale('iter'), ss.EliminateConstraints(1), ss.Girard(1))``. None (default): the
        exact filter.
    detect_empty : bool
        Check each posterior for emptiness (one feasibility program per step) and return `EmptySet`
        from the first empty one on. With False the sets are returned as computed; an empty one is
        still empty (``is_empty()``), only not simplified.

    Returns
    -------
    list of ConvexSet
        ``posteriors[k]`` = ⟦x_k | y_{0:k}⟧, or a superset of it with ``reduce``. An empty posterior
        means the measurements are inconsistent with the model (ill-posedness is data, not an
        exception).
    """
    ys = as_measurements(ys, system.m)
    methods = None if reduce is None else as_methods(reduce, "reduce")
    if not isinstance(X0, ConvexSet) or X0.dim != system.n:
        raise ValueError(f"X0 must be a ConvexSet of dimension n = {system.n}")
    minus_V = -system.V
    posteriors: list[ConvexSet] = []
    prior = X0
    for k, y in enumerate(ys):
        if k > 0:
            prior = predict(system, k - 1, posteriors[-1])
        posterior = update(system, k, prior, y, minus_V)
        if methods is not None:
            posterior = apply_methods(posterior, methods)
        if detect_empty and not isinstance(posterior, EmptySet) and posterior.is_empty():
            posterior = EmptySet(system.n)
        posteriors.append(posterior)
    return posteriors


def predict(system, k: int, posterior: ConvexSet) -> ConvexSet:
    """⟦x_{k+1} | y_{0:k}⟧ = A_k ⟦x_k | y_{0:k}⟧ ⊕ B_k W ⊕ {u_k} (stability (3), CZ form (20))."""
    return system.A(k) @ posterior + system.B(k) @ system.W + system.input_term(k)


def update(system, k: int, prior: ConvexSet, y: np.ndarray, minus_V: ConvexSet | None = None) -> ConvexSet:
    """⟦x_k | y_{0:k}⟧ = prior ∩_{C_k} (y_k ⊕ D_k(−V)) (stability (4), CZ form (21))."""
    minus_V = -system.V if minus_V is None else minus_V
    return prior.intersect_preimage(system.C(k), system.D(k) @ minus_V + y)
