"""Certified support values are upper bounds in floating point, free factors included."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth.solvers import certify

try:  # the trajectory set moved below filters and smoothers (issue 6)
    from setsmooth.trajectories import trajectory_set
except ImportError:
    from setsmooth.smoothers.trajectory import trajectory_set


def random_system(rng: np.random.Generator) -> ss.LinearSystem:
    """Random (A, B, C, D) with spectral radius in [0.7, 1.15] and box noises."""
    n, p, m = (int(v) for v in (rng.integers(2, 5), rng.integers(1, 3), rng.integers(1, 3)))
    A = rng.standard_normal((n, n))
    A *= rng.uniform(0.7, 1.15) / max(abs(np.linalg.eigvals(A)))
    D = rng.standard_normal((m, m)) * 0.3 + np.eye(m)
    return ss.LinearSystem(A, None, rng.standard_normal((m, n)), E=rng.standard_normal((n, p)), F=D,
                           W=ss.Box(-np.ones(p), np.ones(p)), V=ss.Box(-np.ones(m), np.ones(m)))


def witness(Z: ss.ConstrainedZonotope, d: np.ndarray) -> tuple[float, float]:
    """HiGHS's maximizer of dᵀx over Z: (its value dᵀ(Gξ + c), its residual ‖Aξ − b‖∞)."""
    G, A = Z.G.toarray(), Z.A.toarray()
    bounds = [(None, None) if np.isinf(h) else (-h, h) for h in Z.h]
    res = linprog(-(G.T @ d), A_eq=A, b_eq=Z.b, bounds=bounds, method="highs",
                  options=dict(primal_feasibility_tolerance=1e-10, dual_feasibility_tolerance=1e-10))
    assert res.status == 0
    xi = np.clip(res.x, -Z.h, Z.h)
    return float(d @ (G @ xi + Z.c)), float(np.abs(A @ xi - Z.b).max())


@pytest.mark.parametrize("seed", [0, 8, 28])
def test_certified_trajectory_bounds_are_never_below_a_feasible_witness(seed):
    # Seeds where the old certificate (free reduced costs taken as zero within a tolerance) fell
    # 1e-9 .. 6e-9 below HiGHS's feasible maximizer (residual ~1e-14).
    rng = np.random.default_rng(seed)
    system = random_system(rng)
    T = int(rng.integers(20, 40))
    x, ys = rng.uniform(-1, 1, system.n), []
    for k in range(T + 1):
        ys.append(system.C_at(k) @ x + system.F_at(k) @ rng.uniform(-1, 1, system.m))
        x = system.A_at(k) @ x + system.E_at(k) @ rng.uniform(-1, 1, system.E_at(k).shape[1])
    Z = trajectory_set(system, ss.Box(-np.ones(system.n), np.ones(system.n)), np.array(ys))
    D = np.vstack([np.eye(Z.dim)[rng.choice(Z.dim, 4, replace=False)],
                   rng.standard_normal((4, Z.dim))])
    certified = Z.support_many(D, certified=True)
    checked = 0
    for d, bound in zip(D, certified):
        value, residual = witness(Z, d)
        if residual > 1e-12:  # not a feasible witness: skip it
            continue
        checked += 1
        assert bound >= value, (bound, value)
        assert bound - value <= 1e-6 * (1.0 + abs(value))  # and not uselessly loose
    assert checked >= 4


def test_the_free_factor_bound_encloses_the_determined_free_factors():
    # ξ3 = ξ1 + 2ξ2 − 0.5 (free but determined): |ξ3| ≤ 3.5 over the box.
    A = sp.csc_matrix(np.array([[1.0, 2.0, -1.0]]))
    bound = certify.free_factor_bound(A, np.array([0.5]), np.array([1.0, 1.0, np.inf]))
    assert bound is not None and bound >= 3.5
    # Two free factors in one row are not determined: no bound.
    A2 = sp.csc_matrix(np.array([[1.0, 1.0, -1.0]]))
    assert certify.free_factor_bound(A2, np.zeros(1), np.array([1.0, np.inf, np.inf])) is None


