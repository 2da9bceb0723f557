"""The simplex backends' tolerance ladder (`highs.SIMPLEX_TOLERANCES`), cold and warm-started.

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

from setsmooth.solvers import highs
from setsmooth.solvers import warm_simplex as warm_module
from setsmooth.solvers.highs import interior_point, simplex_cold
from setsmooth.solvers.presolved import Presolved

DATA = Path(__file__).parent / "data" / "cycling_program.npz"


def simplex(pre: Presolved, q: np.ndarray, batch: object = None):
    """The warm-started simplex method, every call in one batch unless told otherwise."""
    return warm_module.simplex(pre, q, batch)


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
    real = highs.set_rung

    def recorded(h, tolerance, cap, strategy=1):
        seen.append((tolerance, cap))
        real(h, tolerance, cap, strategy)

    monkeypatch.setattr(highs, "set_rung", recorded)
    name, eta, lam = simplex_cold(pre, q)
    size = sum(pre.A.shape)
    assert seen[0] == (1e-10, size + 200)
    assert len(seen) <= len(highs.SIMPLEX_TOLERANCES)
    assert name == "AlmostSolved" and pre.checked_gap(q, eta, lam) is not None


def test_programs_whose_value_decides_never_go_below_1e_9(monkeypatch):
    """Phase one (empty iff its optimum exceeds 1e-8) and the recession program: a rung at HiGHS's
    defaults (1e-7) could call a non-empty set empty, so their ladder stops at 1e-9."""
    seen = []
    real = highs.set_rung

    def recorded(h, tolerance, cap, strategy=1):
        seen.append(tolerance)
        real(h, tolerance, cap, strategy)

    monkeypatch.setattr(highs, "set_rung", recorded)
    monkeypatch.setattr(highs, "settled_point", lambda h: None)  # every rung fails
    monkeypatch.setattr(highs, "verdict", lambda h: "MaxIterations")
    rows = sp.csc_matrix(np.vstack([np.eye(2), -np.eye(2)]))
    assert highs.simplex_inequalities(np.ones(2), rows, np.ones(4))[0] != "optimal"
    assert seen == [1e-10, 1e-9]
    seen.clear()
    A = sp.csc_matrix(np.ones((1, 2)))
    assert highs.simplex_box_equalities(np.ones(2), A)[0] != "optimal"
    assert seen == [1e-10, 1e-9]
    seen.clear()
    pre, q = _cycling_program()
    assert simplex_cold(pre, q)[0] == "MaxIterations"
    assert seen == [1e-10, 1e-9, None]


def test_no_solve_of_the_solvers_package_has_a_time_limit():
    """The same input gives the same output on any machine under any load: HiGHS's runs are capped
    by iteration counts only, and no answer reads a clock."""
    package = Path(__file__).resolve().parents[2] / "setsmooth" / "solvers"
    for path in package.glob("*.py"):
        text = path.read_text()
        assert "time_limit" not in text, path.name
        if path.name != "instances.py":  # the per-thread solver instances
            assert "threading.local" not in text, path.name


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
        model = cached_instance(pre, warm_module.WARM_MODEL_KEY, lambda: None)
        assert model._h.getInfo().simplex_iteration_count <= 20 * size + 1000


def test_the_first_highs_model_of_a_process_prints_nothing():
    """HiGHS prints a banner when a process makes its first model; the library keeps it quiet."""
    import subprocess
    import sys

    code = ("import numpy as np, scipy.sparse as sp\n"
            "from setsmooth.solvers.warm_simplex import WarmSimplex\n"
            "m = WarmSimplex(sp.csc_matrix(np.ones((1, 2))), np.array([0.5]),\n"
            "                np.array([True, True]))\n"
            "print(m.minimize(np.array([1.0, -1.0]), None)[0])\n")
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
    """Each new batch token starts the model from its program's feasible basis (the zero
    objective's optimum), so a batch's answers depend on the batch alone, bit for bit, not on the
    queries solved before it; and each objective settles from there, where a cold start on 2 of
    these 8 fails at every rung."""
    pre, q0 = _cycling_program()
    rng = np.random.default_rng(9)
    objectives = [rng.standard_normal(q0.size) for _ in range(8)]

    def batch(qs):
        token = object()
        return [simplex(pre, q, token) for q in qs]

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
    from setsmooth.solvers.warm_simplex import WarmSimplex

    pre, q0 = _cycling_program()
    rng = np.random.default_rng(9)
    objectives = [rng.standard_normal(q0.size) for _ in range(8)]
    calls = []
    real = WarmSimplex.minimize

    def recorded(self, q, batch, dual=False):
        answer = real(self, q, batch, dual)
        calls.append((dual, pre.checked_gap(q, answer[1], answer[2])))
        return answer

    monkeypatch.setattr(WarmSimplex, "minimize", recorded)
    asked_again = 0
    for q in objectives:
        calls.clear()
        name, eta, lam = simplex(pre, q, object())
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
    """`highs.interior_point` (HiGHS's interior-point method without crossover, the last
    fallback before the relaxed program) answers a random feasible program at the cold simplex
    method's optimum, with multipliers that pass the caller's independent check."""
    from setsmooth import tolerances as tol

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


def _small_cz(rng: np.random.Generator):
    import setsmooth as ss

    G, A = rng.standard_normal((2, 20)), rng.standard_normal((8, 20))
    return ss.ConstrainedZonotope(G, rng.standard_normal(2), A=A, b=A @ rng.uniform(-0.8, 0.8, 20))


def test_a_small_programs_batch_is_one_block_lp_with_the_warm_runs_answers(monkeypatch):
    """A batch of k objectives over a small program is solved as one block-diagonal LP
    (`warm_simplex.Batch`): one HiGHS run per interval hull of a 2-D set with 20 factors instead of
    five (the feasible basis and four warm runs), and the hulls, plain and certified, agree with
    the warm runs' to 1e-9 of the width and with an independent `linprog` of every direction."""
    import highspy

    runs = []
    real_run = highspy.Highs.run
    monkeypatch.setattr(highspy.Highs, "run", lambda h: runs.append(1) or real_run(h))
    rng = np.random.default_rng(12)
    for _ in range(5):
        Z = _small_cz(rng)
        runs.clear()
        block = Z.interval_hull(certified=True)
        assert len(runs) == 1
        with monkeypatch.context() as m:
            m.setattr(warm_module, "BLOCK_SIZE_MAX", 0)
            Z2 = type(Z)(Z.G, Z.c, A=Z.A, b=Z.b)  # a fresh set: no program kept
            runs.clear()
            warm = Z2.interval_hull(certified=True)
            assert len(runs) == 5
        width = block.hi - block.lo
        assert np.all(np.abs(block.lo - warm.lo) <= 1e-9 * width)
        assert np.all(np.abs(block.hi - warm.hi) <= 1e-9 * width)
        for i in range(2):
            for sign in (1.0, -1.0):
                res = linprog(-sign * Z.G[i], A_eq=Z.A, b_eq=Z.b, bounds=(-1, 1), method="highs")
                exact = sign * Z.c[i] - res.fun  # h_Z(±e_i)
                bound = block.hi[i] if sign > 0 else -block.lo[i]
                assert bound >= exact - 1e-9 * width[i]
                assert bound <= exact + 1e-6 * width[i]
