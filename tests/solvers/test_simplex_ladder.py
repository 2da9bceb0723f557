"""The simplex fallback's tolerance ladder (`presolve.SIMPLEX_TOLERANCES`), cold and warm-started.

``data/cycling_program.npz`` is one presolved support program of the recursion smoother (reliability
case 000 at T = 20: 158 rows, 293 factors, σ_min(Â) ≈ 6e-8, degenerate). HiGHS at feasibility
tolerances 1e-10 ran 529,246 iterations on it (20 s) and ended with 'numerical difficulties'; at
its defaults it needs about 250. 196 such fallback solves were 82 % of that smoother's time.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from setsmooth.solvers import presolve as presolve_module
from setsmooth.solvers.presolve import Presolved, simplex, simplex_cold

DATA = Path(__file__).parent / "data" / "cycling_program.npz"


def _cycling_program() -> tuple[Presolved, np.ndarray]:
    z = np.load(DATA)
    A = sp.csc_matrix((z["data"], z["indices"], z["indptr"]), shape=tuple(z["shape"]))
    m, p = A.shape
    pre = Presolved(A=A, b=z["b"], rows=np.arange(m), cols=np.arange(p), row_scale=np.ones(m),
                    col_scale=np.ones(p), bounded=z["bounded"], empty=False,
                    dependent_checked=True)
    return pre, z["q"]


def test_a_program_the_tight_tolerance_cycles_on_is_settled_by_a_looser_rung():
    pre, q = _cycling_program()
    name, eta, lam = simplex(pre, q)
    assert name == "AlmostSolved"  # before: 'NumericalError' after 529,246 iterations
    gap = pre.checked_gap(q, eta, lam)  # the caller's independent check
    assert gap is not None and gap <= 1e-6
    reference = linprog(q, A_eq=pre.A, b_eq=pre.b, bounds=[(-1, 1)] * q.size, method="highs")
    assert abs(q @ eta - reference.fun) <= 1e-6 * (1 + abs(reference.fun))


def test_each_rung_is_capped_and_the_first_settled_answer_is_kept(monkeypatch):
    pre, q = _cycling_program()
    seen = []
    real = linprog

    def recorded(*args, **kwargs):
        res = real(*args, **kwargs)
        seen.append((kwargs["options"].get("primal_feasibility_tolerance"),
                     kwargs["options"]["maxiter"], res.status, res.nit))
        return res

    monkeypatch.setattr("scipy.optimize.linprog", recorded)
    simplex_cold(pre, q)
    size = sum(pre.A.shape)
    assert seen[0][:2] == (1e-10, size + 200)
    assert all(status in (1, 4) for _, _, status, _ in seen[:-1])  # only failures move down
    assert seen[-1][2] == 0
    assert all(nit <= cap for _, cap, _, nit in seen)
    assert len(seen) <= len(presolve_module.SIMPLEX_TOLERANCES)


def test_programs_whose_value_decides_never_go_below_1e_9(monkeypatch):
    """Phase one (empty iff its optimum exceeds 1e-8) and the recession program: a rung at HiGHS's
    defaults (1e-7) could call a non-empty set empty, so their ladder stops at 1e-9."""
    from types import SimpleNamespace

    from setsmooth.solvers.presolve import simplex_box_equalities, simplex_inequalities

    seen = []

    def failing(q, **kwargs):
        seen.append(kwargs["options"].get("primal_feasibility_tolerance"))
        return SimpleNamespace(status=4, message="numerical difficulties", nit=0)

    monkeypatch.setattr("scipy.optimize.linprog", failing)
    rows = sp.csc_matrix(np.vstack([np.eye(2), -np.eye(2)]))
    assert simplex_inequalities(np.ones(2), rows, np.ones(4))[0] == "status 4"
    assert seen == [1e-10, 1e-9]
    seen.clear()
    assert simplex_box_equalities(np.ones(2), sp.csc_matrix(np.ones((1, 2))))[0] == "status 4"
    assert seen == [1e-10, 1e-9]
    seen.clear()
    pre, q = _cycling_program()
    assert simplex_cold(pre, q)[0] == "NumericalError"
    assert seen == [1e-10, 1e-9, None]


def test_the_warm_started_simplex_agrees_with_cold_solves_over_many_objectives():
    """One kept HiGHS model, costs changed, each solve from the last basis (`WarmSimplex`), against
    SciPy's cold ``linprog`` ladder. Every warm answer passes the caller's independent check with a
    relative duality gap below ``ACCURATE_GAP_TOL`` (weak duality: the gap bounds its error), and
    agrees with each cold answer that passes the check itself. (On this program the warm solves
    settle at the tight rung in 20–40 iterations, while 3 of the 12 cold ones fail the check:
    their rung's cap sent them to HiGHS's defaults, 1.7e-5 off.)"""
    from setsmooth import tolerances as tol
    from setsmooth.solvers.instances import cached_instance

    pre, q0 = _cycling_program()
    rng = np.random.default_rng(4)
    objectives = [q0, -q0] + [rng.standard_normal(q0.size) for _ in range(10)]
    size = sum(pre.A.shape)
    for q in objectives:
        warm, cold = simplex(pre, q), simplex_cold(pre, q)
        assert warm[0] == cold[0] == "AlmostSolved"
        gap = pre.checked_gap(q, warm[1], warm[2])
        assert gap is not None and gap <= tol.ACCURATE_GAP_TOL
        if pre.checked_gap(q, cold[1], cold[2]) is not None:
            assert abs(q @ warm[1] - q @ cold[1]) <= 1e-6 * (1 + abs(q @ cold[1]))
        model = cached_instance(pre, presolve_module.WARM_MODEL_KEY, lambda: None)
        assert model._h.getInfo().simplex_iteration_count <= 20 * size + 1000


def test_the_first_highs_model_of_a_process_prints_nothing():
    """HiGHS prints a banner when a process makes its first model; the library keeps it quiet."""
    import subprocess
    import sys

    code = ("import numpy as np, scipy.sparse as sp\n"
            "from setsmooth.solvers.warm_simplex import WarmSimplex\n"
            "m = WarmSimplex(sp.csc_matrix(np.ones((1, 2))), np.array([0.5]),\n"
            "                np.array([True, True]))\n"
            "print(m.minimize(np.array([1.0, -1.0]), (1e-10,), (100,))[0])\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[2])
    assert out.stdout == "AlmostSolved\n", out.stdout


def test_the_warm_models_are_per_thread_and_the_program_still_pickles():
    """Four threads solving the same program's objectives, each in its own order, each warm their
    own HiGHS model (a shared one would mix bases and costs between threads): every answer passes
    the caller's independent check and all threads agree with the serial answers. Each model is
    first warmed on q0, whose cold solve settles (a cold start on some of these objectives does not,
    at any rung: that is what the warm start and the caller's other fallbacks are for)."""
    import pickle
    from concurrent.futures import ThreadPoolExecutor

    pre, q0 = _cycling_program()
    rng = np.random.default_rng(9)
    objectives = [rng.standard_normal(q0.size) for _ in range(8)]

    def solve_all(shift: int) -> list[float]:
        assert simplex(pre, q0)[0] == "AlmostSolved"
        values = {}
        for i in list(range(shift, 8)) + list(range(shift)):
            name, eta, lam = simplex(pre, objectives[i])
            assert name == "AlmostSolved"
            assert pre.checked_gap(objectives[i], eta, lam) is not None
            values[i] = objectives[i] @ eta
        return [values[i] for i in range(8)]

    serial = np.array(solve_all(0))
    with ThreadPoolExecutor(max_workers=4) as pool:
        for values in pool.map(solve_all, range(4)):
            assert np.allclose(values, serial, rtol=1e-7, atol=0.0)
    again = pickle.loads(pickle.dumps(pre))
    assert simplex(again, q0)[0] == "AlmostSolved"


def test_a_batch_starts_from_the_programs_feasible_basis_whatever_came_before():
    """Each `new_batch` starts every model from its program's feasible basis (the zero objective's
    optimum), so a batch's answers depend on the batch alone, bit for bit, not on the queries
    solved before it; and each objective settles from there, where a cold start on 2 of these 8
    fails at every rung."""
    from setsmooth.solvers.warm_simplex import new_batch

    pre, q0 = _cycling_program()
    rng = np.random.default_rng(9)
    objectives = [rng.standard_normal(q0.size) for _ in range(8)]

    def batch(qs):
        new_batch()
        return [simplex(pre, q) for q in qs]

    first = batch(objectives[:3])
    batch([q0, -objectives[1], objectives[5]])  # other queries on the same model in between
    again = batch(objectives[:3])
    for (n1, eta1, lam1), (n2, eta2, lam2) in zip(first, again):
        assert n1 == n2 == "AlmostSolved"
        assert np.array_equal(eta1, eta2) and np.array_equal(lam1, lam2)
    for q in objectives:
        [(name, eta, lam)] = batch([q])
        assert name == "AlmostSolved"
        assert pre.checked_gap(q, eta, lam) is not None


def test_a_loose_primal_answer_is_asked_again_of_the_dual_method_from_the_batch_start(monkeypatch):
    """From a feasible basis the primal method answers (`warm_simplex.WARM_STRATEGY`). Where its
    answer fails `Presolved.checked_gap` at ``ACCURATE_GAP_TOL`` (loose duals on this
    ill-conditioned program: 4 of the 8 objectives, gaps 2.7e-7 to 8e-7 or failing), `simplex`
    asks the dual method from the batch's start and keeps the better answer. Every answer then
    passes the check at ``ACCURATE_GAP_TOL``."""
    from setsmooth import tolerances as tol
    from setsmooth.solvers.warm_simplex import WarmSimplex, new_batch

    pre, q0 = _cycling_program()
    rng = np.random.default_rng(9)
    objectives = [rng.standard_normal(q0.size) for _ in range(8)]
    calls = []
    real = WarmSimplex.minimize

    def recorded(self, q, tolerances, caps, dual=False):
        answer = real(self, q, tolerances, caps, dual)
        calls.append((dual, pre.checked_gap(q, answer[1], answer[2])))
        return answer

    monkeypatch.setattr(WarmSimplex, "minimize", recorded)
    asked_again = 0
    for q in objectives:
        new_batch()
        calls.clear()
        name, eta, lam = simplex(pre, q)
        first_gap = calls[0][1]
        assert calls[0][0] is False
        if first_gap is None or first_gap > tol.ACCURATE_GAP_TOL:
            assert [dual for dual, _ in calls] == [False, True]
            asked_again += 1
        else:
            assert len(calls) == 1
        assert name == "AlmostSolved"
        gap = pre.checked_gap(q, eta, lam)
        assert gap is not None and gap <= tol.ACCURATE_GAP_TOL
    assert asked_again >= 1  # the premise: the primal method is loose somewhere on this program


def test_the_interior_point_fallback_reaches_the_simplex_methods_optimum():
    """`interior_point.interior_point` (HiGHS's interior-point method without crossover, the last
    fallback before the relaxed program) answers a random feasible program at the cold simplex
    method's optimum, with multipliers that pass the caller's independent check."""
    from setsmooth import tolerances as tol
    from setsmooth.solvers.interior_point import interior_point

    rng = np.random.default_rng(3)
    m, p = 20, 45
    A = sp.csc_matrix(rng.standard_normal((m, p)))
    bounded = np.ones(p, dtype=bool)
    bounded[:3] = False  # free factors too
    b = A @ rng.uniform(-0.5, 0.5, p)
    pre = Presolved(A=A, b=b, rows=np.arange(m), cols=np.arange(p), row_scale=np.ones(m),
                    col_scale=np.ones(p), bounded=bounded, empty=False, dependent_checked=True)
    for _ in range(4):
        q = rng.standard_normal(p)
        q[:3] = -(A[:, :3].T @ rng.standard_normal(m))  # bounded: q cancels on the free factors
        name, eta, lam = interior_point(pre, q)
        assert name == "AlmostSolved"
        gap = pre.checked_gap(q, eta, lam)
        assert gap is not None and gap <= tol.ACCURATE_GAP_TOL
        reference = simplex_cold(pre, q)
        assert reference[0] == "AlmostSolved"
        assert abs(q @ eta - q @ reference[1]) <= 1e-8 * (1 + abs(q @ reference[1]))


def test_the_interior_point_fallback_settles_where_every_simplex_basis_is_singular():
    """Reliability case 184 at noise 1e3, smoothed set k = 25 (``data/singular_bases_program.npz``,
    1,308 rows, 1,726 factors): along this direction HiGHS's dual simplex method meets a
    rank-deficient basis from scratch, and the interior-point method with crossover fails in the
    crossover. Without crossover it answers, and the caller's check accepts its gap."""
    from setsmooth import tolerances as tol
    from setsmooth.solvers.interior_point import interior_point

    z = np.load(Path(__file__).parent / "data" / "singular_bases_program.npz")
    A = sp.csc_matrix((z["data"], z["indices"], z["indptr"]), shape=tuple(z["shape"]))
    m, p = A.shape
    pre = Presolved(A=A, b=z["b"], rows=np.arange(m), cols=np.arange(p), row_scale=np.ones(m),
                    col_scale=np.ones(p), bounded=z["bounded"], empty=False,
                    dependent_checked=True)
    q = z["q"]
    cold = linprog(q, A_eq=A, b_eq=pre.b, bounds=np.where(pre.bounded[:, None], [[-1.0, 1.0]],
                   [[-np.inf, np.inf]]), method="highs-ds")
    assert cold.status != 0 or pre.checked_gap(q, cold.x, -cold.eqlin.marginals) is None
    name, eta, lam = interior_point(pre, q)
    assert name == "AlmostSolved"
    gap = pre.checked_gap(q, eta, lam)
    assert gap is not None and gap <= tol.ACCURATE_GAP_TOL


def test_a_rungs_time_limit_counts_from_its_own_start(monkeypatch):
    """HiGHS's ``time_limit`` is on a model's run time summed over all its solves; the kept model
    (`WarmSimplex`) solves many objectives, so each rung's limit (`presolve.rung_seconds`) is set
    from the current run time. A model whose solves sum to several limits still answers every
    objective (set from zero, every rung after the first 0.15 s would stop at once)."""
    from setsmooth.solvers import warm_simplex
    from setsmooth.solvers.instances import cached_instance
    from setsmooth.solvers.warm_simplex import new_batch

    monkeypatch.setattr(warm_simplex, "rung_seconds", lambda size: 0.15)
    pre, q0 = _cycling_program()
    rng = np.random.default_rng(11)
    for _ in range(120):
        new_batch()  # each objective from the program's feasible basis: ~5 ms of HiGHS's time
        q = rng.standard_normal(q0.size)
        assert simplex(pre, q)[0] == "AlmostSolved"  # a rung that stopped at once: 'MaxIterations'
    model = cached_instance(pre, presolve_module.WARM_MODEL_KEY, lambda: None)
    assert model._h.getRunTime() > 0.3  # the premise: the solves summed to over twice the limit


def test_after_a_rung_reaches_its_time_limit_the_dual_method_does_not_perturb_the_costs(
        monkeypatch):
    """HiGHS's dual method can loop in the primal clean-up after it removes its cost perturbation,
    without counting iterations (reliability case 184 at noise 1e3, k = 17: hours at any cap).
    A rung that reaches its time limit has failed like a capped one, and the later rungs of its
    ladder solve with unperturbed costs. Here the first rung's limit is zero."""
    from setsmooth import tolerances as tol
    from setsmooth.solvers import warm_simplex
    from setsmooth.solvers.warm_simplex import WarmSimplex, new_batch

    pre, q = _cycling_program()
    new_batch()
    simplex(pre, -q)  # the model and its feasible basis, with the real limits
    limits = iter([0.0])
    real_limit = warm_simplex.rung_seconds
    monkeypatch.setattr(warm_simplex, "rung_seconds", lambda size: next(limits, real_limit(size)))
    perturbed = []
    real_rung = WarmSimplex._set_rung

    def recorded(self, *args, **kwargs):
        perturbed.append(kwargs.get("perturbed", True))
        real_rung(self, *args, **kwargs)

    monkeypatch.setattr(WarmSimplex, "_set_rung", recorded)
    new_batch()
    name, eta, lam = simplex(pre, q)
    assert perturbed[:2] == [True, False]
    assert name == "AlmostSolved"
    gap = pre.checked_gap(q, eta, lam)
    assert gap is not None and gap <= tol.ACCURATE_GAP_TOL


def _random_cz_and_hull_directions():
    """A random non-empty CZ in R³ (40 factors, 12 rows) and the six directions of its hull."""
    import setsmooth as ss

    rng = np.random.default_rng(29)
    ng, nc = 40, 12
    A = rng.standard_normal((nc, ng))
    Z = ss.ConstrainedZonotope(rng.standard_normal((3, ng)), rng.standard_normal(3), A,
                               A @ rng.uniform(-0.5, 0.5, ng))
    return Z, np.vstack([np.eye(3), -np.eye(3)])


def test_after_a_time_out_the_rest_of_the_batch_asks_the_interior_point_method_first(monkeypatch):
    """A program on which the warm simplex method ran out of time gets the interior-point method
    first for the remaining directions of that support call (`factor_set.AFTER_TIME_OUT_ATTEMPTS`;
    reliability case 029, k = 0: 76 s limits reached on several directions of one hull), the same
    values to the checks' accuracy, and the next call starts with the simplex method again."""
    from setsmooth.solvers import factor_set, warm_simplex

    Z, D = _random_cz_and_hull_directions()
    firsts: list = []  # the first solve of every direction
    real_maximize, real_solve_on = factor_set.FactorConstraints.maximize, \
        factor_set.FactorConstraints._solve_on

    def maximize(self, *args, **kwargs):
        firsts.append(None)
        return real_maximize(self, *args, **kwargs)

    def solve_on(self, pre, q, refine):
        if firsts[-1] is None:
            firsts[-1] = refine
        return real_solve_on(self, pre, q, refine)

    monkeypatch.setattr(factor_set.FactorConstraints, "maximize", maximize)
    monkeypatch.setattr(factor_set.FactorConstraints, "_solve_on", solve_on)
    reference = Z.support_many(D)  # the warm model and its feasible basis, with the real limits
    assert firsts == ["simplex"] * 6  # the premise: the simplex method first, no time-out
    limits = iter([0.0])  # the first direction's first rung stops at once
    real_limit = warm_simplex.rung_seconds
    monkeypatch.setattr(warm_simplex, "rung_seconds", lambda size: next(limits, real_limit(size)))
    firsts.clear()
    after_time_out, next_call = Z.support_many(D), Z.support_many(D)
    assert firsts == ["simplex"] + ["cold interior"] * 5 + ["simplex"] * 6
    width = reference[:3] + reference[3:]
    for values in (after_time_out, next_call):
        assert np.all(np.abs(values - reference) <= 1e-8 * np.tile(width, 2))


def test_after_a_time_out_the_simplex_method_is_not_repeated_on_the_same_rows(monkeypatch):
    """On a program too large for the dense dependent-row check, the "fully presolved" fallback
    has the same rows as the first program. After the warm simplex method ran out of time on the
    first program in this support call, it is not run again on that copy (reliability case 029,
    k = 0: a second 81 s time-out on the first direction); the interior-point method answers."""
    import setsmooth as ss
    from setsmooth.solvers import factor_set, warm_simplex

    monkeypatch.setattr(factor_set, "DENSE_PRESOLVE_MAX", 0)  # dependent rows not looked for
    Z, D = _random_cz_and_hull_directions()
    reference = Z.support_many(D)
    Z = ss.ConstrainedZonotope(Z.G, Z.c, Z.A, Z.b)  # a fresh factor set
    calls: list = []
    real_solve_on = factor_set.FactorConstraints._solve_on

    def solve_on(self, pre, q, refine):
        name, eta, z = real_solve_on(self, pre, q, refine)
        calls.append((pre is self.presolved, refine))
        if refine is False:  # the kept interior-point instance does not settle either
            name = "InsufficientProgress"
        return name, eta, z

    monkeypatch.setattr(factor_set.FactorConstraints, "_solve_on", solve_on)
    monkeypatch.setattr(warm_simplex, "rung_seconds", lambda size: 0.0)  # every rung times out
    values = Z.support_many(D)
    assert calls[:3] == [(True, "simplex"), (True, False), (True, "cold interior")]
    assert all(on_first for on_first, _ in calls)  # the copy of the rows is never solved
    width = reference[:3] + reference[3:]
    assert np.all(np.abs(values - reference) <= 1e-8 * np.tile(width, 2))
