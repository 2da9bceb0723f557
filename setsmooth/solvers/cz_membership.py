"""Membership in a constrained zonotope: the distance program on its presolved factor set.

`contains` decides p ∈ Z ⊕ [−m, m] by min{t : |Gξ + c − p| ≤ t, t ≥ m, Aξ = b, |ξ| ≤ h}, posed in
the presolved program's deviation coordinates and, for free factors, in units of their rigorous
bound (`free_units`), so every variable of the program is O(1) in the set's own metric.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from .. import tolerances as tol
from .backends import box_rows
from .clarabel_lp import _ALMOST_SOLVED, SolverError, solve_lp

__all__ = ["contains", "free_units"]


def free_units(factors, pre) -> np.ndarray:
    """Column units of the presolved program's factors for the membership program: 1 on bounded
    factors (|η_B| ≤ 1), and β / s_j on free ones, β ≥ ‖ξ_F‖∞ the factor set's rigorous bound
    (`FactorConstraints.free_bound`, when known or cheap), so every factor of the program is
    O(1) in the set's own metric.

    The presolve gives a free factor the units of its tightest row. On a thin set (a state
    pinned to 1e-6 by a measurement of noise 1e-6, the others only by a prior box of size 5)
    that put the free factors at |η_F| ~ 1e7, and Clarabel returned 'optimal' with distance 0.93
    (in the set's units) for a member; in units of β it returns the margin itself.
    """
    units = np.ones(pre.A.shape[1])
    if pre.bounded.all():
        return units
    beta = factors.cheap_free_bound()
    if beta is not None and np.isfinite(beta) and beta > 0:
        free = ~pre.bounded
        units[free] = beta / pre.col_scale[free]
    return units

def contains(program, p: np.ndarray, margin: float) -> bool:
    """Whether some ξ with Aξ = b, |ξ| ≤ h has ‖Gξ + c − p‖∞ ≤ margin, for the CZ of ``program``
    (a `CZProgram`).

    Decided by the distance program min{t : |Gξ + c − p| ≤ t, t ≥ margin, Aξ = b, |ξ| ≤ h},
    which is feasible whenever Z is and bounded below, rather than by the feasibility of
    ``t = margin``: an interior-point method certifies infeasibility less reliably
    (AlmostPrimalInfeasible) than it solves. The explicit row t ≥ margin matters: without it a
    member (distance 0) leaves no slack and Clarabel often stops at AlmostSolved. The optimum is
    compared with ``margin`` up to the solver's accuracy on the program's data (the point, the
    centre and the set's extent).

    A program Clarabel does not settle on the stored rows is decided as the supports decide one
    (`maximization`): by the emptiness verdict, and on a non-empty set on the rows relaxed to
    |Âη − b̂| ≤ ρ (`FactorConstraints.relaxation`), which have an interior (Clarabel, then the
    simplex method). So membership agrees with the hulls, which are then the relaxed set's
    (reliability case 069 at offset 1e6: a posterior pinned to a point by rounded 1e6-sized data,
    whose hull held the true state while the simplex method on the stored rows called it outside
    and on the next posterior stalled).
    """
    factors = program.factors
    pre = factors.presolved
    if pre.empty:
        return False
    units = free_units(factors, pre)
    M, rhs, _ = box_rows(pre)  # the presolved factor set: rows Âη = b̂, |η_B| ≤ 1
    M = sp.csc_matrix(M @ sp.diags(units))
    G = program.G[:, pre.cols]
    scale = pre.col_scale * units
    G = sp.csc_matrix(G @ sp.diags(scale)) if sp.issparse(G) else G * scale
    # The program's η is the deviation from the presolve's nominal point (`Presolved.shift`).
    centre = program.c if pre.shift is None else program.c + np.asarray(
        program.G[:, pre.cols] @ (pre.shift * pre.col_scale)).reshape(-1)
    # The optimum is accurate to the solver's tolerance relative to the data of its rows, which
    # include the set's extent |G|·1 (η in the unit box): a blown-up set (generators ~1e15, as a
    # reduced filter with few outputs can produce) cannot resolve distances below that, and
    # calling a member a non-member there would be a silent wrong answer.
    extent = abs(G).sum(axis=1).max() if sp.issparse(G) else np.abs(G).sum(axis=1).max(initial=0.0)
    accuracy = tol.scaled(tol.SOLVER_TOL, max(np.abs(p).max(initial=0.0),
                                              np.abs(program.c).max(initial=0.0), float(extent)))
    program_rows = (M, rhs, pre.A.shape[0], G, centre - p)
    status, t = _distance(program_rows, margin, None)
    if status != "optimal":
        if factors.is_empty():
            return False
        status, t = _distance(program_rows, margin, factors.relaxation(pre))
    if status != "optimal":
        raise SolverError(_ALMOST_SOLVED if status == "inaccurate" else "NumericalError",
                          "deciding membership in a constrained zonotope", kind="membership")
    return bool(t <= margin + accuracy)


def _distance(program_rows: tuple, margin: float, rho: float | None) -> tuple[str, float]:
    """(status, t*) of the distance program, on the rows exact (``rho`` None: Clarabel) or
    relaxed to |Âη − b̂| ≤ ρ (Clarabel, then the simplex method): 'optimal', 'infeasible', or
    another status when they do not settle it. ``program_rows`` = (M, rhs, m, G, c − p): the `box_rows` of the
    presolved factor set (m equality rows first), the generators and the centre's offset from p."""
    M, rhs, m, G, offset = program_rows
    n, nvar = G.shape[0], M.shape[1]
    ones = sp.csc_matrix(np.ones((n, 1)))
    t_row = sp.csc_matrix(([-1.0], ([0], [nvar])), shape=(1, nvar + 1))
    # Equalities first (Âη = b̂; relaxed: ±(Âη − b̂) ≤ ρ), then the bound rows,
    # ±(Gη + c − p) ≤ t and −t ≤ −margin.
    eq = sp.hstack([M[:m], sp.csc_matrix((m, 1))])
    if rho is None:
        head, head_rhs, neq = eq, rhs[:m], m
    else:
        head, head_rhs, neq = sp.vstack([eq, -eq]), np.concatenate([rhs[:m] + rho, rho - rhs[:m]]), 0
    rows = sp.vstack([head, sp.hstack([M[m:], sp.csc_matrix((M.shape[0] - m, 1))]),
                      sp.hstack([G, -ones]), sp.hstack([-G, -ones]), t_row], format="csc")
    r = np.concatenate([head_rhs, rhs[m:], -offset, offset, [-margin]])
    q = np.zeros(nvar + 1)
    q[-1] = 1.0
    # With iterative refinement: without it, 2 in 1,500 members of random CZs with free factors
    # came out as non-members or AlmostSolved (t* a few 1e-9 above the margin).
    context = "deciding membership in a constrained zonotope"
    try:
        sol = solve_lp(q, rows, r, neq, rows.shape[0] - neq, context, refine=True, kind="membership")
        status, t = sol.status, float(sol.x[-1])
    except SolverError:
        status, t = "stalled", np.nan
    if status in ("optimal", "infeasible") or rho is None:
        return status, t
    # The simplex method settles what the interior-point method could not.
    res = linprog(q, A_ub=rows[neq:], b_ub=r[neq:], A_eq=rows[:neq] if neq else None,
                  b_eq=r[:neq] if neq else None, bounds=[(None, None)] * (nvar + 1), method="highs")
    # SciPy reports HiGHS's refusal of the data (entries beyond 1e15: "Model error") with the
    # infeasible status too; only a verdict of infeasibility means empty.
    if res.status == 2 and "infeasible" in res.message.lower():
        return "infeasible", np.nan
    if res.status == 0:
        return "optimal", float(res.x[-1])
    return status, np.nan
