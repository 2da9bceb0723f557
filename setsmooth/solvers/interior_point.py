"""HiGHS's interior-point method without crossover: the last fallback of a support program.

Every other fallback of `factor_set.FactorConstraints.maximize` ends in a simplex basis: HiGHS's
simplex rungs (`presolve.simplex`, `presolve.simplex_cold`) and the crossover that turns an
interior solution into a vertex. On the recursion smoother's nearly flat sets the optimal bases
are nearly singular, and all of them fail together. On the smoothed set k = 25 of reliability case
184 at noise 1e3 (1,308 rows, 1,726 factors), for 12 support directions solved from scratch: the
dual simplex method met a rank-deficient basis on all 12, the interior-point method's crossover
ended at an optimal vertex on 2, and without crossover all 12 passed the caller's independent
check (`Presolved.checked_gap`) with relative duality gaps of 1.7e-11 to 1.6e-10, in 0.6-0.8 s
each. The interior solution is not a vertex; the support value and the multipliers are what the
callers use, and the check judges them.
"""

from __future__ import annotations

import numpy as np

from .presolve import Presolved, _rung_iterations, rung_seconds
from .warm_simplex import factor_model, settled_point

__all__ = ["interior_point"]

#: HiGHS's ``ipm_optimality_tolerance`` here: two orders below ``tolerances.ACCURATE_GAP_TOL``, the
#: relative gap the caller's check accepts (HiGHS's default is 1e-8, that gap itself).
IPM_OPTIMALITY_TOLERANCE = 1e-10


def interior_point(pre: Presolved, q: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """min qᵀη subject to Âη = b̂ and |η_B| ≤ 1 by HiGHS's interior-point method from scratch.

    Returns
    -------
    (status name, η, λ̂)
        As `presolve.simplex`: 'AlmostSolved' for a point with a dual (HiGHS's 'Optimal', or its
        'Unknown' with a valid primal and dual solution; the caller checks either), else
        'PrimalInfeasible', 'DualInfeasible', 'MaxIterations' (its iteration or time limit,
        `presolve.rung_seconds`) or 'NumericalError', with NaN η and λ̂. λ̂ is in Clarabel's
        convention, q + Âᵀλ̂ = 0 on the free factors.
    """
    import highspy

    m, p = pre.A.shape
    h = factor_model(pre.A, pre.b, pre.bounded)
    h.changeColsCost(p, np.arange(p, dtype=np.int32), np.asarray(q, dtype=float))
    h.setOptionValue("solver", "ipm")
    h.setOptionValue("run_crossover", "off")
    h.setOptionValue("ipm_optimality_tolerance", IPM_OPTIMALITY_TOLERANCE)
    h.setOptionValue("ipm_iteration_limit", _rung_iterations(m + p, False))
    h.setOptionValue("time_limit", rung_seconds(m + p))
    h.run()
    point = settled_point(h)
    if point is not None:
        return ("AlmostSolved", *point)
    status = highspy.HighsModelStatus
    model_status = h.getModelStatus()
    names = {status.kInfeasible: "PrimalInfeasible", status.kUnbounded: "DualInfeasible",
             status.kUnboundedOrInfeasible: "DualInfeasible",
             status.kIterationLimit: "MaxIterations", status.kTimeLimit: "MaxIterations"}
    return names.get(model_status, "NumericalError"), np.full(p, np.nan), np.full(m, np.nan)
