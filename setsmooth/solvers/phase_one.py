"""The elastic phase-one program of a factor set: its emptiness, and the relaxed support programs.

Emptiness (`decide_empty`): a feasibility solve on the kept Clarabel instance whose point satisfies
the rows to ``EMPTINESS_TOL`` proves non-emptiness (the common case, one solve). Anything else is
decided by the elastic phase-one program

    min{t : |Âη − b̂| ≤ t, |η_B| ≤ 1},

which is feasible and bounded whatever the data, so it settles even on flat or nearly empty sets: the
set is empty iff t* > ``EMPTINESS_TOL`` in the equilibrated units (every presolved row has unit
∞-norm and every bounded factor unit bound; thresholds scale with `Presolved.data_scale`). Clarabel
solves it on the kept program, refined, then on the fully presolved program if that differs; the
simplex method decides it where none settles (data consistent only to their rounding, e.g. states
of 1e28 on a strongly unstable system).

`relaxed` maximizes over {η : |Âη − b̂| ≤ ρ, |η_B| ≤ 1} with ρ the phase-one residual plus
``EMPTINESS_TOL``: the outer value for a set the phase-one program calls non-empty whose support LP
no backend settles or every backend calls infeasible (rows inconsistent by rounding).
"""

from __future__ import annotations

import clarabel
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from . import clarabel_lp
from .backends import box_rows, clarabel_kept
from .clarabel_lp import SolverError, _zero_cost
from .highs import simplex_inequalities
from .presolved import Presolved

__all__ = ["decide_empty", "relaxed_point"]


def _residual(pre: Presolved, eta: np.ndarray) -> float:
    """max |Âη − b̂| at η with its bounded factors clipped into [−1, 1]: attained by a point."""
    eta = eta.copy()
    eta[pre.bounded] = np.clip(eta[pre.bounded], -1.0, 1.0)
    return float(np.abs(pre.A @ eta - pre.b).max(initial=0.0))


def _elastic(pre: Presolved) -> tuple[sp.csc_matrix, np.ndarray, np.ndarray]:
    """(rows, r, cost) of the phase-one program in the variables (η, t): rows·(η, t) ≤ r."""
    m, p = pre.A.shape
    M, rhs, _ = box_rows(pre)
    ones = sp.csc_matrix(np.ones((m, 1)))
    t_row = sp.csc_matrix(([-1.0], ([0], [p])), shape=(1, p + 1))
    rows = sp.vstack([sp.hstack([pre.A, -ones]), sp.hstack([-pre.A, -ones]),
                      sp.hstack([M[m:], sp.csc_matrix((M.shape[0] - m, 1))]), t_row], format="csc")
    r = np.concatenate([pre.b, -pre.b, rhs[m:], [0.0]])
    cost = np.zeros(p + 1)
    cost[-1] = 1.0
    return rows, r, cost


def _verdict(pre: Presolved, x: np.ndarray) -> tuple[bool, float]:
    """(empty, residual) from a phase-one solution (η, t)."""
    limit = tol.EMPTINESS_TOL * pre.data_scale
    upper = _residual(pre, x[:-1])
    return bool(x[-1] > limit and upper > limit), min(float(x[-1]), upper)


def _clarabel_phase_one(pre: Presolved, refine: bool) -> tuple[str, tuple[bool, float] | None]:
    """(Clarabel's status name, the verdict or None when the solve does not settle it)."""
    rows, r, cost = _elastic(pre)
    solver = clarabel.DefaultSolver(_zero_cost(cost.size), cost, rows, r,
                                    [clarabel.NonnegativeConeT(rows.shape[0])],
                                    clarabel_lp.settings(refine=refine))
    sol = solver.solve()
    name = str(sol.status).split(".")[-1]
    x = np.asarray(sol.x)
    limit = tol.EMPTINESS_TOL * pre.data_scale
    settled = name == "Solved" or (name == "AlmostSolved" and (
        _residual(pre, x[:-1]) <= limit or x[-1] > 10 * limit))
    return name, (_verdict(pre, x) if settled else None)


def _feasible_by_kept_instance(pre: Presolved) -> float | None:
    """The rows' residual at the kept instance's feasibility point when it proves non-emptiness
    (within ``EMPTINESS_TOL``), else None."""
    answer = clarabel_kept(pre, np.zeros(pre.A.shape[1]))
    if answer.status != "solved":
        return None
    upper = _residual(pre, answer.eta)
    return upper if upper <= tol.EMPTINESS_TOL * pre.data_scale else None


def decide_empty(factors) -> tuple[bool, float | None]:
    """(whether the factor set of ``factors`` (`FactorConstraints`) is empty, the phase-one
    residual, None when not computed)."""
    if factors.nc == 0:
        return False, 0.0  # ξ = 0 is feasible since h ≥ 0
    first = factors.presolved
    if first.empty:
        return True, None
    if first.A.shape[0] and first.A.shape[1]:
        upper = _feasible_by_kept_instance(first)
        if upper is not None:
            return False, upper
    programs = [(first, False), (first, True)]
    full = factors.fully_presolved_if_new(first)
    if full is not None:
        programs.append((full, True))
    last, pre = "Unknown", first
    for pre, refine in programs:
        if pre.empty:
            return True, None
        if pre.A.shape[0] == 0:
            return False, 0.0
        last, verdict = _clarabel_phase_one(pre, refine)
        if verdict is not None:
            return verdict
    rows, r, cost = _elastic(pre)
    status, x, _ = simplex_inequalities(cost, rows, r)
    if status == "optimal":
        return _verdict(pre, x)
    raise SolverError(last, "deciding emptiness of a constrained zonotope", kind="emptiness")


def relaxed_point(pre: Presolved, q: np.ndarray, rho: float) -> tuple[np.ndarray, np.ndarray]:
    """(η, λ̂) of min qᵀη over {η : |Âη − b̂| ≤ ρ, |η_B| ≤ 1} (feasible for ρ at least the
    phase-one residual, and bounded), by Clarabel, else the simplex method; λ̂ = z⁺ − z⁻ of the two
    row blocks cancels the objective as Âᵀλ̂ would."""
    m, p = pre.A.shape
    M, rhs, _ = box_rows(pre)
    rows = sp.vstack([pre.A, -pre.A, M[m:]], format="csc")
    r = np.concatenate([pre.b + rho, rho - pre.b, rhs[m:]])
    solver = clarabel.DefaultSolver(_zero_cost(p), q, rows, r,
                                    [clarabel.NonnegativeConeT(rows.shape[0])],
                                    clarabel_lp.settings(refine=True))
    sol = solver.solve()
    name = str(sol.status).split(".")[-1]
    x, z = np.asarray(sol.x), np.asarray(sol.z)
    if name != "Solved":
        # The simplex method settles what the interior-point method did not (a set the
        # measurements pin to a sliver).
        fallback, x, z = simplex_inequalities(q, rows, r)
        if fallback != "optimal":
            raise SolverError(name, "computing a support function of a nearly empty constrained "
                              "zonotope", kind="support")
    return x, z[:m] - z[m:2 * m]
