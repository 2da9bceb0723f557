"""OIT-inspired filtering (stability Algorithm 2) and the OIT-CZ SMF (Algorithm 3).

Independent references: `filtering_map` (the trajectory set with the states as free factors, a
different construction from the window of (23)), the exact classical filter, the true states of
seeded simulations.
"""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis
from setsmooth.filters import oit
from setsmooth.solvers.parametric import ParametricSupport

TOL = 1e-6


def box(half: float, n: int, centre=None) -> ss.Box:
    c = np.zeros(n) if centre is None else np.asarray(centre, dtype=float)
    return ss.Box(c - half, c + half)


def example_25() -> ss.LinearSystem:
    w = box(1.0, 1)
    return ss.LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]], W=w, V=w)


def example_26() -> ss.LinearSystem:
    w = box(1.0, 1)
    return ss.LinearSystem([[0.5, 1.0], [0.0, 1.0]], None, [[0.0, 1.0]], E=[[0.5], [1.0]], W=w, V=w)


def inside(xs: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.all((lo - TOL <= xs) & (xs <= hi + TOL), axis=-1)


# -- observable systems: the window is F_{k,k−δ̄}(ℝⁿ) --------------------------------------------------
@pytest.mark.parametrize("seed", range(4))
def test_observable_estimate_equals_filtering_map_of_the_whole_space(seed):
    rng = np.random.default_rng(seed)
    drawn = analysis.random_observable_system(rng, 3, 2, 2)
    system = drawn.linear_system()
    X0 = box(5.0, 3)
    xs, ys = ss.simulate(system, X0, 9, rng)
    res = ss.oit_cz_filter(system, box(1.0, 3, rng.uniform(-5, 5, 3)), ys, hulls=True)
    d = res.delta_bar
    D = rng.normal(size=(8, 3))
    for k in range(d, 10):
        reference = ss.filtering_map(system, ss.Reals(3), ys, k - d, k)
        np.testing.assert_allclose(res.estimates[k].support_many(D), reference.support_many(D),
                                   rtol=1e-6, atol=1e-6)
        hull = reference.interval_hull(certified=True)
        lo, hi = res.hulls[0][k], res.hulls[1][k]
        np.testing.assert_allclose(lo, hull.lo, atol=1e-6)
        np.testing.assert_allclose(hi, hull.hi, atol=1e-6)
        assert np.all(lo <= hull.lo + 1e-7) and np.all(hi >= hull.hi - 1e-7)  # both outer, both tight


def test_observable_windows_share_one_constraint_matrix_and_change_only_b():
    rng = np.random.default_rng(3)
    system = analysis.random_observable_system(rng, 4, 2, 2).linear_system()
    _, ys = ss.simulate(system, box(3.0, 4), 12, rng)
    res = ss.oit_cz_filter(system, box(3.0, 4), ys, delta_bar=4)
    windows = res.estimates[4:]
    assert all(np.shares_memory(Z.A, windows[0].A) and np.shares_memory(Z.G, windows[0].G) for Z in windows)
    assert windows[0].nc == 5 * 2 and windows[0].ng == 4 + 4 * 2 + 5 * 2  # (δ̄+1)m, n + δ̄p + (δ̄+1)m
    assert not np.allclose(windows[0].b, windows[1].b)


def test_observable_estimate_forgets_the_initial_condition_after_delta_bar():
    rng = np.random.default_rng(5)
    system = example_25()
    xs, ys = ss.simulate(system, box(1.0, 2, [2, 2]), 10, rng)
    a = ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=2, hulls=True)
    b = ss.oit_cz_filter(system, box(50.0, 2, [30, -7]), ys, delta_bar=2, hulls=True)
    np.testing.assert_array_equal(a.hulls[0][2:], b.hulls[0][2:])
    np.testing.assert_array_equal(a.hulls[1][2:], b.hulls[1][2:])
    assert inside(xs[2:], a.hulls[0][2:], a.hulls[1][2:]).all()


# -- Line 5: the reset --------------------------------------------------------------------------------
def test_line5_resets_an_empty_estimate_with_the_smallest_doubled_theta():
    system = example_25()
    ys = np.array([[10.0], [11.0], [12.0]])  # x_1 ∈ [9, 11] contradicts ⟦x̂_0⟧ = [−1, 1]²
    res = ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=2)
    assert res.resets == [0] and res.thetas == {0: 16.0}
    dec = analysis.observability_decomposition(system.A_at(0), system.C_at(0))
    expected = ss.filtering_map(system, dec.U @ box(16.0, 2), ys, 0, 0)  # P⁻¹(B_16)
    D = np.vstack([np.eye(2), -np.eye(2), [[1.0, 1.0]]])
    np.testing.assert_allclose(res.estimates[0].support_many(D), expected.support_many(D), atol=1e-7)
    smaller = ss.filtering_map(system, dec.U @ box(8.0, 2), ys, 0, 0)
    assert smaller.is_empty()