def test_multipliers_of_a_hull_are_corrected_together_as_one_by_one():
    # A_F of full column rank (8 rows, 5 free factors): the least-norm correction cancels the free
    # factors' reduced cost to rounding, for every direction at once as for each alone, and agrees
    # with the rank-revealing least-squares path (lsqr).
    rng = np.random.default_rng(5)
    AF = sp.csc_matrix(sp.random(8, 5, density=0.5, random_state=6) + sp.eye(8, 5))
    gF, lam = rng.standard_normal((6, 5)), rng.standard_normal((6, 8))
    lam[2] = np.linalg.lstsq(AF.toarray().T, gF[2], rcond=None)[0]  # already cancelling
    solve = certify.normal_solver(AF)
    together = certify.correct_multipliers(AF, gF, lam, solve)
    alone = np.vstack([certify.correct_multipliers(AF, gF[i:i + 1], lam[i:i + 1], solve)
                       for i in range(6)])
    by_lsqr = certify.correct_multipliers(AF, gF, lam)
    np.testing.assert_allclose(together, alone, rtol=0, atol=1e-13)
    for corrected in (together, by_lsqr):
        assert np.abs(corrected @ AF.toarray() - gF).max() < 1e-12


def test_a_certified_value_with_undetermined_free_factors_needs_exact_cancellation():
    # A strip {(s + ξ3, s)}: bounded exactly in the directions ±(1, −1), certified there.
    Z = ss.ConstrainedZonotope([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0]], [0.1, -0.2],
                               A=[[1.0, -1.0, 0.0]], b=[0.0], h=[np.inf, np.inf, 1.0])
    bound = Z.support([1.0, -1.0], certified=True)
    assert bound >= 1.0 + 0.3 and bound <= 1.3 + 1e-9


def test_a_certified_bound_holds_for_any_multiplier():
    rng = np.random.default_rng(3)
    G, A = rng.standard_normal((2, 6)), rng.standard_normal((2, 6))
    b, h, c = A @ rng.uniform(-0.5, 0.5, 6), np.ones(6), rng.standard_normal(2)
    d = rng.standard_normal((1, 2))
    bounds = [(-1.0, 1.0)] * 6
    exact = float(d[0] @ c - linprog(-(G.T @ d[0]), A_eq=A, b_eq=b, bounds=bounds).fun)
    for lam in rng.standard_normal((20, 1, 2)) * 3:  # arbitrary multipliers: loose but valid
        assert certify.certified_bound(d, G, c, sp.csc_matrix(A), b, h, lam, 0.0)[0] >= exact - 1e-12


def test_interval_hulls_of_czs_are_certified_by_default():
    rng = np.random.default_rng(11)
    G, A = rng.standard_normal((3, 10)), rng.standard_normal((3, 10))
    Z = ss.ConstrainedZonotope(G, rng.standard_normal(3), A=A, b=A @ rng.uniform(-0.5, 0.5, 10))
    default, certified = Z.interval_hull(), Z.interval_hull(certified=True)
    np.testing.assert_array_equal(default.lo, certified.lo)
    np.testing.assert_array_equal(default.hi, certified.hi)
    plain = Z.interval_hull(certified=False)
    assert np.all(default.lo <= plain.lo) and np.all(default.hi >= plain.hi)
    np.testing.assert_allclose(default.hi, plain.hi, atol=1e-7)
    assert Z.diameter() >= Z.diameter(certified=False)


