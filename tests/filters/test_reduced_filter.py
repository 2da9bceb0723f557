"""The bounded (reduced) classical filter: an outer bound of the exact posterior, every step.

Monte Carlo over random `control.drss` systems (n = 2..10, m = 1..n outputs, horizon 8, seeded; 20
steps in ``benchmarks/bench_reduction.py --montecarlo``), with box noises (drawn uniformly or at the
vertices, the hardest case for a bound) and constrained-zonotope noises: the true state must be
inside every reduced posterior; on a subset, every reduced posterior must contain the exact one.
"""

import control
import numpy as np
import pytest
import scipy.linalg
import scipy.optimize
import scipy.sparse as sp

import setsmooth as ss

RUNS = 1000
HORIZONS = (8, 8)  # posteriors k = 0..T, T drawn in this range per run (8: the file stays ~1 min)
PIPELINES = {
    "cora_girard": ss.CORA_GIRARD,
    "cora_combastel": ss.CORA_COMBASTEL,
    "eliminate2_combastel2": (ss.EliminateConstraints(2), ss.Combastel(2)),
    "rescale_exact_girard": (ss.Rescale("exact"), ss.EliminateConstraints(1), ss.Girard(1.5)),
    "interval_hull": ss.IntervalHull(),
}


def drss(seed: int, n: int, m: int):
    """control.drss(n, m, n) (m outputs) from a seed; python-control draws from NumPy's global
    generator, whose state is restored afterwards so that nothing else sees the seeding."""
    state = np.random.get_state()
    try:
        np.random.seed(seed)
        return control.drss(n, m, n)
    finally:
        np.random.set_state(state)


class CZNoise:
    """A random constrained-zonotope noise range Z(G, 0, a, a·ξ0) with a sampler of its members."""

    def __init__(self, rng: np.random.Generator, dim: int):
        ng = dim + 1
        self.G = np.hstack([np.eye(dim), 0.5 * rng.standard_normal((dim, 1))])
        self.a = rng.standard_normal((1, ng))
        self.xi0 = rng.uniform(-0.5, 0.5, ng)
        self.null = scipy.linalg.null_space(self.a)
        self.set = ss.ConstrainedZonotope(self.G, np.zeros(dim), A=self.a, b=self.a @ self.xi0)

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """ξ0 + t·v, v in ker(a), pushed to the factor box's boundary in a random direction."""
        v = self.null @ rng.standard_normal(self.null.shape[1])
        with np.errstate(divide="ignore"):
            steps = np.where(v != 0, (np.sign(v) - self.xi0) / v, np.inf)
        t = rng.uniform(0.0, 1.0) * np.min(steps[steps > 0], initial=0.0)
        return self.G @ (self.xi0 + t * v)


def trial(run: int, horizon: int | None = None):
    """One seeded run: system, noises, trajectory. Returns (system, X0, xs, ys, pipeline name).

    n = 2..10; m = n in a third of the runs, fewer outputs (1..n−1) otherwise, so most posteriors are
    bounded by the dynamics, not by one measurement; horizon T in HORIZONS unless given.
    """
    rng = np.random.default_rng([run, 6])
    n = int(rng.integers(2, 11))
    m = n if run % 3 == 1 else int(rng.integers(1, n))
    T = int(rng.integers(HORIZONS[0], HORIZONS[1] + 1)) if horizon is None else horizon
    sysc = drss(10_000 + run, n, m)
    kind = ("uniform", "vertices", "cz")[run % 3]
    if kind == "cz":
        W, V = CZNoise(rng, n), CZNoise(rng, m)
        system = ss.LinearSystem(sysc.A, None, sysc.C, E=sysc.B, W=W.set, V=V.set)
        draw_w, draw_v = W.sample, V.sample
    else:
        system = ss.LinearSystem(sysc.A, None, sysc.C, E=sysc.B, W=ss.Box(-np.ones(n), np.ones(n)),
                                 V=ss.Box(-np.ones(m), np.ones(m)))

        def box_draw(dim):
            def draw(r):
                return r.choice([-1.0, 1.0], dim) if kind == "vertices" else r.uniform(-1, 1, dim)
            return draw
        draw_w, draw_v = box_draw(n), box_draw(m)
    X0 = ss.Box(-3 * np.ones(n), 3 * np.ones(n))
    xs = [rng.uniform(-3, 3, n)]
    for _ in range(T):
        xs.append(sysc.A @ xs[-1] + sysc.B @ draw_w(rng))
    ys = np.array([sysc.C @ x + draw_v(rng) for x in xs])
    names = list(PIPELINES)
    return system, X0, np.array(xs), ys, names[run % len(names)]


