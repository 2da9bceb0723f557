"""The solver layer: status policy, SolverError, the CZ fast path's LPs, the generic path, tolerances."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss
from setsmooth import solvers
from setsmooth import tolerances as tol


def nontrivial_cz(seed=0, ng=8, nc=3):
    """A fresh CZ (no cached solver instance), feasible by construction."""
    rng = np.random.default_rng(seed)
    G, A = rng.standard_normal((3, ng)), rng.standard_normal((nc, ng))
    xi0 = rng.uniform(-0.5, 0.5, ng)
    return ss.ConstrainedZonotope(G, rng.uniform(-1, 1, 3), A=A, b=A @ xi0)


def patched_settings(monkeypatch, **overrides):
    original = solvers.clarabel_lp.settings

    def settings(**kwargs):
        s = original(**kwargs)
        for name, value in overrides.items():
            setattr(s, name, value)
        return s

    monkeypatch.setattr(solvers.clarabel_lp, "settings", settings)


# -- status policy ---------------------------------------------------------------------------------

def test_a_stalled_interior_point_solve_is_settled_by_the_verified_simplex_fallback(monkeypatch):
    exact = nontrivial_cz().support_many(np.eye(3))
    patched_settings(monkeypatch, max_iter=1)
    np.testing.assert_allclose(nontrivial_cz().support_many(np.eye(3)), exact, atol=1e-8)


def test_a_stalled_phase_one_program_is_settled_by_the_simplex_method(monkeypatch):
    """The elastic phase-one program is always feasible and bounded: where Clarabel stalls on it,
    HiGHS decides emptiness (both ways) instead of a SolverError."""
    patched_settings(monkeypatch, max_iter=1)
    assert not nontrivial_cz().is_empty()
    empty = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0], [1.0, -1.0]], b=[1.5, 1.2])
    assert empty.is_empty()  # ξ1 = 1.35 > 1


def test_a_stalled_membership_program_is_settled_by_the_simplex_method(monkeypatch):
    Z = nontrivial_cz()
    member = Z.support_point([1.0, 0.5, 0.0])
    outside = member + 0.1 * np.array([1.0, 0.5, 0.0])
    patched_settings(monkeypatch, max_iter=1)
    assert nontrivial_cz().contains(member) and not nontrivial_cz().contains(outside)


def _no_highs_fallback(monkeypatch):
    """Make every HiGHS backend (simplex and interior-point method) fail, as on data no solver
    settles."""
    from setsmooth.solvers.backends import BACKENDS, Answer

    for name in ("simplex", "simplex cold", "interior"):
        monkeypatch.setitem(BACKENDS, name, lambda pre, q, batch=None: Answer(
            "unsettled", np.full(pre.A.shape[1], np.nan), np.full(pre.A.shape[0], np.nan),
            "MaxIterations"))
    monkeypatch.setattr(solvers.phase_one, "simplex_inequalities", lambda q, rows, r: (
        "MaxIterations", np.full(rows.shape[1], np.nan), np.full(rows.shape[0], np.nan)))
    monkeypatch.setattr(solvers.recession, "simplex_box_equalities", lambda q, A: (
        "MaxIterations", np.full(A.shape[1], np.nan)))


def test_a_solver_stopped_early_raises_solver_error_carrying_its_status(monkeypatch):
    patched_settings(monkeypatch, max_iter=1)
    _no_highs_fallback(monkeypatch)
    Z = nontrivial_cz()
    with pytest.raises(ss.SolverError, match="MaxIterations") as info:
        Z.support([1.0, 1.0, 0.0])
    assert info.value.status == "MaxIterations"
    assert isinstance(info.value, RuntimeError)
    with pytest.raises(ss.SolverError) as info:
        nontrivial_cz().is_empty()
    assert info.value.status == "MaxIterations"


def test_a_generic_program_stopped_early_raises_clarabels_status_and_the_program_kind(monkeypatch):
    patched_settings(monkeypatch, max_iter=1)
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2))
    with pytest.raises(ss.SolverError) as info:
        E.support([1.0, 0.0], path="generic")
    assert info.value.status == "MaxIterations"  # Clarabel's name, not CVXPY's 'user_limit'
    assert info.value.kind == "support"
    assert "generic path" in str(info.value)


def test_a_certified_value_bounds_the_exact_support_even_at_reduced_accuracy(monkeypatch):
    exact = nontrivial_cz().support([1.0, 1.0, 0.0])
    patched_settings(monkeypatch, max_iter=5, reduced_tol_gap_abs=1e-2, reduced_tol_gap_rel=1e-2,
                     reduced_tol_feas=1e-2)
    _no_highs_fallback(monkeypatch)  # no fallback settles it
    assert nontrivial_cz().support([1.0, 1.0, 0.0], certified=True) >= exact
    with pytest.raises(ss.SolverError) as info:
        nontrivial_cz().support([1.0, 1.0, 0.0])  # the unverified primal value is refused
    assert info.value.status == "AlmostSolved"


def test_solver_error_message_names_the_status_and_the_context():
    err = ss.SolverError("NumericalError", "computing something")
    assert err.status == "NumericalError"
    assert "'NumericalError'" in str(err) and "computing something" in str(err)


def test_solver_error_carries_the_program_kind_and_survives_pickling():
    import pickle

    err = ss.SolverError("InsufficientProgress", "deciding emptiness", kind="emptiness")
    assert err.kind == "emptiness" and "emptiness program" in str(err)
    again = pickle.loads(pickle.dumps(err))
    assert (again.status, again.context, again.kind) == ("InsufficientProgress",
                                                         "deciding emptiness", "emptiness")
    assert ss.SolverError("MaxIterations").kind is None  # the positional signature still works


# -- solve_lp --------------------------------------------------------------------------------------

def test_solve_lp_reports_optimal_infeasible_and_unbounded():
    # min x subject to x = 1 (equality) and x ≤ 2
    A = sp.csc_matrix(np.array([[1.0], [1.0]]))
    sol = solvers.solve_lp(np.array([1.0]), A, np.array([1.0, 2.0]), 1, 1, "test")
    assert sol.status == "optimal" and sol.x[0] == pytest.approx(1.0)
    # x ≤ 0 and −x ≤ −1
    A = sp.csc_matrix(np.array([[1.0], [-1.0]]))
    assert solvers.solve_lp(np.array([0.0]), A, np.array([0.0, -1.0]), 0, 2, "t").status \
        == "infeasible"
    # min −x subject to x ≥ 0
    A = sp.csc_matrix(np.array([[-1.0]]))
    assert solvers.solve_lp(np.array([-1.0]), A, np.array([0.0]), 0, 1, "t").status == "unbounded"


def test_solve_lp_without_constraints_is_bounded_only_for_a_zero_objective():
    empty = sp.csc_matrix((0, 2))
    assert solvers.solve_lp(np.zeros(2), empty, np.zeros(0), 0, 0, "t").status == "optimal"
    assert solvers.solve_lp(np.ones(2), empty, np.zeros(0), 0, 0, "t").status == "unbounded"


# -- the CZ fast path ------------------------------------------------------------------------------

def test_maps_translations_and_projections_of_a_cz_share_its_factor_set():
    Z = nontrivial_cz()
    factors = Z.factors
    assert (np.ones((2, 3)) @ Z)._factors is factors
    assert (Z + np.ones(3))._factors is factors
    assert Z.project([0, 2])._factors is factors
    assert Z.is_empty() is False
    assert factors._empty is False  # the verdict is cached for every sharer


def test_the_factor_set_of_a_cz_with_contradictory_constraints_is_empty():
    factors = solvers.FactorConstraints(np.array([[1.0, 0.0], [1.0, 0.0]]), np.array([0.5, -0.5]),
                                        np.ones(2))
    assert factors.is_empty()


def test_unbounded_objectives_are_those_not_cancelled_on_the_free_factors():
    # ξ1 free, ξ2 ∈ [−1, 1], ξ1 − ξ2 = 0: the free factor is pinned, the set is bounded.
    pinned = solvers.FactorConstraints(np.array([[1.0, -1.0]]), np.zeros(1), np.array([np.inf, 1.0]))
    g = np.array([[1.0, 0.0], [-3.0, 2.0]])
    assert not pinned.unbounded_objectives(g, "t").any()
    # ξ1, ξ2 free with ξ1 − ξ2 = 0: the line ξ1 = ξ2; objectives (1, −1) vanish on it, (1, 0) do not.
    line = solvers.FactorConstraints(np.array([[1.0, -1.0]]), np.zeros(1), np.full(2, np.inf))
    flags = line.unbounded_objectives(np.array([[1.0, -1.0], [1.0, 0.0]]), "t")
    assert flags.tolist() == [False, True]


def test_a_support_call_records_clarabels_solve_time():
    Z = nontrivial_cz()
    Z.support_many(np.eye(3))
    assert Z._program.last_solve_time > 0.0


# -- the generic path ------------------------------------------------------------------------------

def test_the_generic_program_is_compiled_once_and_reused():
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2)) & ss.Box([-0.5, -2], [0.5, 2])
    program = E._generic
    E.support_many(np.eye(2), path="generic")
    E.support([1.0, 1.0], path="generic")
    assert E._generic is program


def test_generic_program_detects_unbounded_directions_of_a_strip_with_a_ball():
    strip = ss.Reals(2).intersect_preimage([[1.0, 0.0]], ss.Box([0.0], [1.0]))
    S = ss.Ellipsoid([0.0, 0.0], np.eye(2)) + strip
    assert isinstance(S, ss.MinkowskiSum)
    values = S.support_many(np.array([[1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]), path="generic")
    assert values[0] == pytest.approx(2.0, abs=1e-6)
    assert values[1:].tolist() == [np.inf, np.inf]


def test_chebyshev_ball_of_a_box_is_its_centre_and_half_width():
    H = np.vstack([np.eye(2), -np.eye(2)])
    center, radius = solvers.chebyshev_ball(H, np.array([1.0, 3.0, 1.0, 1.0]))
    assert radius == pytest.approx(1.0, abs=1e-7)
    # The centres of the unit balls in [-1, 1] × [-1, 3] fill the segment {0} × [0, 2].
    assert center[0] == pytest.approx(0.0, abs=1e-7) and -1e-7 <= center[1] <= 2.0 + 1e-7


def test_chebyshev_ball_of_an_empty_polyhedron_is_nan_with_radius_minus_inf():
    center, radius = solvers.chebyshev_ball(np.array([[1.0], [-1.0]]), np.array([0.0, -1.0]))
    assert np.isnan(center).all() and radius == -np.inf


def test_chebyshev_ball_of_a_half_plane_does_not_exist():
    with pytest.raises(ValueError, match="balls of every radius"):
        solvers.chebyshev_ball(np.array([[1.0, 0.0]]), np.array([1.0]))


# -- tolerances ------------------------------------------------------------------------------------

def test_scaled_tolerances_never_shrink_below_the_absolute_one():
    assert tol.scaled(1e-7, 0.0) == 1e-7
    assert tol.scaled(1e-7, 1e3) == pytest.approx(1e-4)


def test_nearly_equal_is_relative_and_exact_for_infinities():
    assert tol.nearly_equal(1e6, 1e6 + 1e-2)
    assert not tol.nearly_equal(1.0, 1.0 + 1e-5)
    assert tol.nearly_equal(np.inf, np.inf)
    assert not tol.nearly_equal(np.inf, 1e300)
    assert not tol.nearly_equal(-np.inf, np.inf)


def test_the_tolerances_are_ordered_from_solver_accuracy_to_decisions():
    assert tol.SOLVER_TOL < tol.MEMBERSHIP_TOL <= tol.SOLVER_CHECK_TOL
    assert tol.RANK_TOL < tol.SOLVER_TOL
