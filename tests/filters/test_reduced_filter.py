"""The bounded (reduced) classical filter: an outer bound of the exact posterior, every step.

Monte Carlo over the seeded trials of `setsmooth.reliability.reduced_filter_trials` (random
`control.drss` systems, box and constrained-zonotope noises, horizon 8; 20 steps in
``benchmarks/bench_reduction.py --montecarlo``): the true state must be inside every reduced posterior;
on a subset, every reduced posterior must contain the exact one.
"""

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.reliability.reduced_filter_trials import PIPELINES, drss, holds, trial

RUNS = 1000

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