def holds(post: ss.ConvexSet, x: np.ndarray) -> bool:
    """x ∈ post. A reduced filter can blow up (m < n, order-1 reduction: the wrapping effect the
    stability paper studies), and membership in a CZ of generators ~1e9 may be beyond Clarabel's
    accuracy (`SolverError`): then it is decided by an independent HiGHS LP, the smallest relative
    violation t of Gξ = x − c, Aξ = b over the factor box, inside when t ≤ MEMBERSHIP_TOL."""
    try:
        return post.contains(x)
    except ss.SolverError:
        pass
    G = post.G.toarray() if sp.issparse(post.G) else np.asarray(post.G)
    A = post.A.toarray() if sp.issparse(post.A) else np.asarray(post.A)
    M = np.vstack([G, A])
    rhs = np.concatenate([x - post.c, post.b])
    scale = 1.0 + np.abs(rhs) + np.abs(M) @ post.h
    # |Mξ − rhs| ≤ t·scale, |ξ| ≤ h, rows divided by their scale (a blown-up set has entries ~1e15,
    # which HiGHS refuses): variables (ξ, t), minimize t.
    Ms, rs, ones = M / scale[:, None], rhs / scale, np.ones((M.shape[0], 1))
    A_ub = np.vstack([np.hstack([Ms, -ones]), np.hstack([-Ms, -ones])])
    b_ub = np.concatenate([rs, -rs])
    bounds = [(-hj, hj) for hj in post.h] + [(0, None)]
    cost = np.zeros(M.shape[1] + 1)
    cost[-1] = 1.0
    res = scipy.optimize.linprog(cost, A_ub=A_ub, b_ub=b_ub, bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return bool(res.fun <= ss.tolerances.MEMBERSHIP_TOL)


CHUNKS = 8


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_true_state_is_inside_every_reduced_posterior(chunk):
    # 1000 runs in 8 chunks (parallel under xdist); every pipeline and noise kind in each chunk.
    outside = []
    for run in range(chunk, RUNS, CHUNKS):
        system, X0, xs, ys, name = trial(run)
        posteriors = ss.classical_filter(system, X0, ys, reduce=PIPELINES[name], detect_empty=False)
        for k, (post, x) in enumerate(zip(posteriors, xs)):
            if not holds(post, x):
                outside.append((run, name, k))
    assert outside == []


@pytest.mark.parametrize("run", range(0, 60, 3))
def test_reduced_posterior_contains_exact_posterior(run):
    system, X0, xs, ys, name = trial(run)
    exact = ss.classical_filter(system, X0, ys, detect_empty=False)
    reduced = ss.classical_filter(system, X0, ys, reduce=PIPELINES[name], detect_empty=False)
    rng = np.random.default_rng(run)
    D = np.vstack([rng.standard_normal((40, system.n)), np.eye(system.n), -np.eye(system.n)])
    for k, (E, R) in enumerate(zip(exact, reduced)):
        he, hr = E.support_many(D), R.support_many(D)
        scale = 1.0 + np.abs(he).max()
        assert np.all(hr >= he - 1e-7 * scale), (name, k, (he - hr).max() / scale)


@pytest.mark.parametrize("pipeline", [ss.CORA_GIRARD, ss.CORA_COMBASTEL])
def test_cora_reduced_filter_keeps_complexity_bounded(pipeline):
    # 30 steps simulated with the system's own noises (ss.simulate): every posterior is non-empty,
    # holds the true state, and has one constraint and DOF order one after the reduction.
    system, X0, _, _, _ = trial(1)
    xs, ys = ss.simulate(system, X0, 30, np.random.default_rng(0))
    posteriors = ss.classical_filter(system, X0, ys, reduce=pipeline)
    assert len(posteriors) == 31
    for post, x in zip(posteriors, xs):
        assert not isinstance(post, ss.EmptySet)
        assert holds(post, x)
        if isinstance(post, ss.ConstrainedZonotope):
            assert post.nc <= 1 and post.ng - post.nc <= system.n


def _cz(S: ss.ConvexSet):
    """(G, c, A, b, h) of a set as dense arrays (boxes and CZs)."""
    Z = S if isinstance(S, ss.ConstrainedZonotope) else S.to_constrained_zonotope()
    dense = [M.toarray() if sp.issparse(M) else np.asarray(M, dtype=float) for M in (Z.G, Z.A)]
    return dense[0], np.asarray(Z.c, float), dense[1], np.asarray(Z.b, float), np.asarray(Z.h, float)


def _exact_posteriors(A, B, C, X0, W, V, ys):
    """The exact posteriors written out with the CZ formulas of Scott et al. 2016 (linear map,
    Minkowski sum, generalized intersection with {x : Cx ∈ y − V}), independently of the filter."""
    G, c, Ac, b, h = _cz(X0)
    Gw, cw, Aw, bw, hw = _cz(W)
    Gv, cv, Av, bv, hv = _cz(V)
    out = []
    for k, y in enumerate(ys):
        if k:  # prior: A·post ⊕ B·W
            G, c = np.hstack([A @ G, B @ Gw]), A @ c + B @ cw
            Ac, b, h = scipy.linalg.block_diag(Ac, Aw), np.concatenate([b, bw]), np.concatenate([h, hw])
        # C(c + Gξ) + cv + Gv·η = y, η in V's factors
        nv = Gv.shape[1]
        Ac = np.vstack([np.hstack([Ac, np.zeros((Ac.shape[0], nv))]),
                        np.hstack([np.zeros((Av.shape[0], G.shape[1])), Av]),
                        np.hstack([C @ G, Gv])])
        b = np.concatenate([b, bv, y - C @ c - cv])
        G, h = np.hstack([G, np.zeros((G.shape[0], nv))]), np.concatenate([h, hv])
        out.append(ss.ConstrainedZonotope(G, c, A=Ac, b=b, h=h))
    return out


@pytest.mark.parametrize("run", [1, 2])
def test_without_reduce_the_filter_is_exact(run):
    # reduce=None is the exact filter: same supports as the posteriors written out by hand.
    system, X0, xs, ys, _ = trial(run, horizon=4)
    rng = np.random.default_rng(run)
    sysc = drss(10_000 + run, system.n, system.m)
    by_hand = _exact_posteriors(sysc.A, sysc.B, sysc.C, X0, system.W, system.V, ys)
    plain = ss.classical_filter(system, X0, ys, reduce=None)
    D = np.vstack([rng.standard_normal((30, system.n)), np.eye(system.n), -np.eye(system.n)])
    for k, (P, E) in enumerate(zip(plain, by_hand)):
        hp, he = P.support_many(D), E.support_many(D)
        scale = 1.0 + np.abs(he).max()
        np.testing.assert_allclose(hp, he, atol=1e-6 * scale, err_msg=f"k = {k}")
    counts = [p.nc for p in plain]
    assert all(a < b for a, b in zip(counts, counts[1:]))  # one more strip per measurement


def test_bad_reduce_argument_is_refused_at_the_door():
    system, X0, xs, ys, _ = trial(0)
    with pytest.raises(TypeError, match="reduce"):
        ss.classical_filter(system, X0, ys, reduce="girard")
    with pytest.raises(TypeError, match="reduce"):
        ss.classical_filter(system, X0, ys, reduce=[ss.Girard(1), 3])
