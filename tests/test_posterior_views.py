"""The exact filter's posteriors as views of one trajectory CZ, and the banded free-factor bound."""

import pickle

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth.filters.steps import predict, update

#: A horizon long enough for the views' sharing to matter (the recursion is O(T³)).
HORIZON = 64
from setsmooth.papers.smoothing_examples import smoothing_example_31
from setsmooth.trajectories.posterior_views import PosteriorView, posterior_views
from setsmooth.sets.algebra import generalized_intersection, minkowski_sum
from setsmooth.solvers import instances
from setsmooth.trajectories.sparse_cz import _assemble
from setsmooth.trajectories.free_factor_bound import banded_free_factor_bound, gram_lower_bound

X0 = ss.Box([-5.0, -5.0], [5.0, 5.0])
TRIANGLE = ss.ConstrainedZonotope(G=[[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], c=[0.0, 0.0],
                                  A=[[1.0, 1.0, 1.0]], b=[1.0])


def triangle_system() -> ss.LinearSystem:
    """Example (31)'s dynamics with B = I, the triangle CZ of examples/new_set_representation.py as W
    and a zonotope V (issue 8's CZ-noise case)."""
    base = smoothing_example_31()
    V = ss.Zonotope([[1.0, 0.3, 0.0], [0.0, 0.5, 0.8]], [0.1, -0.2])
    return ss.LinearSystem(base.A_at(0), None, base.C_at(0), F=base.F_at(0), W=TRIANGLE, V=V)


def recursion_posteriors(system, X0, ys):
    """Stability (3)–(4) step by step through the public steps: the recursion's own CZs."""
    out = [update(system, 0, X0, ys[0])]
    for k in range(1, len(ys)):
        out.append(update(system, k, predict(system, k - 1, out[-1]), ys[k]))
    return out


def highs_support(system, X0: ss.Box, ys, k: int, d: np.ndarray, last: int | None = None) -> float:
    """max dᵀx_k over the trajectories 0..last (default k) consistent with y_0..y_last, as HiGHS's LP
    over the raw variables (x_0..x_last, η_w, η_v; noises as G η + c with Aη = b, |η| ≤ 1): no CZ
    algebra in it. ``last = T`` gives the smoothed range's support."""
    cost_at, k = k, k if last is None else last
    n, Zw, Zv = system.n, system.W.to_constrained_zonotope(), system.V.to_constrained_zonotope()
    gw, gv = Zw.ng, Zv.ng
    nx, nw, nv = n * (k + 1), gw * k, gv * (k + 1)
    N = nx + nw + nv
    rows, rhs = [], []

    def row_block(entries, b):
        M = np.zeros((len(b), N))
        for col, block in entries:
            M[:, col:col + block.shape[1]] += block
        rows.append(M)
        rhs.append(np.asarray(b, dtype=float))

    G_w, G_v = np.asarray(Zw.G.todense()) if sp.issparse(Zw.G) else Zw.G, np.asarray(Zv.G)
    for j in range(k):
        Bj = system.E_at(j)
        row_block([(n * (j + 1), np.eye(n)), (n * j, -system.A_at(j)), (nx + gw * j, -Bj @ G_w)],
                  Bj @ Zw.c)
        if Zw.nc:
            row_block([(nx + gw * j, np.asarray(Zw.A.todense()) if sp.issparse(Zw.A) else Zw.A)], Zw.b)
    for j in range(k + 1):
        Dj = system.F_at(j)
        row_block([(n * j, system.C_at(j)), (nx + nw + gv * j, Dj @ G_v)], ys[j] - Dj @ Zv.c)
        if Zv.nc:
            row_block([(nx + nw + gv * j, np.asarray(Zv.A))], Zv.b)
    bounds = [(lo, hi) for lo, hi in zip(X0.lo, X0.hi)] + [(None, None)] * (nx - n) + [(-1, 1)] * (nw + nv)
    cost = np.zeros(N)
    cost[n * cost_at:n * (cost_at + 1)] = -d
    res = linprog(cost, A_eq=np.vstack(rows), b_eq=np.concatenate(rhs), bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return -res.fun


def test_a_view_is_exactly_the_trajectory_cz_over_0_to_k():
    system = triangle_system()
    _, ys = ss.simulate(system, X0, 20, np.random.default_rng(0))
    views = posterior_views(system, X0, ys)
    Z0, Zw, Zv = (S.to_constrained_zonotope() for S in (X0, system.W, system.V))
    for k in (0, 1, 7, 20):
        cut, built = views[k]._shared.trajectories(k), _assemble(system, Z0, Zw, Zv, ys, 0, k)
        assert (sp.csc_matrix(cut.A) != sp.csc_matrix(built.A)).nnz == 0
        assert (sp.csc_matrix(cut.G) != sp.csc_matrix(built.G)).nnz == 0
        for a, b in ((cut.b, built.b), (cut.h, built.h), (cut.c, built.c)):
            np.testing.assert_array_equal(a, b)
        posterior, last = views[k]._shared.posterior(k), built._project(np.arange(2 * k, 2 * k + 2))
        assert (sp.csc_matrix(posterior.G) != sp.csc_matrix(last.G)).nnz == 0
        assert (posterior.A != last.A).nnz == 0 and posterior.G.shape == last.G.shape
        np.testing.assert_array_equal(posterior.c, last.c)


def test_views_are_the_recursion_posteriors_with_cz_noises():
    system = triangle_system()
    rng = np.random.default_rng(1)
    _, ys = ss.simulate(system, X0, HORIZON + 5, rng)
    views = ss.classical_filter(system, X0, ys)
    assert all(isinstance(P, PosteriorView) for P in views)
    recursion = recursion_posteriors(system, X0, ys)
    D = np.vstack([np.eye(2), -np.eye(2), rng.standard_normal((6, 2))])
    for k in (0, 1, 2, 10, 33, len(ys) - 1):
        ours, theirs = views[k].support_many(D), recursion[k].support_many(D)
        np.testing.assert_allclose(ours, theirs, atol=1e-6 * (1 + np.abs(theirs).max()), err_msg=f"k={k}")


def test_certified_hulls_of_views_enclose_the_highs_optimum_over_hundreds_of_steps():
    system = triangle_system()
    T = 200
    _, ys = ss.simulate(system, X0, T, np.random.default_rng(0))
    views = ss.classical_filter(system, X0, ys)
    for k in (5, T):
        hull = views[k].interval_hull(certified=True)
        for i in range(2):
            d = np.eye(2)[i]
            hi, lo = highs_support(system, X0, ys, k, d), -highs_support(system, X0, ys, k, -d)
            # Outer (HiGHS's optimum is itself accurate to ~1e-9), and tight.
            assert hull.hi[i] >= hi - 1e-9 * (1 + abs(hi)) and hull.lo[i] <= lo + 1e-9 * (1 + abs(lo))
            assert hull.hi[i] - hi <= 1e-6 * (1 + abs(hi)) and lo - hull.lo[i] <= 1e-6 * (1 + abs(lo))


def test_views_keep_no_matrices_and_the_solver_cache_stays_bounded():
    system = smoothing_example_31()
    _, ys = ss.simulate(system, X0, HORIZON + 16, np.random.default_rng(2))
    views = ss.classical_filter(system, X0, ys)
    hulls = [P.interval_hull(certified=True) for P in views]
    assert all(not isinstance(h, ss.EmptySet) for h in hulls)
    assert len(instances._cache()) <= instances.MAX_INSTANCES
    for P in views:
        assert set(vars(P)) <= {"_shared", "k", "dim", "_interval_hulls", "_flat_cz"}
    # The list pickles as one shared trajectory CZ plus one small view per step.
    size = len(pickle.dumps(views))
    assert size < 2 * len(pickle.dumps(views[:1]))
    again = pickle.loads(pickle.dumps(views[40]))
    np.testing.assert_array_equal(again.interval_hull(certified=True).hi, hulls[40].hi)


def test_an_inconsistent_measurement_empties_the_views_from_its_step_on():
    system = smoothing_example_31()
    _, ys = ss.simulate(system, X0, HORIZON + 10, np.random.default_rng(3))
    ys[50] += 100.0
    posts = ss.classical_filter(system, X0, ys)
    assert all(isinstance(P, PosteriorView) for P in posts[:50])
    assert all(isinstance(P, ss.EmptySet) for P in posts[50:])
    assert not posts[49].is_empty()
    undetected = ss.classical_filter(system, X0, ys, detect_empty=False)
    assert undetected[50].is_empty() and undetected[50].interval_hull().is_empty()


def test_the_banded_gram_bound_is_below_the_smallest_eigenvalue():
    rng = np.random.default_rng(4)
    for trial in range(20):
        N, width = int(rng.integers(5, 80)), int(rng.integers(1, 6))
        M = sp.random(N + 10, N, density=0.0, random_state=trial).tolil()
        for j in range(N):  # rows couple columns j..j+width only: a banded Gram matrix
            for i in range(j, min(N, j + width)):
                M[j, i] = rng.normal()
            M[N + (j % 10), j] = rng.normal() * 0.1
        AF = sp.csc_matrix(M)
        bound = gram_lower_bound(AF)
        exact = np.linalg.eigvalsh((AF.T @ AF).toarray())[0]
        if bound is not None:
            assert 0 < bound <= exact
            assert bound >= 0.5 * exact  # tight enough to be useful
    # A Gram matrix coupling far-apart columns is not banded: left to the dense bound.
    far = sp.csc_matrix(np.eye(200) + np.eye(200, k=150))
    assert gram_lower_bound(far) is None


def test_the_banded_free_factor_bound_encloses_the_states():
    system = triangle_system()
    _, ys = ss.simulate(system, X0, 15, np.random.default_rng(5))
    Z = ss.trajectory_set(system, X0, ys)
    beta = banded_free_factor_bound(Z.A, Z.b, Z.h)
    assert beta is not None and np.isfinite(beta)
    # Every state deviation over the set is at most β (its support along ±e_j of the states).
    hull = Z.interval_hull(certified=True)
    assert np.all(np.maximum(np.abs(hull.hi - Z.c), np.abs(hull.lo - Z.c)) <= beta)


def test_threads_querying_the_same_views_get_the_serial_answers():
    from concurrent.futures import ThreadPoolExecutor

    system = smoothing_example_31()
    _, ys = ss.simulate(system, X0, HORIZON + 2, np.random.default_rng(6))
    views = ss.classical_filter(system, X0, ys)
    picks = [3, 30, 50, len(ys) - 1]
    D = np.vstack([np.eye(2), -np.eye(2)])
    serial = [views[k].support_many(D) for k in picks]
    fresh = ss.classical_filter(system, X0, ys)  # no answers cached on these views yet
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(lambda k: fresh[k].support_many(D), picks * 2))
    for got, want in zip(threaded, serial * 2):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-7 * (1 + np.abs(want).max()))


