"""The bounded (reduced) classical filter: an outer bound of the exact posterior, every step.

Monte Carlo over random `control.drss` systems (n = 2..10, seeded), with box noises (drawn uniformly or
at the vertices, the hardest case for a bound) and constrained-zonotope noises: the true state must be
inside every reduced posterior; on a subset, every reduced posterior must contain the exact one.
"""

import control
import numpy as np
import pytest
import scipy.linalg

import setsmooth as ss

RUNS = 1000
HORIZON = 2  # posteriors k = 0..2
PIPELINES = {
    "cora_girard": ss.CORA_GIRARD,
    "cora_combastel": ss.CORA_COMBASTEL,
    "eliminate2_combastel2": (ss.EliminateConstraints(2), ss.Combastel(2)),
    "rescale_exact_girard": (ss.Rescale("exact"), ss.EliminateConstraints(1), ss.Girard(1.5)),
    "interval_hull": ss.IntervalHull(),
}


def drss(seed: int, n: int):
    """control.drss(n, n, n) from a seed; python-control draws from NumPy's global generator, whose
    state is restored afterwards so that nothing else sees the seeding."""
    state = np.random.get_state()
    try:
        np.random.seed(seed)
        return control.drss(n, n, n)
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


def trial(run: int):
    """One seeded run: system, noises, trajectory. Returns (system, X0, xs, ys, pipeline name)."""
    rng = np.random.default_rng([run, 6])
    n = int(rng.integers(2, 11))
    sysc = drss(10_000 + run, n)
    kind = ("uniform", "vertices", "cz")[run % 3]
    if kind == "cz":
        W, V = CZNoise(rng, n), CZNoise(rng, n)
        system = ss.LinearSystem(sysc.A, sysc.B, sysc.C, np.eye(n), W=W.set, V=V.set)
        draw_w, draw_v = W.sample, V.sample
    else:
        box = ss.Box(-np.ones(n), np.ones(n))
        system = ss.LinearSystem(sysc.A, sysc.B, sysc.C, np.eye(n), W=box, V=box)

        def draw(r):
            return r.choice([-1.0, 1.0], n) if kind == "vertices" else r.uniform(-1, 1, n)
        draw_w = draw_v = draw
    X0 = ss.Box(-3 * np.ones(n), 3 * np.ones(n))
    xs = [rng.uniform(-3, 3, n)]
    for _ in range(HORIZON):
        xs.append(sysc.A @ xs[-1] + sysc.B @ draw_w(rng))
    ys = np.array([sysc.C @ x + draw_v(rng) for x in xs])
    names = list(PIPELINES)
    return system, X0, np.array(xs), ys, names[run % len(names)]


CHUNKS = 4


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_true_state_is_inside_every_reduced_posterior(chunk):
    # 1000 runs in 4 chunks (parallel under xdist); every pipeline and noise kind in each chunk.
    outside = []
    for run in range(chunk, RUNS, CHUNKS):
        system, X0, xs, ys, name = trial(run)
        posteriors = ss.classical_filter(system, X0, ys, reduce=PIPELINES[name], detect_empty=False)
        for k, (post, x) in enumerate(zip(posteriors, xs)):
            if not post.contains(x):
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
    system, X0, xs, ys, _ = trial(1)
    rng = np.random.default_rng(0)
    n = system.n
    long_ys = np.vstack([ys, ys[-1] + rng.uniform(-0.1, 0.1, (20, n))])
    posteriors = ss.classical_filter(system, X0, long_ys, reduce=pipeline)
    for post in posteriors:
        if isinstance(post, ss.ConstrainedZonotope):
            assert post.nc <= 1 and post.ng - post.nc <= n


def test_without_reduce_the_filter_is_exact():
    system, X0, xs, ys, _ = trial(2)
    plain = ss.classical_filter(system, X0, ys)
    explicit = ss.classical_filter(system, X0, ys, reduce=None)
    for a, b in zip(plain, explicit):
        assert (a.ng, a.nc) == (b.ng, b.nc)
    counts = [p.nc for p in plain]
    assert all(a < b for a, b in zip(counts, counts[1:]))  # one more strip per measurement


def test_bad_reduce_argument_is_refused_at_the_door():
    system, X0, xs, ys, _ = trial(0)
    with pytest.raises(TypeError, match="reduce"):
        ss.classical_filter(system, X0, ys, reduce="girard")
    with pytest.raises(TypeError, match="reduce"):
        ss.classical_filter(system, X0, ys, reduce=[ss.Girard(1), 3])
