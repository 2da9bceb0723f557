"""Regressions found by the large reliability run (seed 2026, T = 10..40), each at its smallest size.

Reliability case 000 (n = 6, stable, box noises): the recursion smoother's sets hold copies of the
same posterior factors linked by the states, and on half their directions Clarabel stops at
'AlmostSolved' with a relative gap of 1e-8..1e-7 (the refined solve stops at the same point). Every
such direction went through the refined solve, the same program again as the 'fully presolved' one
(no dependent row found) and the simplex method before `CZProgram._verified` bracketed the answer:
1752 Clarabel solves and 578 simplex solves for 864 directions at T = 29. The refined re-solve
stalls at the same point on these programs, so `CZProgram` (which brackets every answer) went from
a rough first answer straight to the simplex method; it now asks the warm-started simplex method
first (`factor_set.BRACKETED_ATTEMPTS`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.solvers import factor_set
from setsmooth.solvers.presolve import presolve

from .compare import (ENCLOSE_TOL, TrajectoryOracle, compare_case, confirm_by_witnesses, confirm_off,
                      describe)
from .oracle import FactorForm, cz_support, data_scale
from .random_systems import base_case, in_regime


def test_recursion_smoother_directions_are_answered_by_the_simplex_method_first(monkeypatch):
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
    # Before: 40 refined interior-point re-solves (and 3 of the same program again) in the first
    # pass, 13 simplex solves; then Clarabel first, stopping at 'AlmostSolved' on more than 20
    # directions, each re-solved by the simplex method; now the simplex method answers first.
    assert all(solves[0][0] == "simplex" for solves in first_pass)
    assert all(len(solves) <= 2 for solves in first_pass)
    assert sum(len(solves) == 1 for solves in first_pass) >= 0.9 * len(first_pass)  # 156 of 156


def test_recursion_smoother_hulls_are_exact_on_the_hard_case():
    case = base_case(2026, 0, T_range=(12, 12))
    result = compare_case(case, estimators=("recursion",))
    assert not result.failed, describe(result)


def test_certified_filter_hulls_enclose_the_exact_ones_far_from_the_origin_at_tiny_noise():
    """Case 001 (unstable, T = 37) at noise 1e-6: x_37 sits ~130 σ from the origin and the oracle's
    HiGHS value (tolerance 1e-10 on unit factors) was 5e-14 above a feasible witness's coordinate,
    so a sound certified bound between them counted as 'not enclosing'. Scored against the
    witness, the certified hulls enclose."""
    case = in_regime(base_case(2026, 1), "scale1e-06")
    result = compare_case(case, estimators=("filter",))
    assert not result.failed, describe(result)


def test_witness_confirmation_keeps_a_truly_unsound_certified_bound():
    case = base_case(2026, 2, T_range=(10, 10), n_range=(2, 3))
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    lo, hi = oracle.filtered_hulls()
    width = hi - lo
    shrunk = [(lo[k] + 1e-3 * width[k], hi[k] - 1e-3 * width[k]) for k in range(lo.shape[0])]
    sigma = data_scale(case.system, case.X0)
    confirmed_lo, confirmed_hi = confirm_by_witnesses(oracle, True, (lo, hi), shrunk, sigma)
    inside = np.maximum(np.array([c[0] for c in shrunk]) - confirmed_lo,
                        confirmed_hi - np.array([c[1] for c in shrunk]))
    assert np.all(inside > ENCLOSE_TOL * (width + sigma))


def test_a_free_factor_seen_only_by_a_noise_free_row_takes_its_neighbours_units():
    """Case 015 (CZ noises) at noise 1e-6: a state component that neither B·W nor C reaches sits
    in one dynamics row with other states only. The equilibration left it at its raw scale, 1e-7
    of the others', below the solvers' absolute tolerances: filtered hulls 3.8e-3 of the width
    off, certified ones 9e-3 loose."""
    eps = 1e-6
    # ξ_0, ξ_1 bounded (|ξ| ≤ 1); x_0 = eps·(ξ_0 + 0.5 ξ_1) anchored by a row with bounded
    # entries; x_1 = 0.3 x_0 seen only by the free-only row x_1 − 0.3 x_0 = 0.
    A = np.array([[eps, 0.5 * eps, -1.0, 0.0],
                  [0.0, 0.0, -0.3, 1.0]])
    b = np.array([0.2 * eps, 0.0])
    h = np.array([1.0, 1.0, np.inf, np.inf])
    pre = presolve(sp.csc_matrix(A), b, h, dependent=False)
    # x_1 in the bounded factors' units: of the same order as x_0, not 1e6 times larger
    assert 0.1 < pre.col_scale[3] / pre.col_scale[2] < 10
    G = np.array([[0.0, 0.0, 0.0, 1.0]])
    Z = ss.ConstrainedZonotope(G, np.zeros(1), A, b, h)
    exact = [cz_support(FactorForm(G, np.zeros(1), A, b, h), d)[0] for d in ([1.0], [-1.0])]
    plain = Z.support_many(np.array([[1.0], [-1.0]]), certified=False)
    certified = Z.support_many(np.array([[1.0], [-1.0]]), certified=True)
    width = exact[0] + exact[1]
    assert np.allclose(plain, exact, rtol=0, atol=1e-6 * width)
    assert np.all(certified >= np.array(exact) - 1e-12 * width)
    assert np.allclose(certified, exact, rtol=0, atol=1e-6 * width)


def test_filter_hulls_are_exact_with_a_state_no_noise_reaches_at_tiny_noise():
    case = in_regime(base_case(2026, 15), "scale1e-06")
    result = compare_case(case, estimators=("filter",))
    assert not result.failed, describe(result)


def test_a_primal_value_beyond_its_certified_bound_is_escalated_not_kept():
    """Reliability case 150 (n = 5, stable, box noises, states ~3500 σ from the origin): on two
    trajectory-smoother directions Clarabel's point was infeasible beyond tolerance, its value above
    the certified bound; the bracket check read the negative gap as tight and returned the bound,
    9e-5 (4.2e-5 of w + σ) outside the exact hull. An inverted bracket is now escalated like a loose
    one. The reference is the oracle's cold `linprog` per direction (independent of its warm model)."""
    case = base_case(2026, 150)
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    sigma = data_scale(case.system, case.X0)
    smoothed = ss.optimal_smoother(case.system, case.X0, case.ys, method="trajectory")
    for k in (2, 6):
        hull = smoothed[k].interval_hull(certified=True)
        for i in range(case.system.n):
            e = np.eye(case.system.n)[i]
            hi, lo = oracle.support_linprog(k, e), -oracle.support_linprog(k, -e)
            unit = hi - lo + sigma
            assert hull.hi[i] >= hi - ENCLOSE_TOL * unit and hull.lo[i] <= lo + ENCLOSE_TOL * unit
            assert abs(hull.hi[i] - hi) <= 1e-6 * unit and abs(hull.lo[i] - lo) <= 1e-6 * unit, (k, i)