@pytest.mark.parametrize("seed", [0, 1])
def test_views_of_time_varying_systems_with_inputs_are_the_recursion_posteriors(seed):
    from tests.test_trajectories import _random_system

    rng = np.random.default_rng(100 + seed)
    system = _random_system(rng, 3, time_varying=True, with_input=True, sparse_noise=seed == 1)
    prior = ss.Box(-np.ones(3), np.ones(3))
    _, ys = ss.simulate(system, prior, 25, rng)
    views, recursion = posterior_views(system, prior, ys), recursion_posteriors(system, prior, ys)
    D = np.vstack([np.eye(3), -np.eye(3), rng.standard_normal((4, 3))])
    for k in (0, 4, 25):
        ours, theirs = views[k].support_many(D), recursion[k].support_many(D)
        np.testing.assert_allclose(ours, theirs, atol=1e-6 * (1 + np.abs(theirs).max()), err_msg=f"k={k}")


def _factor_extremes(Z: ss.ConstrainedZonotope) -> float:
    """max ‖ξ_F‖∞ over Z's factor set by HiGHS (one LP per free factor and sign)."""
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    h = np.asarray(Z.h)
    bounds = [(-hj, hj) if np.isfinite(hj) else (None, None) for hj in h]
    worst = 0.0
    for j in np.flatnonzero(~np.isfinite(h)):
        for sign in (1.0, -1.0):
            cost = np.zeros(h.size)
            cost[j] = -sign
            res = linprog(cost, A_eq=A, b_eq=Z.b, bounds=bounds, method="highs")
            assert res.status == 0
            worst = max(worst, -res.fun)
    return worst


