"""The point of a constrained zonotope closest to a reference: one Clarabel program on the factor set.

The LSU paper's Method 2 projects a reference point onto the current CZ at every step. On the fast
path that is one program over the factor set {ξ : Aξ = b, |ξ| ≤ h} of Z(G, c, A, b, h), built from
the CZ's matrices, with e = Gξ + c − r the error to the reference r:

* ∞-norm (LP):  minimize t        subject to  −t ≤ Gξ + c − r ≤ t
* 1-norm (LP):  minimize Σᵢ uᵢ    subject to  −u ≤ Gξ + c − r ≤ u
* 2-norm (QP):  minimize ½‖e‖²    subject to  e = Gξ + c − r (strongly convex in the point, so the
  point itself, not only the distance, is accurate to the solver's tolerance)

each with Aξ = b and the finite bounds |ξ_j| ≤ h_j. It is solved by `conic.ConicForm`: equilibrated
(a CZ written with rows or factors at 1e±12 gives the same point), verified (primal feasibility,
dual feasibility and duality gap in the scaled data, else ``SolverError('UnverifiedSolution')``),
with Clarabel's status names and, for an empty CZ, the elastic emptiness verdict (no point).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from .clarabel_lp import SolverError
from .conic import ConicForm

__all__ = ["FAST_NORMS", "closest_point"]

#: The norms of the fast path; other p-norms go through the generic CVXPY path.
FAST_NORMS = (1, 2, np.inf)

_CONTEXT = "finding the point of a constrained zonotope closest to a reference"


def fast_norm(norm) -> float | None:
    """``norm`` as one of `FAST_NORMS` (accepting 'inf'), or None when the fast path has no program."""
    if isinstance(norm, str):
        return np.inf if norm.lower() == "inf" else None
    if isinstance(norm, bool):
        return None
    try:
        value = float(norm)
    except (TypeError, ValueError):
        return None
    return value if value in FAST_NORMS else None


def closest_point(G, c: np.ndarray, A, b: np.ndarray, h: np.ndarray, reference: np.ndarray,
                  norm: float) -> np.ndarray | None:
    """The point of Z(G, c, A, b, h) closest to ``reference`` in the 1-, 2- or ∞-norm.

    Parameters
    ----------
    G : ndarray or sparse matrix, shape (n, ng)
    c : ndarray, shape (n,)
    A : ndarray or sparse matrix, shape (nc, ng)
    b : ndarray, shape (nc,)
    h : ndarray, shape (ng,)
        Factor bounds in [0, ∞]. Arguments are trusted (validated by the caller).
    reference : ndarray, shape (n,)
    norm : {1, 2, inf}

    Returns
    -------
    ndarray, shape (n,), or None
        A closest point (the unique one for the 2-norm); None when Z is empty.

    Raises
    ------
    SolverError
        When the program ends in a status with no trustworthy answer (Clarabel's name, kind
        'closest point'), or its answer fails verification ('UnverifiedSolution').
    """
    G = sp.csc_matrix(G)
    n, ng = G.shape
    nc = A.shape[0]
    finite = np.flatnonzero(np.isfinite(h))
    E = sp.csc_matrix((np.ones(finite.size), (np.arange(finite.size), finite)),
                      shape=(finite.size, ng))
    Aeq, bounds = sp.csc_matrix(A), sp.vstack([E, -E], format="csc")  # ±ξ_j ≤ h_j, h_j finite
    rhs = np.concatenate([b, h[finite], h[finite]])
    nb = bounds.shape[0]
    r = np.asarray(reference, dtype=float) - c
    P = None
    if norm == 2:  # variables (ξ, e): Gξ − e = r, minimize ½‖e‖²
        A = sp.vstack([sp.hstack([Aeq, sp.csc_matrix((nc, n))]),
                       sp.hstack([G, -sp.identity(n)]),
                       sp.hstack([bounds, sp.csc_matrix((nb, n))])], format="csc")
        b = np.concatenate([rhs[:nc], r, rhs[nc:]])
        dims = SimpleNamespace(zero=nc + n, nonneg=nb, soc=[], psd=[], exp=0, p3d=[], pnd=[])
        q = np.zeros(ng + n)
        P = sp.block_diag([sp.csc_matrix((ng, ng)), sp.identity(n)], format="csc")
    else:  # variables (ξ, s) with s = t (one) for ∞, u (n) for 1: ±(Gξ − r) ≤ s
        k = 1 if norm == np.inf else n
        S = sp.csc_matrix(np.ones((n, 1))) if k == 1 else sp.identity(n, format="csc")
        A = sp.vstack([sp.hstack([Aeq, sp.csc_matrix((nc, k))]),
                       sp.hstack([bounds, sp.csc_matrix((nb, k))]),
                       sp.hstack([G, -S]), sp.hstack([-G, -S])], format="csc")
        b = np.concatenate([rhs[:nc], rhs[nc:], r, -r])
        dims = SimpleNamespace(zero=nc, nonneg=nb + 2 * n, soc=[], psd=[], exp=0, p3d=[], pnd=[])
        q = np.concatenate([np.zeros(ng), np.ones(k)])
    form = ConicForm(A, b, dims, _CONTEXT, "closest point", P)
    sol = form.solve(q)
    if sol.status == "infeasible":
        return None
    if sol.status != "optimal":  # the distance is bounded below: 'unbounded' is the solver's error
        raise SolverError("DualInfeasible", f"{_CONTEXT}: a distance reported unbounded below",
                          kind="closest point")
    return np.asarray(G @ sol.z[:ng]).reshape(-1) + c