def test_an_off_endpoint_is_confirmed_by_a_cold_solve_of_the_oracle():
    """Case 150 at k = 21: the oracle's warm model stopped 3.2e-6 below the maximum (1e-6 of w + σ)
    that its own cold solve and the smoother agree on to 1e-12; `confirm_off` keeps the better of
    the two oracle answers, so only an endpoint off from both counts."""
    case = base_case(2026, 150)
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    exact = oracle.smoothed_hulls()
    result = compare_case(case, exact={"filtered": None, "smoothed": exact}, estimators=("trajectory",))
    assert not result.failed, describe(result)
    # A truly off hull still counts: the hull at k = 21 shrunk by 1e-3 of the width.
    lo, hi = exact[0].copy(), exact[1].copy()
    lo[21] += 1e-3 * (exact[1][21] - exact[0][21])
    hi[21] -= 1e-3 * (exact[1][21] - exact[0][21])
    sigma = data_scale(case.system, case.X0)
    confirmed = confirm_off(oracle, False, exact, [(lo, hi)], sigma)
    unit = confirmed[1][21] - confirmed[0][21] + sigma
    assert np.all(confirmed[1][21] - hi[21] > 1e-6 * unit) and np.all(lo[21] - confirmed[0][21] > 1e-6 * unit)


def test_an_oracle_program_thinner_than_the_rounding_of_its_data_is_still_solved():
    """Case 074 at offset 1e6: three measurements of a 2-state system with one noise factor pin the
    state exactly (hulls 2e-9 wide at 1e6); at 1e-10 HiGHS called k = 1 infeasible, which left the
    case out of the counts. The oracle now retries at the data's rounding level."""
    case = in_regime(base_case(2026, 74), "offset1e+06")
    result = compare_case(case, estimators=("filter",))
    assert not result.failed, describe(result)


def test_a_sliver_at_noise_1e3_is_answered_not_raised():
    """Case 069 at noise 1e3 (non-square D, CZ noises: the measurements pin the state to a sliver):
    an escalated direction found the simplex method calling the sliver infeasible at 1e-10 and the
    relaxed program's interior-point solve stalled ('AlmostSolved'), so the trajectory smoother's
    hull raised. The relaxed program (always feasible) now falls back to the simplex method."""
    case = in_regime(base_case(2026, 69), "scale1e+03")
    result = compare_case(case, estimators=("trajectory",))
    assert not any(o.error for o in result.outcomes), describe(result)


