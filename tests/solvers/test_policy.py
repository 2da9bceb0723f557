"""The solver policy (`policy.policy`) and what `FactorConstraints.maximize` makes of its attempts,
driven with fake backends: which backends are asked, in which order, and what settles an objective.

The fakes wrap the real backends (`backends.BACKENDS`) and record or replace their answers; the
independent references are HiGHS LPs on the original data (`_exact_max`).
"""

from __future__ import annotations

import numpy as np
import pytest

from setsmooth.solvers import backends as backends_module
from setsmooth.solvers import factor_set
from setsmooth.solvers.backends import BACKENDS, Answer
from setsmooth.solvers.clarabel_lp import SolverError
from setsmooth.solvers.factor_set import FactorConstraints
from setsmooth.solvers.policy import POLICIES, PURPOSES, Attempt, policy


def _strip(seed: int = 3, nc: int = 4, ng: int = 12) -> tuple[FactorConstraints, np.ndarray,
                                                          np.ndarray]:
    """A non-empty factor set with independent rows: {ξ : Aξ = Aξ₀, |ξ| ≤ 1}, ξ₀ inside."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((nc, ng))
    xi0 = rng.uniform(-0.5, 0.5, ng)
    return FactorConstraints(A, A @ xi0, np.ones(ng)), A, xi0


def _exact_max(A, b, g, h=None) -> float:
    from scipy.optimize import linprog

    bounds = [(-1, 1)] * g.size if h is None else [(None, None) if np.isinf(v) else (-v, v)
                                                     for v in h]
    res = linprog(-g, A_eq=A, b_eq=b, bounds=bounds, method="highs")
    assert res.status == 0
    return -res.fun


def _recording(replace=None) -> tuple[dict, list]:
    """Backends that record (program, backend) and answer as the real ones, or as ``replace(name,
    pre, real answer)`` returns."""
    calls: list = []

    def wrap(name):
        def backend(pre, q, batch=None):
            answer = BACKENDS[name](pre, q, batch)
            calls.append((pre, name))
            return answer if replace is None else replace(name, pre, answer)
        return backend

    return {name: wrap(name) for name in BACKENDS}, calls


def _unsettled(name, pre, answer) -> Answer:
    return Answer("unsettled", answer.eta, answer.z, "InsufficientProgress")


def test_the_policy_is_data_a_function_of_the_purpose():
    F, _, _ = _strip()
    pre = F.presolved
    for purpose in PURPOSES:
        attempts = policy(pre, purpose)
        assert attempts == POLICIES[purpose]
        assert all(isinstance(a, Attempt) and a.backend in BACKENDS for a in attempts)
        assert attempts[-1] == Attempt("interior")  # HiGHS's interior-point method last
    assert policy(pre, "bracketed")[0] == Attempt("simplex")
    assert policy(pre, "escalated")[0] == Attempt("simplex cold")
    with pytest.raises(ValueError, match="purpose"):
        policy(pre, "fast")


def test_the_sequence_purposes_name_sequence_backends():
    from setsmooth.solvers.backends import SEQUENCE_BACKENDS
    from setsmooth.solvers.policy import SEQUENCE_PURPOSES

    assert not set(SEQUENCE_PURPOSES) & set(PURPOSES)
    for purpose in SEQUENCE_PURPOSES:
        attempts = policy(None, purpose)
        assert attempts and all(a.backend in SEQUENCE_BACKENDS and not a.on_full for a in attempts)


@pytest.mark.parametrize("purpose", PURPOSES)
def test_a_support_whose_every_backend_is_unsettled_is_relaxed_on_the_solved_program(
        monkeypatch, purpose):
    """The last resort on a non-empty set: the program relaxed by the phase-one residual, an outer
    value. (Reliability case 018 once reached it with no program at hand.)"""
    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)  # dependent rows not looked for
    F, A, xi0 = _strip()
    assert not F.presolved.dependent_checked
    fakes, calls = _recording(_unsettled)
    g = np.linspace(-1.0, 1.0, A.shape[1])
    answer = F.maximize(g, "test", purpose=purpose, backends=fakes)
    assert answer.status == "relaxed"
    assert g @ answer.xi >= _exact_max(A, A @ xi0, g) - 1e-7
    asked = [name for _, name in calls]
    planned = [a.backend for a in policy(F.presolved, purpose)]
    assert asked == list(dict.fromkeys(planned))  # each backend once: the full program is the same
    # with unverified=True the last point is returned for a certificate instead
    assert F.maximize(g, "test", purpose=purpose, backends=fakes,
                      unverified=True).status == "unverified"


def test_with_no_point_and_no_relaxation_the_error_carries_the_last_status(monkeypatch):
    F, A, _ = _strip()
    fakes = {name: (lambda pre, q, batch=None: Answer(
        "unsettled", np.full(pre.A.shape[1], np.nan), np.full(pre.A.shape[0], np.nan),
        "MaxIterations")) for name in BACKENDS}
    monkeypatch.setattr(FactorConstraints, "relaxed", lambda self, *args: (_ for _ in ()).throw(
        SolverError("NumericalError", "relaxed")))
    with pytest.raises(SolverError) as info:
        F.maximize(np.ones(A.shape[1]), "test", backends=fakes)
    assert info.value.status == "NumericalError"  # the relaxed program's own failure
    F2, A2, _ = _strip(seed=4)
    F2._empty, F2._phase_one = True, None  # an empty set: no relaxed program
    with pytest.raises(SolverError) as info:
        F2.maximize(np.ones(A2.shape[1]), "test", backends=fakes)
    assert info.value.status == "MaxIterations" and info.value.kind == "support"


def test_a_solved_answer_is_taken_and_a_candidate_only_after_its_independent_check():
    F, A, xi0 = _strip(seed=5)
    g = np.cos(np.arange(A.shape[1]))
    exact = _exact_max(A, A @ xi0, g)

    def off_candidate(name, pre, answer):
        if name == "clarabel":  # a point far from optimal, offered for the check
            return Answer("candidate", np.zeros_like(answer.eta), answer.z, "AlmostSolved")
        return answer

    fakes, calls = _recording(off_candidate)
    answer = F.maximize(g, "test", purpose="plain", backends=fakes)
    assert [name for _, name in calls] == ["clarabel", "clarabel refined"]  # the check refused it
    assert abs(g @ answer.xi - exact) <= 1e-7
    fakes, calls = _recording()
    F.maximize(g, "test", purpose="plain", backends=fakes)
    assert [name for _, name in calls] == ["clarabel"]


def test_an_infeasible_verdict_on_a_non_empty_set_goes_to_the_relaxed_program():
    F, A, xi0 = _strip(seed=6)
    fakes, calls = _recording(lambda name, pre, answer: Answer(
        "infeasible", answer.eta * np.nan, answer.z * np.nan, "PrimalInfeasible"))
    g = np.sin(np.arange(A.shape[1]))
    answer = F.maximize(g, "test", purpose="bracketed", backends=fakes)
    assert answer.status == "relaxed" and len(calls) == 1
    exact = _exact_max(A, A @ xi0, g)
    assert exact - 1e-9 <= g @ answer.xi <= exact + 1e-6 * np.abs(g).sum()
    empty = FactorConstraints(A, A @ xi0 + np.array([40.0, 0, 0, 0]), np.ones(A.shape[1]))
    assert empty.maximize(g, "test", backends=fakes).status == "infeasible"


def test_an_unbounded_direction_is_decided_by_the_recession_program():
    """Free factors: a direction cancelled on them is bounded, another is not."""
    A = np.array([[1.0, 1.0, 0.0], [0.0, 1.0, 1.0]])
    h = np.array([1.0, np.inf, 1.0])
    F = FactorConstraints(A, np.array([0.5, 0.2]), h)
    assert F.maximize(np.array([0.0, 1.0, 0.0]), "t").status == "optimal"  # ξ₂ = 0.5 − ξ₁
    assert F.maximize(np.array([1.0, 1.0, 1.0]), "t").status == "optimal"
    free_line = FactorConstraints(np.array([[1.0, 0.0, 0.0]]), np.array([0.5]), h)
    assert free_line.maximize(np.array([0.0, 1.0, 0.0]), "t").status == "unbounded"


@pytest.mark.parametrize("simplex_settles", [True, False])
def test_a_bracketed_direction_is_answered_on_the_kept_program_without_the_dense_presolve(
        monkeypatch, simplex_settles):
    """The bracketed purpose on a program too large for the dense dependent-row check: the
    warm-started simplex method first on the kept program, the kept Clarabel instance when it does
    not settle; the fully presolved program (a dense rank-revealing QR, 72 % of the recursion
    smoother's time on reliability case 029) is not built."""
    from setsmooth.solvers import presolve as presolve_module

    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)
    F, A, xi0 = _strip(seed=7)
    assert not F.presolved.dependent_checked
    factorizations = []
    real_rows = presolve_module.independent_rows
    monkeypatch.setattr(presolve_module, "independent_rows",
                        lambda *args, **kwargs: factorizations.append(1) or real_rows(*args,
                                                                                    **kwargs))
    monkeypatch.setattr(presolve_module, "INDEPENDENT_RCOND", 2.0)  # never "certainly independent"
    fakes, calls = _recording(None if simplex_settles else (
        lambda name, pre, answer: _unsettled(name, pre, answer) if name == "simplex" else answer))
    g = np.linspace(-1.0, 1.0, A.shape[1])
    answer = F.maximize(g, "test", purpose="bracketed", backends=fakes)
    assert answer.status == "optimal"
    assert abs(g @ answer.xi - _exact_max(A, A @ xi0, g)) <= 1e-7
    assert [(pre is F.presolved, name) for pre, name in calls] == (
        [(True, "simplex")] if simplex_settles else [(True, "simplex"), (True, "clarabel")])
    assert not factorizations


