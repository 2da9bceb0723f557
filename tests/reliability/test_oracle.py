"""The HiGHS trajectory-LP oracle against brute force, and the random-case generator against the oracle."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import setsmooth as ss

from ..smoothers.polytope_oracle import brute_force_filter_and_smoother
from setsmooth.reliability.oracle import TrajectoryOracle, factor_form
from setsmooth.reliability.random_systems import KINDS, REGIMES, base_case, in_regime, make_cases


def _vertex_hulls(system, X0, ys, upto: int):
    """Interval hulls of x_0..x_upto over the trajectory polytope, by enumerating its vertices.

    Independent of the oracle's formulation: the states are kept as free variables, nothing is
    scaled, and every vertex is found by fixing N − r factors at their bounds and solving the
    equalities (x_0 = G0ξ0 + c0, x_{j+1} = A x_j + B(G_w ξ_w + c_w), y_j = C x_j + D(G_v ξ_v + c_v),
    A_s ξ_s = b_s) for the rest.
    """
    n = system.n
    forms = [("x0", factor_form(X0))] + [("w", factor_form(system.W))] * upto + \
            [("v", factor_form(system.V))] * (upto + 1)
    sizes = [f.G.shape[1] for _, f in forms]
    N = sum(sizes)
    nx = n * (upto + 1)
    starts = np.concatenate([[0], np.cumsum(sizes)]) + nx
    rows, rhs = [], []

    def row_block(r):
        return np.zeros((r, nx + N))

    f0 = forms[0][1]
    Rb = row_block(n)
    Rb[:, :n] = np.eye(n)
    Rb[:, starts[0]:starts[1]] = -f0.G
    rows.append(Rb)
    rhs.append(f0.c)
    for j in range(upto):
        fw = forms[1 + j][1]
        Rb = row_block(n)
        Rb[:, (j + 1) * n:(j + 2) * n] = np.eye(n)
        Rb[:, j * n:(j + 1) * n] = -system.A_at(j)
        Rb[:, starts[1 + j]:starts[2 + j]] = -system.E_at(j) @ fw.G
        rows.append(Rb)
        rhs.append(system.E_at(j) @ fw.c + system.input_term(j))
    for j in range(upto + 1):
        fv = forms[1 + upto + j][1]
        Rb = row_block(system.m)
        Rb[:, j * n:(j + 1) * n] = system.C_at(j)
        Rb[:, starts[1 + upto + j]:starts[2 + upto + j]] = system.F_at(j) @ fv.G
        rows.append(Rb)
        rhs.append(ys[j] - system.F_at(j) @ fv.c)
    for s, (_, f) in enumerate(forms):
        if f.A.shape[0]:
            Rb = row_block(f.A.shape[0])
            Rb[:, starts[s]:starts[s + 1]] = f.A
            rows.append(Rb)
            rhs.append(f.b)
    E, f = np.vstack(rows), np.concatenate(rhs)
    h = np.concatenate([fm.h for _, fm in forms])
    rank = np.linalg.matrix_rank(E)
    n_fixed = nx + N - rank
    points = []
    for fixed in itertools.combinations(range(N), n_fixed):
        fixed_cols = nx + np.array(fixed, dtype=int)
        free = np.setdiff1d(np.arange(nx + N), fixed_cols)
        Ef = E[:, free]
        if np.linalg.matrix_rank(Ef) < free.size:
            continue
        for signs in itertools.product((-1.0, 1.0), repeat=n_fixed):
            z = np.zeros(nx + N)
            z[fixed_cols] = np.array(signs) * h[np.array(fixed)]
            sol, *_ = np.linalg.lstsq(Ef, f - E[:, fixed_cols] @ z[fixed_cols], rcond=None)
            z[free] = sol
            if np.abs(E @ z - f).max() > 1e-9:
                continue
            if np.all(np.abs(z[nx:]) <= h + 1e-9):
                points.append(z[:nx].reshape(upto + 1, n))
    assert points, "the brute force found no vertex: the data are inconsistent"
    P = np.array(points)
    return P.min(axis=0), P.max(axis=0)


def _tiny_system(rng, cz_noise: bool):
    A = np.array([[0.9, 0.4], [-0.3, 0.8]])
    B = np.array([[0.5], [1.0]])
    C = np.array([[1.0, 0.5]])
    W = (ss.ConstrainedZonotope([[0.6, -0.3, 0.2]], [0.05], [[1.0, 1.0, -0.5]], [0.2])
         if cz_noise else ss.Box([-0.5], [0.4]))
    system = ss.LinearSystem(A, None, C, E=B, W=W, V=ss.Box([-0.3], [0.5]))
    X0 = ss.Box([-1.0, -0.5], [1.0, 1.5])
    xs, ys = ss.simulate(system, X0, 2, rng)
    return system, X0, xs, ys


@pytest.mark.parametrize("cz_noise", [False, True], ids=["box_noise", "cz_noise"])
def test_oracle_hulls_equal_vertex_enumeration_of_the_trajectory_polytope(cz_noise):
    system, X0, xs, ys = _tiny_system(np.random.default_rng(3), cz_noise)
    oracle = TrajectoryOracle(system, X0, ys)
    s_lo, s_hi = oracle.smoothed_hulls()
    f_lo, f_hi = oracle.filtered_hulls()
    v_lo, v_hi = _vertex_hulls(system, X0, ys, upto=2)
    np.testing.assert_allclose(s_lo, v_lo, atol=1e-9)
    np.testing.assert_allclose(s_hi, v_hi, atol=1e-9)
    for k in range(3):
        lo, hi = _vertex_hulls(system, X0, ys, upto=k)
        np.testing.assert_allclose(f_lo[k], lo[k], atol=1e-9)
        np.testing.assert_allclose(f_hi[k], hi[k], atol=1e-9)
    assert np.all(s_lo <= xs + 1e-12) and np.all(xs <= s_hi + 1e-12)


def test_oracle_hulls_equal_the_halfspace_polytope_brute_force_over_six_steps():
    system = ss.LinearSystem([[0.8, 0.5], [-0.4, 0.9]], None, [[1.0, 0.0], [0.4, 1.0]], E=[[1.0], [0.3]],
                             W=ss.Box([-0.4], [0.6]), V=ss.Box([-0.5, -0.2], [0.3, 0.4]))
    X0 = ss.Box([-2.0, -1.0], [1.0, 2.0])
    _, ys = ss.simulate(system, X0, 6, np.random.default_rng(11))
    posts, smoothed = brute_force_filter_and_smoother(
        system.A_at(0), system.E_at(0), system.C_at(0), system.W.lo, system.W.hi, system.V.lo, system.V.hi,
        X0.lo, X0.hi, ys)
    oracle = TrajectoryOracle(system, X0, ys)
    f_lo, f_hi = oracle.filtered_hulls()
    s_lo, s_hi = oracle.smoothed_hulls()
    np.testing.assert_allclose(f_lo, [P.min(axis=0) for P in posts], atol=1e-8)
    np.testing.assert_allclose(f_hi, [P.max(axis=0) for P in posts], atol=1e-8)
    np.testing.assert_allclose(s_lo, [P.min(axis=0) for P in smoothed], atol=1e-8)
    np.testing.assert_allclose(s_hi, [P.max(axis=0) for P in smoothed], atol=1e-8)


def test_warm_started_oracle_equals_cold_linprog_on_a_random_case():
    case = base_case(0, 8, T_range=(10, 12), n_range=(2, 3))
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    rng = np.random.default_rng(0)
    for k in (0, case.T // 2, case.T):
        d = rng.normal(size=case.system.n)
        for upto in (k, case.T):
            warm = oracle.support(k, d, upto)
            assert warm == pytest.approx(oracle.support_linprog(k, d, upto), rel=1e-9, abs=1e-9)


def test_generator_is_reproducible_and_covers_every_kind():
    a = make_cases(5, seed=4, regimes=("scale1",), T_range=(10, 11), n_range=(2, 3))
    b = make_cases(5, seed=4, regimes=("scale1",), T_range=(10, 11), n_range=(2, 3))
    assert [c.kind for c in a] == list(KINDS)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x.ys, y.ys)
        np.testing.assert_array_equal(x.system.A_at(0), y.system.A_at(0))
    rho = max(abs(np.linalg.eigvals(a[1].system.A_at(0))))
    assert 1.02 <= rho <= 1.15
    assert np.linalg.matrix_rank(a[2].system.A_at(0)) < a[2].system.n
    assert np.linalg.matrix_rank(a[3].system.C_at(0)) < a[3].system.m
    assert a[4].system.q != a[4].system.m
    # drss is seeded through NumPy's global state, which must come back untouched.
    state = np.random.get_state()[1].copy()
    base_case(4, 0, T_range=(10, 11), n_range=(2, 3))
    np.testing.assert_array_equal(np.random.get_state()[1], state)


@pytest.mark.parametrize("index", [1, 7])
def test_every_regime_is_an_exact_change_of_units_of_the_same_exact_sets(index):
    """The oracle's hulls move with the regime (×s, +o) and contain the simulated truth."""
    base = base_case(0, index, T_range=(10, 12), n_range=(2, 3))
    ref_lo, ref_hi = TrajectoryOracle(base.system, base.X0, base.ys).smoothed_hulls()
    width = (ref_hi - ref_lo).max() + 1.0
    for regime in REGIMES:
        case = in_regime(base, regime)
        lo, hi = TrajectoryOracle(case.system, case.X0, case.ys).smoothed_hulls()
        back_lo = (lo - case.offset) / case.scale
        back_hi = (hi - case.offset) / case.scale
        assert np.abs(back_lo - ref_lo).max() <= 1e-8 * width
        assert np.abs(back_hi - ref_hi).max() <= 1e-8 * width
        slack = 1e-9 * case.scale * width + 1e-15 * np.abs(case.xs).max()
        assert np.all(lo - slack <= case.xs) and np.all(case.xs <= hi + slack)
