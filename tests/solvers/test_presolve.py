"""The fast path's presolve: one set, many representations, the same answers (or a SolverError)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth.solvers.presolve import presolve


def highs_support(Z: ss.ConstrainedZonotope, d: np.ndarray) -> float:
    """Independent value: HiGHS on max dᵀ(Gξ + c) s.t. Aξ = b, |ξ| ≤ h."""
    G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    bounds = [(None, None) if np.isinf(h) else (-h, h) for h in Z.h]
    res = linprog(-(G.T @ d), A_eq=A, b_eq=Z.b, bounds=bounds, method="highs")
    assert res.status == 0
    return float(d @ Z.c - res.fun)


def random_cz(seed: int, n: int = 3, ng: int = 6, nc: int = 2) -> ss.ConstrainedZonotope:
    rng = np.random.default_rng(seed)
    G, A = rng.standard_normal((n, ng)), rng.standard_normal((nc, ng))
    return ss.ConstrainedZonotope(G, rng.standard_normal(n), A=A, b=A @ rng.uniform(-0.6, 0.6, ng),
                                  h=rng.uniform(0.5, 2.0, ng))


def test_a_row_scaled_by_1e_minus_12_is_not_dropped():
    # The example: ξ1 − ξ2 = 1/2 written with coefficients 1e-12; exact support 1.5, not 2.
    Z = ss.ConstrainedZonotope([[1.0, 1.0]], [0.0], A=[[1e-12, -1e-12]], b=[0.5e-12])
    assert Z.support([1.0]) == pytest.approx(1.5, abs=1e-8)
    assert Z.support([-1.0]) == pytest.approx(1.5, abs=1e-8)
    assert Z.support([1.0], certified=True) >= 1.5


@pytest.mark.parametrize("how", ["rows", "factors", "coordinates"])
@pytest.mark.parametrize("seed", range(4))
def test_a_set_rescaled_by_1e_pm12_gives_the_same_support_values(how, seed):
    Z = random_cz(seed)
    rng = np.random.default_rng(100 + seed)
    if how == "rows":
        s = rng.choice([1e-12, 1e12], Z.nc)
        W = ss.ConstrainedZonotope(Z.G, Z.c, A=Z.A * s[:, None], b=Z.b * s, h=Z.h)
        M = np.eye(Z.dim)
    elif how == "factors":  # ξ_j → ξ_j / s_j: the same set
        s = rng.choice([1e-12, 1e12], Z.ng)
        W = ss.ConstrainedZonotope(Z.G * s, Z.c, A=Z.A * s, b=Z.b, h=Z.h / s)
        M = np.eye(Z.dim)
    else:  # W = M Z, queried in M⁻ᵀd
        M = np.diag(rng.choice([1e-12, 1e12], Z.dim))
        W = ss.ConstrainedZonotope(M @ Z.G, M @ Z.c, A=Z.A, b=Z.b, h=Z.h)
    for d in rng.standard_normal((6, Z.dim)):
        exact = highs_support(Z, d)
        dw = np.linalg.solve(M.T, d)
        scale = 1.0 + np.abs(Z.G.T @ d) @ Z.h + abs(d @ Z.c)
        assert W.support(dw) == pytest.approx(exact, abs=1e-7 * scale)
        assert W.support(dw, certified=True) >= exact - 1e-12 * scale


def test_free_factors_scaled_by_1e12_keep_the_set_bounded():
    # ξ3 free but tied to the bounded ones: ξ3 = ξ1 + ξ2; scaled by 1e12 it is the same set.
    G = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, -1.0]])
    A = np.array([[1.0, 1.0, -1.0]])
    h = np.array([1.0, 1.0, np.inf])
    Z = ss.ConstrainedZonotope(G, [0.0, 0.0], A=A, b=[0.0], h=h)
    s = np.array([1.0, 1.0, 1e12])
    W = ss.ConstrainedZonotope(G * s, [0.0, 0.0], A=A * s, b=[0.0], h=h)
    for d in np.random.default_rng(0).standard_normal((5, 2)):
        assert np.isfinite(W.support(d))
        assert W.support(d) == pytest.approx(Z.support(d), abs=1e-7)


def test_presolve_drops_fixed_factors_zero_rows_and_dependent_rows():
    A = sp.csc_matrix(np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 5.0], [0.0, 0.0, 0.0]]))
    b = np.array([1.0, 2.0, 0.0, 0.0])
    pre = presolve(A, b, np.array([1.0, 2.0, 0.0]), dependent=True)
    assert pre.cols.tolist() == [0, 1]  # h = 0: ξ3 fixed at 0
    assert len(pre.rows) == 1 and not pre.empty  # rows 2 = 2·row 1; rows 3, 4 zero once ξ3 is gone
    assert np.abs(pre.A.toarray()).max() == pytest.approx(1.0)  # unit ∞-norm rows
    inconsistent = presolve(A, np.array([1.0, 2.5, 0.0, 0.0]), np.ones(3), dependent=True)
    assert inconsistent.empty
    zero_row = presolve(A, np.array([1.0, 2.0, 0.0, 3.0]), np.ones(3), dependent=False)
    assert zero_row.empty  # 0 = 3


def test_programs_beyond_the_dense_limit_skip_the_dependent_rows_and_still_answer(monkeypatch):
    """Above `DEPENDENT_DENSE_MAX` the dense Gram/QR of the rows is not formed (its memory grows as
    m·p): no dependent row is looked for, and the answers still come (HiGHS's presolve handles the
    dependent rows in the fallback)."""
    import setsmooth.solvers.presolve as presolve_module

    A = sp.csc_matrix(np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 1.0, 5.0]]))
    b = np.array([1.0, 2.0, 0.5])
    monkeypatch.setattr(presolve_module, "DEPENDENT_DENSE_MAX", 5)
    monkeypatch.setattr(presolve_module, "_well_conditioned", lambda *a: pytest.fail("dense test run"))
    pre = presolve(A, b, np.ones(3), dependent=True)
    assert not pre.dependent_checked and len(pre.rows) == 3
    Z = ss.ConstrainedZonotope(np.eye(3), np.zeros(3), A=A.toarray(), b=b)
    D = np.vstack([np.eye(3), -np.eye(3)])
    values = Z.support_many(D, certified=True)
    np.testing.assert_allclose(values, [highs_support(Z, d) for d in D], atol=1e-7)


def test_dependent_rows_make_no_difference_to_the_answers():
    Z = random_cz(7)
    A = np.vstack([Z.A, 3.0 * Z.A[:1] - 1e-3 * Z.A[1:2]])
    b = np.concatenate([Z.b, 3.0 * Z.b[:1] - 1e-3 * Z.b[1:2]])
    W = ss.ConstrainedZonotope(Z.G, Z.c, A=A, b=b, h=Z.h)
    D = np.random.default_rng(1).standard_normal((6, Z.dim))
    np.testing.assert_allclose(W.support_many(D), [highs_support(Z, d) for d in D], atol=1e-7)
    assert not W.is_empty()


@pytest.mark.parametrize("seed", range(3))
def test_members_of_a_factor_rescaled_set_are_accepted(seed):
    Z = random_cz(seed)
    rng = np.random.default_rng(200 + seed)
    s = rng.choice([1e-12, 1e12], Z.ng)
    W = ss.ConstrainedZonotope(Z.G * s, Z.c, A=Z.A * s, b=Z.b, h=Z.h / s)
    for d in rng.standard_normal((3, Z.dim)):
        boundary = Z.support_point(d)
        assert W.contains(boundary)
        assert not W.contains(boundary + 1e-3 * d / np.linalg.norm(d))


def test_a_trajectory_set_presolves_to_the_same_program_at_every_noise_scale():
    # Scaling every noise set, the states and the measurements by s is a change of units: the
    # presolved program must not see it. The free factors (states) take the units of the rows with
    # bounded entries; measured by all rows, the noise-free dynamics rows pinned them at their raw
    # scale (1e3 at noise scale 1e3), where Clarabel stopped with a loose dual.
    from setsmooth.reliability.random_systems import base_case, in_regime

    base = base_case(2026, 0, T_range=(10, 16), n_range=(2, 4))
    programs = []
    for regime in ("scale1", "scale1e+03", "scale1e-06"):
        case = in_regime(base, regime)
        S = ss.optimal_smoother(case.system, case.X0, case.ys, method="trajectory")[3]
        programs.append(S.factors.presolved)
    first = programs[0]
    assert first.has_free
    for pre in programs[1:]:
        assert abs(pre.A - first.A).max() <= 1e-14
        np.testing.assert_allclose(pre.b, first.b, atol=1e-13)


def test_the_rows_are_called_independent_exactly_when_scipys_cholesky_of_the_shifted_gram_exists():
    # `_well_conditioned` calls LAPACK's potrf directly; scipy.linalg.cholesky (the former call)
    # must reach the same verdict on well-conditioned, nearly dependent and dependent rows.
    import scipy.linalg

    from setsmooth.solvers.presolve import INDEPENDENT_RCOND, _well_conditioned
    from setsmooth.solvers.small_products import gram

    rng = np.random.default_rng(29)
    verdicts = set()
    for trial in range(60):
        m, p = int(rng.integers(2, 6)), int(rng.integers(6, 12))
        A = rng.standard_normal((m, p))
        if trial % 3 == 1:
            A[-1] = A[0] + 10.0 ** -rng.uniform(2, 9) * rng.standard_normal(p)  # nearly dependent
        elif trial % 3 == 2:
            A[-1] = 2.0 * A[0]  # dependent
        A /= np.abs(A).max(axis=1, keepdims=True)
        M = sp.csc_matrix(A)
        rows = np.arange(m)
        G = gram(M)
        G[np.diag_indices(m)] -= (INDEPENDENT_RCOND ** 2 + 4 * m * np.finfo(float).eps) \
            * float(np.abs(G).sum(axis=1).max())
        try:
            scipy.linalg.cholesky(G, lower=True, check_finite=False)
            expected = True
        except np.linalg.LinAlgError:
            expected = False
        assert _well_conditioned(M, rows) is expected
        verdicts.add(expected)
    assert verdicts == {True, False}
