"""Every fast-path support value is checked a posteriori against its own certified bound.

The certified weak-duality bound U and the solver's value L of the same solve bracket the exact
support, so U − L bounds the error of both; a bracket wider than ``SUPPORT_GAP_TOL`` of the set's
width is solved again by the simplex method (`CZProgram._verified`). These tests make Clarabel stop
early on purpose (loose tolerances) and check that the answers stay exact to that accuracy.
"""

from __future__ import annotations

import clarabel
import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth import tolerances as tol
from setsmooth.solvers import clarabel_lp, policy
from setsmooth.solvers.cz_program import CZProgram

from setsmooth.reliability.random_systems import base_case, in_regime


#: Clarabel answers every direction first (the simplex method answers first as built): the check
#: under test is the same for either answer.
INTERIOR_FIRST = (policy.Attempt("clarabel"), policy.Attempt("simplex")) + policy.FALLBACKS


def interior_first(monkeypatch) -> None:
    monkeypatch.setitem(policy.POLICIES, "bracketed", INTERIOR_FIRST)


def exact_hull(Z: ss.ConstrainedZonotope) -> tuple[np.ndarray, np.ndarray]:
    """The interval hull of Z by HiGHS's LPs on its factor set (an independent computation)."""
    G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    bounds = [(None, None) if np.isinf(h) else (-h, h) for h in Z.h]
    out = []
    for d in np.vstack([np.eye(Z.dim), -np.eye(Z.dim)]):
        res = linprog(-(G.T @ d), A_eq=A, b_eq=Z.b, bounds=bounds, method="highs",
                      options=dict(primal_feasibility_tolerance=1e-10,
                                   dual_feasibility_tolerance=1e-10))
        assert res.status == 0
        out.append(d @ Z.c - res.fun)
    out = np.array(out)
    return -out[Z.dim:], out[:Z.dim]


def loose_settings(*, refine: bool = False) -> clarabel.DefaultSettings:
    """Clarabel stopping at a relative gap of 1e-4: answers off by far more than 1e-6."""
    s = clarabel.DefaultSettings()
    s.verbose = False
    s.iterative_refinement_enable = refine
    s.tol_gap_abs = s.tol_gap_rel = s.tol_feas = 1e-4
    return s


def smoothed_sets(regime: str):
    case = in_regime(base_case(2026, 0, T_range=(10, 16), n_range=(2, 4)), regime)
    return ss.optimal_smoother(case.system, case.X0, case.ys, method="trajectory")


@pytest.mark.parametrize("regime", ["scale1", "offset1e+06"])
def test_hulls_stay_exact_when_clarabel_stops_early(monkeypatch, regime):
    monkeypatch.setattr(clarabel_lp, "settings", loose_settings)
    interior_first(monkeypatch)
    sets = smoothed_sets(regime)
    for k in (3, len(sets) - 1):
        S = sets[k]
        lo_x, hi_x = exact_hull(S)
        width = hi_x - lo_x
        plain = S.interval_hull(certified=False)
        cert = S.interval_hull(certified=True)
        limit = 2 * tol.SUPPORT_GAP_TOL * width + 1e-11 * (np.abs(lo_x) + np.abs(hi_x))
        assert np.all(np.abs(plain.lo - lo_x) <= limit) and np.all(np.abs(plain.hi - hi_x) <= limit)
        assert np.all(cert.lo <= lo_x + 1e-12 * np.abs(lo_x)) and np.all(cert.hi >= hi_x - 1e-12 * np.abs(hi_x))
        assert np.all(cert.hi - hi_x <= limit) and np.all(lo_x - cert.lo <= limit)


def test_without_the_check_the_loose_solver_is_visibly_off(monkeypatch):
    # The premise of the test above: the loose settings do produce wrong values when unchecked.
    monkeypatch.setattr(clarabel_lp, "settings", loose_settings)
    interior_first(monkeypatch)
    monkeypatch.setattr(CZProgram, "_gap_tolerance",
                        staticmethod(lambda D, lo, up, rounding=None, partner=None:
                                     np.full(D.shape[0], np.inf)))
    S = smoothed_sets("scale1")[3]
    lo_x, hi_x = exact_hull(S)
    plain = S.interval_hull(certified=False)
    err = np.maximum(np.abs(plain.lo - lo_x), np.abs(plain.hi - hi_x)) / (hi_x - lo_x)
    assert err.max() > 1e-6


def test_the_gap_tolerance_is_relative_to_the_width_when_both_directions_are_asked():
    D = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]])
    lower = np.array([1e6 + 1.0, -1e6 + 1.0, 5.0])
    upper = lower + 1e-3
    t = CZProgram._gap_tolerance(D, lower, upper)
    magnitude = np.abs(lower) + np.abs(upper)
    np.testing.assert_allclose(t[:2], tol.SUPPORT_GAP_TOL * 2.0 + tol.SUPPORT_GAP_FLOOR * magnitude[:2])
    np.testing.assert_allclose(t[2], (tol.SUPPORT_GAP_TOL + tol.SUPPORT_GAP_FLOOR) * magnitude[2])
    # the certificate's own rounding allowance is added four times
    own = np.array([1e-9, 2e-9, 0.0])
    np.testing.assert_allclose(CZProgram._gap_tolerance(D, lower, upper, own) - t, 4.0 * own)