def test_line5_gives_up_on_data_no_box_can_explain(monkeypatch):
    monkeypatch.setattr(oit, "MAX_DOUBLINGS", 3)  # θ ≤ 8 cannot reach y_0 = 100
    system = example_25()
    ys = np.array([[100.0], [0.0]])
    with pytest.raises(ValueError, match="contradict"):
        ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=1, on_inconsistent="raise")
    with pytest.warns(ss.ModelInvalidationWarning, match="contradict"):
        assert ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=1).first_empty == 0


# -- detectable systems: Theorem 4 ---------------------------------------------------------------------
def test_detectable_estimates_contain_the_true_state_in_1000_seeded_runs():
    """Theorem 4 with ⟦x̂_0⟧ ∋ x_0: the induction of its proof gives Z_k ∋ x_k from k̲ = 0 on."""
    violations = runs = 0
    rng = np.random.default_rng(20240)
    system = example_26()
    dec = analysis.observability_decomposition(system.A_at(0), system.C_at(0))
    T = 5
    for run in range(1000):
        if run % 2:  # half on (26), half on random detectable systems with n = 3, n_o = 2
            drawn = analysis.random_detectable_system(rng, 3, 2, 1, 1)
            sys_, dec_, n = drawn.linear_system(), drawn.decomposition, 3
        else:
            sys_, dec_, n = system, dec, 2
        X0 = box(1.0, n, rng.uniform(-3, 3, n))
        xs, ys = ss.simulate(sys_, X0, T, rng)
        res = ss.oit_cz_filter(sys_, X0, ys, delta_bar=2 if n == 3 else 1, decomposition=dec_, hulls=True)
        violations += int((~inside(xs, *res.hulls)).sum())
        if run < 40:  # set membership itself (one LP per step) on the first runs
            violations += sum(not Z.contains(x, tol=TOL) for Z, x in zip(res.estimates, xs))
        runs += 1
    assert runs == 1000 and violations == 0


def test_detectable_estimate_contains_the_exact_posterior_eventually():
    """(24): Z_k ⊇ ⟦x_k | y_{0:k}⟧ (the true initial set's posterior) for k ≥ k̲, here with an initial
    condition that misses ⟦x_0⟧ (Carol's [−1, 1]² on example (26)); k̲ from the run's own Line 12:
    the first i ≥ δ̄ from which ‖Ã_ō^{i−δ̄}‖∞ (|x̃^ō_δ̄ − ĉ^ō_δ̄| − d∞/2)⁺ ≤ ε, plus δ̄."""
    system = example_26()
    true_set = box(1.0, 2, [2, 2])
    D = np.vstack([np.eye(2), -np.eye(2), [[1, 1], [1, -1], [-1, 1], [-1, -1]]])
    for seed in range(6):
        rng = np.random.default_rng(seed)
        xs, ys = ss.simulate(system, true_set, 30, rng)
        res = ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=3, hulls=True)
        exact = ss.classical_filter(system, true_set, ys)
        dec = analysis.observability_decomposition(system.A_at(0), system.C_at(0))
        d = res.delta_bar
        worst = max(Z.support(D[j]) - res.estimates[k].support(D[j])
                    for k, Z in enumerate(exact) if k >= 4 * d for j in range(len(D)))
        assert worst <= 1e-6
        x_obar = dec.P_obar @ xs[d]
        half_d = (res.alpha[d] - 1e-3)  # α_δ̄ = d∞/2 + ε
        gap = max(0.0, float(np.abs(x_obar - res.c_obar[d]).max()) - half_d)
        k_low = next(i for i in range(d, 31) if all(
            0.5 ** (j - d) * gap <= 1e-3 for j in range(i, 31))) + d  # ‖Ã_ō^j‖∞ = 0.5^j here
        assert inside(xs[k_low:], res.hulls[0][k_low:], res.hulls[1][k_low:]).all()


