"""Seeded trials of the reduced (bounded) classical filter: random systems, noises and trajectories.

Random `control.drss` systems (n = 2..10, m = 1..n outputs, seeded), with box noises (drawn uniformly or
at the vertices, the hardest case for a bound) or constrained-zonotope noises, and the reduction
pipelines they cycle through. ``tests/filters/test_reduced_filter.py`` (horizon 8) and
``benchmarks/bench_reduction.py --montecarlo`` (20 steps) check that the true state is inside every
reduced posterior; `holds` decides membership, independently of Clarabel where it cannot.
"""

from __future__ import annotations

import control
import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.sparse as sp

import setsmooth as ss

__all__ = ["HORIZONS", "PIPELINES", "drss", "CZNoise", "trial", "holds"]

#: Posteriors k = 0..T, T drawn in this range per run (8: tests/filters/test_reduced_filter.py stays ~1 min).
HORIZONS = (8, 8)

#: The reduction pipelines the runs cycle through (run r takes the (r mod 5)-th).
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

