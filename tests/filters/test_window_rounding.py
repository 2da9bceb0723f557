"""The OIT-CZ window's rounding charges (`Window.charged_data`) against exact rational arithmetic.

The window's G, A, nominal trajectory and right-hand side are recomputed with `fractions.Fraction`
from the same floating-point data; every charge must cover the difference between the stored window and
the exact one: |c − c*| + |G − G*|·h ≤ pad (+ pad_free per unit of the free factors), and the same for
the rows with A, b and slack.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.filters._window import Window
from setsmooth.solvers.parametric import ParametricSupport


def _frac(M) -> list:
    M = np.atleast_1d(np.asarray(M, dtype=float))
    if M.ndim == 1:
        return [Fraction(float(v)) for v in M]
    return [[Fraction(float(v)) for v in row] for row in M]


def _mat(X, Y):
    return [[sum((X[i][t] * Y[t][j] for t in range(len(Y))), Fraction(0)) for j in range(len(Y[0]))]
            for i in range(len(X))]


def _vec(X, v):
    return [sum((X[i][t] * v[t] for t in range(len(v))), Fraction(0)) for i in range(len(X))]


def _exact_window(system, d, M, ys, k, c_p):
    """G*, A* (measurement rows only), c*, b* (measurement rows) of the window, exactly."""
    A, B, C, D = (_frac(f(0)) for f in (system.A_at, system.E_at, system.C_at, system.F_at))
    # the noise sets as the window uses them (a box converted with charges, materialized)
    Wz, Vz = (S.to_constrained_zonotope() for S in (system.W, system.V))
    Wz, Vz = (Z.materialized() if Z._charged else Z for Z in (Wz, Vz))
    Gw, Gv, cw, cv = _frac(Wz.G), _frac(Vz.G), _frac(Wz.c), _frac(Vz.c)
    Mf = _frac(M)
    n = system.n
    powers = [[[Fraction(int(i == j)) for j in range(n)] for i in range(n)]]
    for _ in range(d):
        powers.append(_mat(A, powers[-1]))
    BG = _mat(B, Gw)
    G = [row[:] for row in _mat(powers[d], Mf)]
    for l in range(d):
        blk = _mat(powers[d - 1 - l], BG)
        for i in range(n):
            G[i] += blk[i]
    qv = len(Gv[0])
    meas = []
    for j in range(d + 1):
        CP = _mat(C, powers[j])
        rows = [r[:] for r in _mat(CP, Mf)]
        for l in range(d):
            blk = _mat(_mat(C, powers[j - 1 - l]), BG) if l < j else [[Fraction(0)] * len(BG[0])] * len(C)
            for i in range(len(C)):
                rows[i] += blk[i]
        DGv = _mat(D, Gv)
        for jj in range(d + 1):
            blk = DGv if jj == j else [[Fraction(0)] * qv] * len(C)
            for i in range(len(C)):
                rows[i] += blk[i]
        meas.extend(rows)
    x = _frac(c_p)
    i0 = k - d
    b = []
    Dcv = _vec(D, cv)
    Bcw = _vec(B, cw)
    for j in range(d + 1):
        Cx = _vec(C, x)
        y = _frac(ys[i0 + j])
        b.extend(y[r] - Dcv[r] - Cx[r] for r in range(len(Cx)))
        if j < d:
            Ax = _vec(A, x)
            u = _frac(system.input_term(i0 + j))
            x = [Ax[r] + Bcw[r] + u[r] for r in range(n)]
    return G, meas, x, b


def _system(rng, n, m, offset):
    A = rng.normal(size=(n, n)) * 0.6
    B = rng.normal(size=(n, 1))
    C = rng.normal(size=(m, n))
    W = ss.Box([-0.3], [0.7])
    V = ss.Box(-0.2 * np.ones(m), 0.9 * np.ones(m))
    u = (np.eye(n) - A) @ np.full(n, offset)  # keeps a state offset constant
    return ss.LinearSystem(A, np.eye(n), C, E=B, W=W, V=V, u=lambda k: u)


@pytest.mark.parametrize("seed,offset,free", [(0, 1e6, True), (1, 1e6, False), (2, 1.0, True),
                                              (3, 3e4, False)])
def test_window_charges_cover_the_exact_window(seed, offset, free):
    rng = np.random.default_rng(seed)
    n, m, d = 3, 2, 3
    system = _system(rng, n, m, offset)
    X0 = ss.Box(np.full(n, offset - 1), np.full(n, offset + 1))
    xs, ys = ss.simulate(system, X0, 8, rng)
    M = np.eye(n) if free else rng.normal(size=(n, n))
    window = Window(system, d, M)
    k = 6
    c_p = xs[k - d] + rng.uniform(-0.5, 0.5, n) * (0.0 if free else 1.0)
    h_p = np.full(n, np.inf) if free else np.full(n, 2.0)
    c, b, h, charges = window.charged_data(ys, k, c_p, h_p)
    G_ex, A_ex, c_ex, b_ex = _exact_window(system, d, M, ys, k, c_p)

    def covered(stored_M, exact_M, stored_v, exact_v, charge, charge_free):
        for i in range(len(exact_v)):
            bounded = abs(Fraction(float(stored_v[i])) - exact_v[i])
            per_free = Fraction(0)
            for j in range(len(exact_M[i])):
                diff = abs(Fraction(float(stored_M[i, j])) - exact_M[i][j])
                if np.isinf(h[j]):
                    per_free += diff
                else:
                    bounded += diff * Fraction(float(h[j]))
            assert bounded <= Fraction(float(0.0 if charge is None else charge[i])), (i, float(bounded))
            assert per_free <= Fraction(float(0.0 if charge_free is None else charge_free[i])), i

    covered(window.G, G_ex, c, c_ex, charges["pad"], charges["pad_free"])
    rows = slice(window.meas_row, None)
    slack = None if charges["slack"] is None else charges["slack"][rows]
    slack_free = None if charges["slack_free"] is None else charges["slack_free"][rows]
    covered(window.A[rows], A_ex, b[rows], b_ex, slack, slack_free)
    # the noise rows are exact copies: charged nothing
    for name in ("slack", "slack_free"):
        if charges[name] is not None:
            assert not charges[name][:window.meas_row].any()
    if offset >= 1e4:  # the nominal trajectory at 1e6 is rounded: the charges are not all zero
        assert charges["pad"] is not None and charges["slack"] is not None


def test_a_window_of_exact_matrices_charges_only_the_steps_rounding():
    system = ss.LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]],
                             W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    ys = np.array([[1.0], [2.0], [4.0], [7.0], [11.0]])
    window = Window(system, 2, np.eye(2))
    assert window._dG is None and window._dA is None  # exact powers and products: no matrix charge
    *_, charges = window.charged_data(ys, 3, np.zeros(2), np.full(2, np.inf))
    assert charges["pad_free"] is None and charges["slack_free"] is None
    # the exact nominal steps are charged at most the extended format's bound of their terms
    assert charges["pad"].max() < 1e-16 and charges["slack"].max() < 1e-16


def test_certified_window_hulls_carry_the_charges():
    """ParametricSupport with the charges: above its value without them by at most the charges'
    effect, and every bound holds against the exact window's support at a feasible point (the truth).
    With the least-squares prior centre (`Window.centred_prior`) the engine's values agree with the CZ
    path's to 1e-6 of the unit width; from c_p = 0 they were up to 4e-3 looser at states 1e6 (the
    interior-point multipliers' reduced costs times a free-factor bound β ~ 1e6)."""
    rng = np.random.default_rng(7)
    n, m, d = 3, 2, 3
    system = _system(rng, n, m, 1e6)
    X0 = ss.Box(np.full(n, 1e6 - 1), np.full(n, 1e6 + 1))
    xs, ys = ss.simulate(system, X0, 10, rng)
    window = Window(system, d, np.eye(n))
    D = np.vstack([np.eye(n), -np.eye(n)])
    engine = ParametricSupport(window.G, window.A, D, window.free(n))
    for k in range(d, 11):
        c, b, h, charges = window.charged_data(ys, k, window.centred_prior(ys, k), np.full(n, np.inf))
        plain = engine.values(c, b, h)
        charged = engine.values(c, b, h, **charges)
        assert np.all(charged >= plain)
        assert np.all(charged - plain <= 1e-6)
        assert np.all(D @ xs[k] <= charged)
        Z = window.estimate_from(c, b, h, **charges)
        assert np.all(D @ xs[k] <= Z.support_many(D, certified=True))
        np.testing.assert_allclose(Z.support_many(D, certified=True), charged, rtol=0, atol=1e-6)
        # the same set from any prior centre: support values agree with c_p = 0's
        c0, b0, h0, ch0 = window.charged_data(ys, k, np.zeros(n), np.full(n, np.inf))
        Z0 = window.estimate_from(c0, b0, h0, **ch0)
        np.testing.assert_allclose(Z0.support_many(D), Z.support_many(D), rtol=0, atol=1e-6)