def test_detectable_estimates_stay_bounded_on_a_long_horizon():
    rng = np.random.default_rng(11)
    drawn = analysis.random_detectable_system(rng, 4, 2, 2, 2)
    system = drawn.linear_system()
    xs, ys = ss.simulate(system, box(2.0, 4), 80, rng)
    res = ss.oit_cz_filter(system, box(2.0, 4, [5, 0, 0, -5]), ys, delta_bar=3,
                           decomposition=drawn.decomposition, hulls=True)
    radius = ((res.hulls[1] - res.hulls[0]) / 2).max(axis=1)
    assert np.all(np.isfinite(radius))
    assert radius[40:].max() <= 1.1 * radius[6:40].max()
    alpha = res.alpha[3:]
    assert np.all(np.isfinite(alpha)) and alpha[40:].max() <= 1.1 * alpha[:40].max()


# -- Algorithm 2 --------------------------------------------------------------------------------------
def test_algorithm2_is_representation_independent_and_forgets_the_initial_condition():
    rng = np.random.default_rng(2)
    system = example_25()
    xs, ys = ss.simulate(system, box(1.0, 2, [2, 2]), 6, rng)
    cz = ss.oit_inspired_filter(system, box(1.0, 2), ys, delta=2)
    hp = ss.oit_inspired_filter(system, ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)), ys,
                                delta=2)
    other = ss.oit_inspired_filter(system, box(4.0, 2, [7, 7]), ys, delta=2)
    D = np.vstack([np.eye(2), -np.eye(2), [[1.0, 1.0], [1.0, -1.0]]])
    for k in range(7):
        np.testing.assert_allclose(cz[k].support_many(D), hp[k].support_many(D, path="generic"), atol=1e-5)
    for k in range(2, 7):  # Line 7: F_{k,0}(ℝ²), whatever ⟦x̂_0⟧ was
        reference = ss.filtering_map(system, ss.Reals(2), ys, 0, k)
        np.testing.assert_allclose(cz[k].support_many(D), reference.support_many(D), atol=1e-6)
        np.testing.assert_allclose(other[k].support_many(D), reference.support_many(D), atol=1e-6)
        assert cz[k].contains(xs[k], tol=TOL)


def test_algorithm2_resets_like_line5_before_the_switch():
    system = example_25()
    ys = np.array([[10.0], [11.0], [12.0], [13.0]])
    est = ss.oit_inspired_filter(system, box(1.0, 2), ys, delta=2)
    assert not est[0].is_empty() and not est[1].is_empty()
    dec = analysis.observability_decomposition(system.A_at(0), system.C_at(0))
    expected = ss.filtering_map(system, dec.U @ box(16.0, 2), ys, 0, 0)
    D = np.vstack([np.eye(2), -np.eye(2)])
    np.testing.assert_allclose(est[0].support_many(D), expected.support_many(D), atol=1e-7)


# -- the kept-instance hulls ----------------------------------------------------------------------------
def test_parametric_support_is_a_tight_upper_bound_and_settles_empty_windows():
    rng = np.random.default_rng(4)
    system = analysis.random_observable_system(rng, 3, 2, 2).linear_system()
    xs, ys = ss.simulate(system, box(3.0, 3), 10, rng)
    res = ss.oit_cz_filter(system, box(3.0, 3), ys, delta_bar=2)
    Z = res.estimates[5]
    D = rng.normal(size=(6, 3))
    engine = ParametricSupport(Z.G, Z.A, D, np.isinf(Z.h))
    for k in range(2, 11):
        W = res.estimates[k]
        values = engine.values(W.c, W.b, W.h)
        exact = W.support_many(D)
        assert np.all(values >= exact - 1e-9) and np.allclose(values, exact, atol=1e-6)
    bad = np.array(Z.b)
    bad[-1] += 1e3  # a measurement no trajectory explains
    assert np.all(engine.values(Z.c, bad, Z.h) == -np.inf)


def test_a_warm_session_agrees_with_cold_solves_and_depends_on_its_own_steps_only():
    """A session re-solves each window from the last window's bases: its bounds are the cold
    solves' to 1e-7 of the width, upper bounds of the exact values, and two sessions over the
    same windows give the same bounds bit for bit, whatever an earlier session saw (an empty
    window in the middle drops nothing a later step needs)."""
    rng = np.random.default_rng(11)
    system = analysis.random_observable_system(rng, 4, 2, 2).linear_system()
    xs, ys = ss.simulate(system, box(3.0, 4), 14, rng)
    res = ss.oit_cz_filter(system, box(3.0, 4), ys, delta_bar=3)
    windows = res.estimates[3:]
    Z = windows[0]
    D = np.vstack([np.eye(4), -np.eye(4)])
    engine = ParametricSupport(Z.G, Z.A, D, np.isinf(Z.h))
    first, second = engine.session(), engine.session()
    bad = np.array(Z.b)
    bad[-1] += 1e3
    assert np.all(second.values(Z.c, bad, Z.h) == -np.inf)  # an earlier, infeasible step
    for W in windows:
        warm = first.values(W.c, W.b, W.h)
        again = second.values(W.c, W.b, W.h)
        cold = engine.values(W.c, W.b, W.h)
        exact = W.support_many(D)
        width = np.tile(exact[:4] + exact[4:], 2)
        assert np.all(warm >= exact - 1e-9 * width)
        assert np.all(np.abs(warm - cold) <= 1e-7 * width)
        assert np.array_equal(warm, again)


