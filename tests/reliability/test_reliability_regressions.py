"""Regressions of the large reliability run (seed 2026, T = 10..40) that check how an answer is
found; the incidents that check an answer against its exact value are the replay corpus
(`replay.py`, ``cases/``).

Reliability case 000 (n = 6, stable, box noises): the recursion smoother's sets hold copies of the
same posterior factors linked by the states, and on half their directions Clarabel stops at
'AlmostSolved' with a relative gap of 1e-8..1e-7 (the refined solve stops at the same point). Every
such direction went through the refined solve, the same program again as the 'fully presolved' one
(no dependent row found) and the simplex method before `CZProgram._verified` bracketed the answer:
1752 Clarabel solves and 578 simplex solves for 864 directions at T = 29. The refined re-solve
stalls at the same point on these programs, so `CZProgram` (which brackets every answer) went from
a rough first answer straight to the simplex method; it now asks the warm-started simplex method
first (`policy.POLICIES`).
"""

from __future__ import annotations

import numpy as np

import setsmooth as ss
from setsmooth.solvers import factor_set
from setsmooth.solvers.backends import BACKENDS

from setsmooth.reliability.random_systems import base_case, in_regime


def test_recursion_smoother_directions_are_answered_by_the_simplex_method_first(monkeypatch):
    case = base_case(2026, 0, T_range=(12, 12))
    first_pass: list[list] = []  # the backends asked for each direction's first pass
    current: list = [None]
    maximize = factor_set.FactorConstraints.maximize

    def counted_maximize(self, *args, **kwargs):
        current[0] = [] if kwargs.get("purpose") != "escalated" else None
        if current[0] is not None:
            first_pass.append(current[0])
        try:
            return maximize(self, *args, **kwargs)
        finally:
            current[0] = None

    def counted(name):
        def backend(pre, q, batch=None):
            out = BACKENDS_REAL[name](pre, q, batch)
            if current[0] is not None:
                current[0].append(name)
            return out
        return backend

    BACKENDS_REAL = dict(BACKENDS)
    for name in BACKENDS_REAL:
        monkeypatch.setitem(BACKENDS, name, counted(name))
    monkeypatch.setattr(factor_set.FactorConstraints, "maximize", counted_maximize)
    for S in ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion"):
        # The recursion's own CZ (its queries would go to its data reference, the trajectory form).
        ss.ConstrainedZonotope(S.G, S.c, S.A, S.b, S.h).interval_hull(certified=False)
    # Before: 40 refined interior-point re-solves (and 3 of the same program again) in the first
    # pass, 13 simplex solves; then Clarabel first, stopping at 'AlmostSolved' on more than 20
    # directions, each re-solved by the simplex method; now the simplex method answers first.
    assert first_pass and all(solves[0] == "simplex" for solves in first_pass)
    assert all(len(solves) <= 2 for solves in first_pass)
    assert sum(len(solves) == 1 for solves in first_pass) >= 0.9 * len(first_pass)  # 156 of 156


def test_case_209s_initial_set_holds_its_initial_state():
    case = base_case(2026, 209)
    assert case.X0.contains(case.xs[0])


def test_a_posterior_pinned_by_rounded_data_holds_the_truth_by_membership_as_by_its_hull():
    """Case 069 at offset 1e6 (three outputs, one measurement noise: the data pin the state, and
    the 1e6-sized data rounded to 1e-10 are inconsistent in exact arithmetic): membership used to
    call the true x_8 outside (the simplex method on the stored rows) and to raise at x_9, where
    the certified hull held it. An unsettled membership program is now decided as an unsettled
    support is, on the rows relaxed by the phase-one residual."""
    case = in_regime(base_case(2026, 69, T_range=(10, 14), noise="box"), "offset1e+06")
    posteriors = ss.classical_filter(case.system, case.X0, case.ys)
    assert posteriors.contains_trajectory(case.xs).all()
    for k in (8, 9):
        hull = posteriors[k].interval_hull(certified=True)
        assert np.all(hull.lo <= case.xs[k]) and np.all(case.xs[k] <= hull.hi)


def test_the_recursion_smoothers_membership_asks_its_data_reference():
    """Case 074 at offset 1e6: the recursion smoother's membership program on its own CZ (the
    normalized one of `settled_without_hull`) raised NumericalError; it is asked of the data
    reference now, like every other query of the set."""
    case = in_regime(base_case(2026, 74, T_range=(10, 14), noise="zonotope"), "offset1e+06")
    smoothed = ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion")
    assert smoothed.contains_trajectory(case.xs).all()
