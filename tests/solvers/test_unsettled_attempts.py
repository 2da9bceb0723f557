"""The last resorts of `FactorConstraints` when every planned solve is unsettled.

On a program too large for the dense dependent-row check, the planned attempts end with "the fully
presolved program, if it differs". When it does not differ that attempt is skipped, and the last
resort (the relaxed program for a support, the simplex method for emptiness) must still get the
program that was actually solved. Reliability case 018 (rank-deficient C, CZ noises, noise 1e-6 and
1e3) reached the support's last resort with None there: ``AttributeError: 'NoneType' object has no
attribute 'A'`` from a recursion smoother's hull.
"""

from __future__ import annotations

import numpy as np
import pytest

from setsmooth.solvers import factor_set
from setsmooth.solvers.factor_set import FactorConstraints


def _strip(seed: int = 3, nc: int = 4, ng: int = 12) -> tuple[FactorConstraints, np.ndarray,
                                                          np.ndarray]:
    """A non-empty factor set with independent rows: {ξ : Aξ = Aξ₀, |ξ| ≤ 1}, ξ₀ inside."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((nc, ng))
    xi0 = rng.uniform(-0.5, 0.5, ng)
    return FactorConstraints(A, A @ xi0, np.ones(ng)), A, xi0


def _exact_max(A, b, g) -> float:
    from scipy.optimize import linprog

    res = linprog(-g, A_eq=A, b_eq=b, bounds=[(-1, 1)] * g.size, method="highs")
    assert res.status == 0
    return -res.fun


def test_a_support_whose_every_solve_is_unsettled_is_relaxed_on_the_solved_program(monkeypatch):
    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)  # dependent rows not looked for
    F, A, xi0 = _strip()
    assert not F.presolved.dependent_checked
    real = FactorConstraints._solve_on

    def unsettled(self, pre, q, refine):
        _, eta, z = real(self, pre, q, refine)
        return "InsufficientProgress", eta, z

    monkeypatch.setattr(FactorConstraints, "_solve_on", unsettled)
    g = np.linspace(-1.0, 1.0, A.shape[1])
    for escalate in (False, True):
        answer = F.maximize(g, "test", escalate=escalate)
        assert answer.status == "relaxed"
        # an outer value: the set relaxed by the emptiness tolerance contains the exact one
        assert g @ answer.xi >= _exact_max(A, A @ xi0, g) - 1e-7


def test_emptiness_the_interior_point_method_cannot_settle_goes_to_the_simplex_method(monkeypatch):
    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)
    F, A, xi0 = _strip(seed=5)
    real_solver = factor_set.clarabel.DefaultSolver

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

    monkeypatch.setattr(factor_set.clarabel, "DefaultSolver", Stalled)
    assert not F.is_empty()
    empty = FactorConstraints(A, A @ xi0 + np.array([40.0, 0, 0, 0]), np.ones(A.shape[1]))
    assert empty.is_empty()


@pytest.mark.parametrize("simplex_settles", [True, False])
def test_a_bracketed_direction_is_answered_on_the_kept_program_without_the_dense_presolve(
        monkeypatch, simplex_settles):
    """The bracketed path (`CZProgram` support directions) on a program too large for the dense
    dependent-row check: the warm-started simplex method answers first on the kept program, and the
    kept interior-point instance when it does not settle. Building the fully presolved program
    first (a dense rank-revealing QR per set) was 72 % of the recursion smoother's time on
    reliability case 029 (CZ noises, T = 16)."""
    from setsmooth.solvers import presolve as presolve_module

    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)
    F, A, xi0 = _strip(seed=7)
    assert not F.presolved.dependent_checked
    real = FactorConstraints._solve_on
    solves, factorizations = [], []

    def recorded(self, pre, q, refine):
        solves.append((pre is F.presolved, refine))
        if refine == "simplex" and not simplex_settles:
            return "NumericalError", np.full(pre.A.shape[1], np.nan), np.full(pre.A.shape[0], np.nan)
        return real(self, pre, q, refine)

    real_rows = presolve_module.independent_rows
    monkeypatch.setattr(presolve_module, "independent_rows",
                        lambda *args, **kwargs: factorizations.append(1) or real_rows(*args,
                                                                                    **kwargs))
    monkeypatch.setattr(presolve_module, "INDEPENDENT_RCOND", 2.0)  # never "certainly independent"
    monkeypatch.setattr(FactorConstraints, "_solve_on", recorded)
    g = np.linspace(-1.0, 1.0, A.shape[1])
    answer = F.maximize(g, "test", bracketed=True)
    assert answer.status == "optimal"
    assert abs(g @ answer.xi - _exact_max(A, A @ xi0, g)) <= 1e-7
    assert solves == ([(True, "simplex")] if simplex_settles else [(True, "simplex"), (True, False)])
    assert not factorizations  # before 1695486: the fully presolved program was built first



def test_once_the_exact_rows_are_found_inconsistent_the_batch_goes_relaxed(monkeypatch):
    """Reliability case 029 (non-square D, fewer noise components than outputs): the recursion
    smoother's flat sets have rows inconsistent by rounding, on which the warm simplex method runs
    into its time limit (76 s a direction) and the exact rows are reported infeasible before the
    relaxed program answers. After one such direction, the later bracketed and escalated directions
    of the same batch (one support call) go to the relaxed program directly. Other callers, other
    batches, other threads, unsettled (not infeasible) answers and batches without a time-out try
    the exact rows first as before."""
    import threading

    from setsmooth.solvers import warm_simplex

    timed_out = [False]
    monkeypatch.setattr(factor_set, "simplex_timed_out", lambda pre: timed_out[0])
    F, A, xi0 = _strip(seed=7)
    status = ["PrimalInfeasible"]
    calls = []

    def exact_rows(self, pre, q, refine):
        calls.append(refine)
        return status[0], np.full(pre.A.shape[1], np.nan), np.full(pre.A.shape[0], np.nan)

    monkeypatch.setattr(FactorConstraints, "_solve_on", exact_rows)
    rng = np.random.default_rng(0)
    g = rng.standard_normal(A.shape[1])

    def tries_exact_rows(**kwargs) -> bool:
        calls.clear()
        assert F.maximize(g, "test", **kwargs).status == "relaxed"
        return bool(calls)

    warm_simplex.new_batch()
    assert tries_exact_rows(bracketed=True) and tries_exact_rows(bracketed=True)  # no time-out
    timed_out[0] = True
    status[0] = "InsufficientProgress"  # unsettled, not infeasible: no evidence about the rows
    assert tries_exact_rows(bracketed=True) and tries_exact_rows(bracketed=True)
    status[0] = "PrimalInfeasible"
    assert tries_exact_rows(bracketed=True)  # infeasible after a time-out: the batch goes relaxed
    for kwargs in ({"bracketed": True}, {"escalate": True}):
        d = rng.standard_normal(A.shape[1])
        calls.clear()
        answer = F.maximize(d, "test", **kwargs)
        assert calls == [] and answer.status == "relaxed"  # straight to the relaxed program
        exact = _exact_max(A, A @ xi0, d)
        assert exact - 1e-9 <= d @ answer.xi <= exact + 1e-6 * np.abs(d).sum()
    assert tries_exact_rows()  # unbracketed: the exact rows first
    other_thread = []
    worker = threading.Thread(target=lambda: other_thread.append(tries_exact_rows(bracketed=True)))
    worker.start()
    worker.join()
    assert other_thread == [True]
    warm_simplex.new_batch()
    assert tries_exact_rows(bracketed=True)  # the next support call starts afresh


def test_after_a_time_out_an_unbracketed_direction_still_gets_the_simplex_method(monkeypatch):
    """The simplex method is skipped only as a repeat on a copy of rows it already ran on for the
    direction: on a small program (dependent rows checked up front, so the "fully presolved" program
    is the first one) an unbracketed direction's only simplex attempt runs after a time-out too."""
    monkeypatch.setattr(factor_set, "simplex_timed_out", lambda pre: True)
    F, A, xi0 = _strip(seed=11)
    assert F.presolved.dependent_checked
    real = FactorConstraints._solve_on
    calls = []

    def unsettled_interior_point(self, pre, q, refine):
        name, eta, z = real(self, pre, q, refine)
        calls.append(refine)
        return ("InsufficientProgress" if refine in (False, True) else name), eta, z

    monkeypatch.setattr(FactorConstraints, "_solve_on", unsettled_interior_point)
    g = np.linspace(-1.0, 1.0, A.shape[1])
    answer = F.maximize(g, "test")
    assert calls[:3] == [False, True, "simplex"]
    assert answer.status == "optimal"
    assert abs(g @ answer.xi - _exact_max(A, A @ xi0, g)) <= 1e-8 * np.abs(g).sum()


def _relaxed_shortcut_status(F: FactorConstraints) -> str:
    """The status of a bracketed direction of ``F`` in a fresh process's first batch."""
    from setsmooth.solvers import warm_simplex

    warm_simplex.new_batch()
    return F.maximize(np.ones(F.ng), "test", bracketed=True).status


def test_the_relaxed_shortcut_does_not_travel_to_another_process():
    """Batch ids are counted per process: a factor set pickled in a batch that took the relaxed
    shortcut must not take it in a worker whose batch happens to have the same id."""
    import pickle
    from concurrent.futures import ProcessPoolExecutor

    from setsmooth.solvers import warm_simplex

    F, _, _ = _strip(seed=13)
    for batch in range(1, 4):  # the ids a fresh worker's first batches get
        F._relaxed_batch = batch
        assert "_relaxed_batch" not in pickle.loads(pickle.dumps(F)).__dict__
    F._relaxed_batch = warm_simplex.current_batch()
    with ProcessPoolExecutor(1) as pool:
        assert pool.submit(_relaxed_shortcut_status, F).result() == "optimal"