def test_a_recession_program_clarabel_cannot_settle_goes_to_the_simplex_method():
    """Case 176 at noise 1e-6 (unstable, CZ noises): Clarabel ended the recession program (feasible
    at η = 0, bounded) 'inaccurate', and the filter's and the smoother's hulls raised. HiGHS now
    settles it; the hulls are scored against the oracle."""
    case = in_regime(base_case(2026, 176), "scale1e-06")
    result = compare_case(case, estimators=("filter",))
    assert not result.failed, describe(result)


def test_recursion_smoother_certified_hulls_enclose_the_exact_ones_far_from_the_origin():
    """Reliability case 000 (n = 6, T = 29) at offset 1e6: the recursion's CZs are formed by products
    of A rounded in floating point, and their certified hulls (valid for the CZs as stored) sat up to
    1.0e-7 of w + σ inside the exact hull at 137 endpoints. The estimators' sets are now certified
    against the data (`setsmooth.trajectories.recursion_certificates`, trajectory rows with their rounding
    charged)."""
    case = in_regime(base_case(2026, 0), "offset1e+06")
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    lo_x, hi_x = oracle.smoothed_hulls()
    sigma = data_scale(case.system, case.X0)
    smoothed = ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion")
    hulls = smoothed.interval_hulls(certified=True)
    lo = np.array([h.lo for h in hulls])
    hi = np.array([h.hi for h in hulls])
    unit = hi_x - lo_x + sigma
    fp = np.finfo(float).eps * (np.abs(lo_x) + np.abs(hi_x))
    assert np.all(lo <= lo_x + ENCLOSE_TOL * unit + fp) and np.all(hi >= hi_x - ENCLOSE_TOL * unit - fp)
    assert np.all(np.maximum(lo_x - lo, hi - hi_x) <= 1e-6 * unit)  # and tight


def test_recursion_smoother_plain_hulls_are_exact_far_from_the_origin():
    """Reliability case 033 (n = 6, rank-deficient C, T = 30) at offset 1e6: the backward recursion
    in absolute coordinates rounded each intersection's centres at 1e6, differently in the two copies
    of the same data, and its plain hulls were up to 5.3e-6 of w + σ narrower than the exact ones
    (4.0e-6 at k = 24, 5.3e-6 at k = 25). The recursion now runs about the nominal trajectory
    (`setsmooth.trajectories.nominal`)."""
    case = in_regime(base_case(2026, 33), "offset1e+06")
    lo_x, hi_x = TrajectoryOracle(case.system, case.X0, case.ys).smoothed_hulls()
    sigma = data_scale(case.system, case.X0)
    smoothed = ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion")
    for k in (24, 25):
        hull = smoothed[k].interval_hull(certified=False)
        unit = hi_x[k] - lo_x[k] + sigma
        fp = 64 * np.finfo(float).eps * (np.abs(lo_x[k]) + np.abs(hi_x[k]))
        assert np.all(np.abs(hull.lo - lo_x[k]) <= 1e-6 * unit + fp), k
        assert np.all(np.abs(hull.hi - hi_x[k]) <= 1e-6 * unit + fp), k


def test_certified_filter_hulls_with_free_factors_stay_tight():
    """Reliability case 069 (n = 6, CZ noises, non-square D, T = 24): the posterior views have free
    factors (the states). With the simplex method answering their directions first, the multipliers
    left its dual tolerance on the free factors and the certified hulls were up to 6.1e-5 of w + σ
    wider than the exact ones (k = 19); Clarabel answers them first
    (`factor_set.BRACKETED_ATTEMPTS_FREE`)."""
    case = base_case(2026, 69)
    lo_x, hi_x = TrajectoryOracle(case.system, case.X0, case.ys).filtered_hulls()
    sigma = data_scale(case.system, case.X0)
    posteriors = ss.classical_filter(case.system, case.X0, case.ys)
    for k in (12, 19):
        hull = posteriors[k].interval_hull(certified=True)
        unit = hi_x[k] - lo_x[k] + sigma
        fp = 64 * np.finfo(float).eps * (np.abs(lo_x[k]) + np.abs(hi_x[k]))
        slack = ENCLOSE_TOL * unit + fp  # the oracle's own tolerance
        assert np.all(hull.lo <= lo_x[k] + slack) and np.all(hull.hi >= hi_x[k] - slack), k
        assert np.all(lo_x[k] - hull.lo <= 1e-6 * unit + fp), k
        assert np.all(hull.hi - hi_x[k] <= 1e-6 * unit + fp), k