def test_a_session_asks_the_policys_sequence_backends_and_the_verified_path_takes_the_rest(
        monkeypatch):
    """The windows' solver is chosen by the solver policy ('along time'), not by the engine: a
    sequence backend recorded there is the one asked, and directions it leaves unsettled get the
    set's own verified bounds, equal to what the HiGHS backend's certificate gives to 1e-7 of the
    width."""
    from setsmooth.solvers import backends, parametric, policy

    rng = np.random.default_rng(5)
    system = analysis.random_observable_system(rng, 3, 2, 2).linear_system()
    xs, ys = ss.simulate(system, box(3.0, 3), 8, rng)
    res = ss.oit_cz_filter(system, box(3.0, 3), ys, delta_bar=2)
    Z = res.estimates[4]
    D = np.vstack([np.eye(3), -np.eye(3)])
    engine = ParametricSupport(Z.G, Z.A, D, np.isinf(Z.h))
    assert policy.policy(engine, "along time") == (policy.Attempt("simplex along time"),)
    real = engine.values(Z.c, Z.b, Z.h)
    asked = []

    class Halfway(backends.SEQUENCE_BACKENDS["simplex along time"]):
        def solve(self, j, b, h):  # settles the first half of the directions only
            asked.append(j)
            answer = super().solve(j, b, h)
            return answer if j < 3 else backends.Answer("unsettled", answer.eta, answer.z, "MaxIterations")

    monkeypatch.setitem(policy.POLICIES, "along time", (policy.Attempt("halfway"),))
    monkeypatch.setitem(parametric.SEQUENCE_BACKENDS, "halfway", Halfway)
    session = engine.session()
    for W in res.estimates[2:]:
        values = session.values(W.c, W.b, W.h)
        exact = W.support_many(D)
        width = np.tile(exact[:3] + exact[3:], 2)
        assert np.all(values >= exact - 1e-9 * width)
        assert np.all(np.abs(values - engine.values(W.c, W.b, W.h)) <= 1e-7 * width)
    assert asked == 2 * 7 * list(range(6))  # every direction of every step, the session's and the cold ones
    assert np.all(np.abs(session.values(Z.c, Z.b, Z.h) - real) <= 1e-7 * np.tile(real[:3] + real[3:], 2))


# -- bad input -------------------------------------------------------------------------------------------
def test_bad_arguments_are_named():
    system = example_25()
    ys = np.zeros((5, 1))
    with pytest.raises(ValueError, match="delta_bar"):
        ss.oit_cz_filter(system, box(1.0, 2), ys, delta_bar=0)
    with pytest.raises(ValueError, match="epsilon"):
        ss.oit_cz_filter(system, box(1.0, 2), ys, epsilon=0.0)
    with pytest.raises(ValueError, match="delta"):
        ss.oit_inspired_filter(system, box(1.0, 2), ys, delta=0)
    with pytest.raises(ValueError, match="constrained-zonotope form"):
        ss.oit_cz_filter(system, ss.Ellipsoid(np.zeros(2), np.eye(2)), ys)
    varying = ss.LinearSystem([np.eye(2)] * 5, None, [[1.0, 0.0]], E=[[0.5], [1.0]], W=box(1.0, 1),
                              V=box(1.0, 1))
    with pytest.raises(ValueError, match="time-invariant"):
        ss.oit_cz_filter(varying, box(1.0, 2), ys)
    unstable = ss.LinearSystem([[2.0, 0.0], [0.0, 1.0]], None, [[0.0, 1.0]], E=[[0.5], [1.0]], W=box(1.0, 1),
                               V=box(1.0, 1))
    with pytest.raises(ValueError, match="detectable"):
        ss.oit_cz_filter(unstable, box(1.0, 2), ys)