def test_a_support_solution_carries_a_feasible_factor_vector_and_its_multipliers():
    rng = np.random.default_rng(5)
    G, A = rng.standard_normal((3, 8)), rng.standard_normal((2, 8))
    Z = ss.ConstrainedZonotope(G, rng.standard_normal(3), A=A, b=A @ rng.uniform(-0.5, 0.5, 8))
    d = rng.standard_normal(3)
    sol = Z.support_solution(d)
    assert sol.value == pytest.approx(Z.support(d), abs=1e-9)
    np.testing.assert_allclose(A @ sol.factors, Z.b, atol=1e-8)
    assert np.all(np.abs(sol.factors) <= 1 + 1e-8)
    np.testing.assert_allclose(G @ sol.factors + Z.c, sol.point, atol=1e-12)
    # The multipliers certify the value: weak duality with them is tight.
    bound = certify.certified_bound(d[None], G, Z.c, sp.csc_matrix(A), Z.b, Z.h,
                                    sol.multipliers[None], 0.0)[0]
    assert sol.value <= bound <= sol.value + 1e-7
    free = ss.ConstrainedZonotope(G, np.zeros(3)).support_solution(d)  # closed form, nc = 0
    assert free.value == pytest.approx(d @ G @ free.factors) and free.multipliers.size == 0


def test_a_certified_bound_far_from_the_origin_is_tight_to_the_width_and_above_the_exact_value():
    # Each sum's rounding is charged by its own length: a centre 1.9e6 from the origin with ~1500
    # factors once cost γ_1500·|d|ᵀ|c| ≈ 6e-7 (1e-6 of a unit width); per sum it is γ_n·|d|ᵀ|c|.
    from fractions import Fraction

    rng = np.random.default_rng(3)
    n, ng = 3, 1500
    G = rng.uniform(-1.0, 1.0, size=(n, ng)) / ng
    c = rng.uniform(1.8e6, 2.0e6, size=n)
    A, b, h = sp.csc_matrix((0, ng)), np.zeros(0), np.ones(ng)
    d = rng.standard_normal((4, n))
    bound = certify.certified_bound(d, G, c, A, b, h, np.zeros((4, 0)), None)
    for i in range(4):
        exact = sum(Fraction(float(di)) * Fraction(float(ci)) for di, ci in zip(d[i], c)) + sum(
            abs(sum(Fraction(float(d[i, r])) * Fraction(float(G[r, j])) for r in range(n))) for j in range(ng))
        width = 2.0 * float(np.abs(d[i] @ G).sum())
        assert Fraction(float(bound[i])) >= exact
        assert float(Fraction(float(bound[i])) - exact) <= 1e-8 * width


def test_below_the_guaranteed_width_a_plain_hull_is_the_certified_one():
    """A coordinate thinner than ``GUARANTEED_WIDTH_RATIO`` of its magnitude (a segment at x₂ = 5e6
    exactly, rounded by the set's own data) gets the certified endpoints as its plain hull: outer,
    holding the exact value, never a solver value placed only to the bracket's floor. The wide
    coordinate keeps the solver's values (inside the certified ones), and a single support value
    along the thin direction stays the solver's."""
    from setsmooth import tolerances

    G = np.array([[1.0, 0.5, 0.25], [1e-9, 0.0, -1e-9]])
    Z = ss.ConstrainedZonotope(G, np.array([0.0, 5e6]), A=np.array([[1.0, 1.0, 1.0]]),
                               b=np.array([0.3]))
    plain, certified = Z.interval_hull(certified=False), Z.interval_hull(certified=True)
    width = plain.hi - plain.lo
    assert width[1] < tolerances.GUARANTEED_WIDTH_RATIO * (abs(plain.lo[1]) + abs(plain.hi[1]))
    assert plain.lo[1] == certified.lo[1] and plain.hi[1] == certified.hi[1]
    exact = [sign * 5e6 - linprog(-sign * G[1], A_eq=Z.A, b_eq=Z.b, bounds=(-1, 1)).fun
             for sign in (1.0, -1.0)]  # h(±e₂), up to linprog's accuracy on the 1e-9 entries
    assert plain.hi[1] >= exact[0] and -plain.lo[1] >= exact[1]
    assert plain.lo[0] >= certified.lo[0] and plain.hi[0] <= certified.hi[0]
    assert (plain.lo[0], plain.hi[0]) != (certified.lo[0], certified.hi[0])
    assert Z.support(np.array([0.0, 1.0])) < certified.hi[1]