def test_trajectory_rows_carry_the_rounding_of_the_nominal_trajectory():
    """Each dynamics row x_{k+1} − A x_k − B G_w ξ = 0 about the nominal x̄ holds exactly only up to
    A x̄_k + B c_w + u_k − x̄_{k+1}, rounded away when x̄ is 1e6: the row's slack covers it (rationals)."""
    from fractions import Fraction

    from setsmooth.trajectories import trajectory_set

    case = in_regime(base_case(2026, 3, T_range=(8, 8), n_range=(3, 3)), "offset1e+06")
    system, n = case.system, case.system.n
    Z = trajectory_set(system, case.X0, case.ys)
    slack = Z.factors.slack
    assert slack is not None
    x = Z.c.reshape(-1, n)
    cw = system.W.to_constrained_zonotope().c
    first_dyn = Z.nc - (case.T + 1) * system.m - case.T * n
    worst = 0.0
    for k in range(case.T):
        A, B, u = system.A(k), system.B(k), system.input_term(k)
        for i in range(n):
            exact = (sum(Fraction(A[i, j]) * Fraction(x[k, j]) for j in range(n))
                     + sum(Fraction(B[i, j]) * Fraction(cw[j]) for j in range(B.shape[1]))
                     + Fraction(u[i]) - Fraction(x[k + 1, i]))
            row = first_dyn + k * n + i
            assert abs(exact) <= Fraction(slack[row])
            worst = max(worst, float(abs(exact)))
    assert worst > 0  # the nominal does round at 1e6


def test_a_prior_whose_vertices_defeat_qhull_is_still_sampled():
    """Reliability system 209: X0 is a 5-D CZ whose vertex set is so nearly degenerate that Qhull's
    triangulation fails ('wide merge'); drawing x_0 crashed the whole benchmark. Sampling falls back
    to hit-and-run ('auto'), and the case is generated."""
    case = base_case(2026, 209)
    assert case.X0.contains(case.xs[0])


def test_a_bracket_far_from_the_origin_is_held_to_the_certificates_own_rounding():
    """Case 168 at offset 1e6 (rank-deficient C, CZ noises, n = 6, T = 15): the bracket check let an
    interior-point answer whose certified bound sat 3e-6 above the optimum pass (states 1.9e6, hull
    width 1.1: 2.1e-6 of it, filter and trajectory smoother at k = 14, 15), because its floor was
    2⁻⁴⁰·|values| where the certificate's own rounding was 2.8e-9. The floor is now that rounding."""
    case = in_regime(base_case(2026, 168), "offset1e+06")
    result = compare_case(case, estimators=("filter",))
    assert not result.failed, describe(result)


def test_recursion_smoother_hull_where_the_simplex_method_meets_a_singular_basis():
    """Reliability case 184 (n = 5, box noises, non-square D, T = 37), smoothed set k = 8 (2,260 ×
    2,967 presolved): along e_1 the warm primal method stopped at 'Unknown' at the optimum and every
    cold rung after it failed or left residuals of 1e-5; along e_2 HiGHS's simplex method met a
    rank-deficient basis on every rung and Clarabel stopped at 'NumericalError'. The hull raised
    `SolverError('AlmostSolved')` from the relaxed last resort. An 'Unknown' point with a dual goes
    to the independent check (`WarmSimplex.minimize`), and HiGHS's interior-point method is the
    last fallback (`interior_point.interior_point`)."""
    case = base_case(2026, 184)
    lo_x, hi_x = TrajectoryOracle(case.system, case.X0, case.ys).smoothed_hulls()
    sigma = data_scale(case.system, case.X0)
    hull = ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion")[8].interval_hull(
        certified=False)
    unit = hi_x[8] - lo_x[8] + sigma
    assert np.all(np.abs(hull.lo - lo_x[8]) <= 1e-6 * unit)
    assert np.all(np.abs(hull.hi - hi_x[8]) <= 1e-6 * unit)


def test_recursion_smoother_hull_where_every_simplex_basis_and_the_crossover_are_singular():
    """Reliability case 184 at noise 1e3, smoothed set k = 25 (1,308 × 1,726 presolved): HiGHS's
    simplex method met a rank-deficient basis on every rung, Clarabel stopped at 'AlmostSolved' or
    'NumericalError', and the interior-point method's crossover failed, so the certified hull raised
    `SolverError('AlmostSolved')`. HiGHS's interior-point method without crossover settles it
    (`interior_point.interior_point`)."""
    case = in_regime(base_case(2026, 184), "scale1e+03")
    lo_x, hi_x = TrajectoryOracle(case.system, case.X0, case.ys).smoothed_hulls()
    sigma = data_scale(case.system, case.X0)
    hull = ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion")[25].interval_hull()
    unit = hi_x[25] - lo_x[25] + sigma
    assert np.all(hull.lo <= lo_x[25] + 1e-9 * unit)  # certified: encloses the exact hull
    assert np.all(hull.hi >= hi_x[25] - 1e-9 * unit)
    assert np.all(np.abs(hull.lo - lo_x[25]) <= 1e-6 * unit)
    assert np.all(np.abs(hull.hi - hi_x[25]) <= 1e-6 * unit)
