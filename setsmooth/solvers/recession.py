"""Which objectives grow without bound on a factor set: the recession program.

The recession cone of {ξ : Aξ = b, |ξ| ≤ h} is {ξ : Aξ = 0, ξ_j = 0 where h_j < ∞}, so only the free
factors matter. On the presolved program an objective ĝ is unbounded on a non-empty factor set
exactly when the gain

    max{ĝ_Fᵀη : Â_F η = 0, |η| ≤ 1} = min_λ ‖ĝ_F − Â_Fᵀλ‖₁

is positive, that is when no multiplier cancels the reduced cost on the free factors. This program is
feasible (η = 0) and bounded, so it is decided reliably, unlike the dual infeasibility of a support LP.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .clarabel_lp import SolverError, solve_lp
from .highs import simplex_box_equalities
from .presolved import Presolved

__all__ = ["unbounded_objectives", "STACK_MAX_VARIABLES"]

#: The recession programs stack their objectives into one LP while it has at most this many
#: variables, and go one objective at a time beyond.
STACK_MAX_VARIABLES = 3000


def _gains(gF: np.ndarray, AF: sp.csc_matrix, context: str) -> np.ndarray:
    """The gains of the rows of ``gF`` (stacked into one LP), by Clarabel, else HiGHS one by one."""
    w, nf = gF.shape
    m = AF.shape[0]
    eye = sp.identity(w, format="csc")
    M = sp.vstack([sp.kron(eye, AF), sp.identity(w * nf), -sp.identity(w * nf)], format="csc")
    rhs = np.concatenate([np.zeros(w * m), np.ones(2 * w * nf)])
    sol = solve_lp(-gF.reshape(-1), M, rhs, w * m, 2 * w * nf, context, refine=True,
                   kind="recession")
    if sol.status == "optimal":
        return np.einsum("ij,ij->i", gF, sol.x.reshape(w, nf))
    # Feasible (η = 0) and bounded: the simplex method settles it where the interior-point method
    # may stop 'inaccurate' on a thin set.
    gains = np.empty(w)
    for i in range(w):
        status, eta = simplex_box_equalities(-gF[i], AF)
        if status != "optimal":
            raise SolverError(sol.status, context, kind="recession")
        gains[i] = float(gF[i] @ eta)
    return gains


def unbounded_objectives(pre: Presolved, g: np.ndarray, context: str,
                         magnitude: np.ndarray | None = None) -> np.ndarray:
    """Which objectives (rows of ``g``, shape (k, ng), original factors) are unbounded on ``pre``.

    Gains above ``REDUCED_COST_TOL·‖ĝ‖∞`` count as positive (the presolve made the free columns
    unit-scaled, so this is scale-free), or, when the ``magnitude`` (shape of ``g``) of the
    computation that produced g is given, above ``REDUCED_COST_TOL·max(1, ‖S·magnitude‖∞)``.
    """
    free = np.flatnonzero(~pre.bounded)
    ghat = pre.objective(g)
    k, nf = ghat.shape[0], free.size
    if nf == 0:
        return np.zeros(k, dtype=bool)
    scale = np.abs(ghat if magnitude is None else pre.objective(magnitude)).max(axis=1, initial=0.0)
    if magnitude is not None:  # absolute floor: a direction of norm 1e-16 sees no lineality
        scale = np.maximum(scale, 1.0)
    gF = ghat[:, free] / np.where(scale > 0, scale, 1.0)[:, None]
    AF = pre.A[:, free]
    width = max(k, 1) if k * nf <= STACK_MAX_VARIABLES else 1
    gains = np.concatenate([_gains(gF[start:start + width], AF, context)
                            for start in range(0, k, width)]) if k else np.zeros(0)
    return gains > tol.REDUCED_COST_TOL