def test_emptiness_the_interior_point_method_cannot_settle_goes_to_the_simplex_method(monkeypatch):
    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)
    F, A, xi0 = _strip(seed=5)
    real_solver = backends_module.clarabel.DefaultSolver

    class Stalled:
        """A Clarabel solver whose every answer is 'InsufficientProgress'."""

        def __init__(self, *args, **kwargs):
            self._inner = real_solver(*args, **kwargs)

        def update(self, **kwargs):
            self._inner.update(**kwargs)

        def solve(self):
            sol = self._inner.solve()

            class Stopped:
                status = "SolverStatus.InsufficientProgress"
                x, z = sol.x, sol.z

            return Stopped()

    monkeypatch.setattr(backends_module.clarabel, "DefaultSolver", Stalled)
    assert not F.is_empty()
    empty = FactorConstraints(A, A @ xi0 + np.array([40.0, 0, 0, 0]), np.ones(A.shape[1]))
    assert empty.is_empty()


def test_answers_do_not_depend_on_the_queries_asked_before():
    """One decision per query: a support answer is the same whether the set was queried along other
    directions first or not (the warm-started simplex method starts every support call from the
    program's feasible basis; HiGHS keeps some state across models, ~1e-15 relative)."""
    import setsmooth as ss

    rng = np.random.default_rng(11)

    def cz():
        r = np.random.default_rng(11)
        G, A = r.standard_normal((3, 14)), r.standard_normal((5, 14))
        return ss.ConstrainedZonotope(G, np.zeros(3), A=A, b=A @ r.uniform(-0.5, 0.5, 14))

    d = rng.standard_normal(3)
    fresh, fresh_hull = cz().support(d), cz().interval_hull()
    shared = cz()
    for other in rng.standard_normal((5, 3)):
        shared.support(other)
    hull = shared.interval_hull()
    assert shared.support(d) == pytest.approx(fresh, rel=1e-12)
    np.testing.assert_allclose(hull.lo, fresh_hull.lo, rtol=1e-12)
    np.testing.assert_allclose(hull.hi, fresh_hull.hi, rtol=1e-12)