def test_joined_factor_sets_carry_their_parts_free_bounds_soundly():
    # A generalized intersection of a posterior view (free state factors, banded bound) with a CZ
    # noise keeps the view's bound: no dense eigenvalue problem on the result, and the bound holds.
    system = triangle_system()
    rng = np.random.default_rng(5)
    ys = rng.uniform(-1.0, 1.0, size=(6, system.m))
    views = ss.classical_filter(system, X0, ys)
    P = views[3]
    S = generalized_intersection(P, system.A_at(3), minkowski_sum(views[4], system.W))
    beta = S.factors._free_bound
    assert beta is not None and beta[0] == max(P.factors.free_bound(), views[4].factors.free_bound())
    assert _factor_extremes(S) <= beta[0]
    # Sums with sets that have no free factors keep the bound; with none free there is nothing to carry.
    assert minkowski_sum(P, system.W).factors._free_bound == (P.factors.free_bound(),)
    assert minkowski_sum(ss.ConstrainedZonotope(np.eye(2), np.zeros(2)), TRIANGLE)._factors is None


def test_recursion_smoother_on_view_posteriors_certifies_beyond_the_dense_bound(monkeypatch):
    # The recursion smoother on the filter's views accumulates the views' free state factors (3899 at
    # T = 29, n = 6 in reliability case 000): more than the dense bound accepts. The joined bound
    # certifies them; here the dense limit is lowered so that a short horizon shows it.
    from setsmooth.solvers import certify

    monkeypatch.setattr(certify, "FREE_BOUND_DENSE_MAX", 8)
    system = triangle_system()
    rng = np.random.default_rng(11)
    ys = rng.uniform(-1.0, 1.0, size=(7, system.m))
    views = ss.classical_filter(system, X0, ys)
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=views)
    exact = ss.optimal_smoother(system, X0, ys, method="trajectory")
    for S, E in zip(smoothed, exact):
        assert S.factors.free.size > 8
        hull, ref = S.interval_hull(certified=True), E.interval_hull(certified=False)
        width = float(np.max(ref.hi - ref.lo))
        assert np.all(hull.lo <= ref.lo + 1e-9 * width) and np.all(hull.hi >= ref.hi - 1e-9 * width)
        assert np.allclose(hull.lo, ref.lo, atol=1e-6 * width) and np.allclose(hull.hi, ref.hi, atol=1e-6 * width)
