"""Regression tests of the fast path's solver policy on the reliability suite's hard cases.

Reliability case 000 (n = 6, stable, box noises): the recursion smoother's sets hold copies of the
same posterior factors linked by the states, and on half their directions Clarabel stops at
'AlmostSolved' with a relative gap of 1e-8..1e-7 (the refined solve stops at the same point). Every
such direction went through the refined solve, the same program again as the 'fully presolved' one
(no dependent row found) and the simplex method before `CZProgram._verified` bracketed the answer:
1752 Clarabel solves and 578 simplex solves for 864 directions at T = 29.
"""

from __future__ import annotations

import setsmooth as ss
from setsmooth.solvers import factor_set

from .compare import compare_case, describe
from .random_systems import base_case


def test_recursion_smoother_settles_a_verified_direction_with_its_first_solve(monkeypatch):
    case = base_case(2026, 0, T_range=(12, 12))
    first_pass: list[list] = []  # the solves (refine, status) of each direction's first pass
    current: list = [None]
    solve_on, maximize = factor_set.FactorConstraints._solve_on, factor_set.FactorConstraints.maximize

    def counted_maximize(self, *args, **kwargs):
        current[0] = [] if not kwargs.get("escalate") else None
        if current[0] is not None:
            first_pass.append(current[0])
        try:
            return maximize(self, *args, **kwargs)
        finally:
            current[0] = None

    def counted_solve_on(self, pre, q, refine):
        out = solve_on(self, pre, q, refine)
        if current[0] is not None:
            current[0].append((refine, out[0]))
        return out

    monkeypatch.setattr(factor_set.FactorConstraints, "maximize", counted_maximize)
    monkeypatch.setattr(factor_set.FactorConstraints, "_solve_on", counted_solve_on)
    for S in ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion"):
        S.interval_hull(certified=False)
    assert sum(solves[0][1] == "AlmostSolved" for solves in first_pass) > 20  # still a hard case
    # Before: 40 refined re-solves and 13 simplex solves in the first pass; the bracket decides now.
    resolved = [solves for solves in first_pass if len(solves) > 1]
    assert len(resolved) <= 2, resolved


def test_recursion_smoother_hulls_are_exact_on_the_hard_case():
    case = base_case(2026, 0, T_range=(12, 12))
    result = compare_case(case, estimators=("recursion",))
    assert not result.failed, describe(result)
