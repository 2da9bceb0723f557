"""Observation-information sets O_{k,i} (stability (12)) and the OIT (Definition 6).

Oracles: the closed-form interval of a scalar system, the classical filter's posterior (Proposition 1:
it lies in the tower for every initial condition), the window F_{k,k−δ}(ℝⁿ), the true states, and the
diameter bound (16).
"""

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis

UNIT1 = ss.Box([-1.0], [1.0])


def _example25():
    return ss.LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]], W=UNIT1, V=UNIT1)


def test_scalar_observation_information_set_in_closed_form():
    a = 1.5
    system = ss.LinearSystem([[a]], None, [[1.0]], W=UNIT1, V=UNIT1)
    ys = np.array([[0.3], [0.7], [-0.2], [0.1]])
    for i in range(4):
        for k in range(i, 6):
            hull = ss.observation_information_set(system, ys, k, i).interval_hull()
            spread = sum(a ** (k - 1 - r) for r in range(i, k))
            lo = a ** (k - i) * (ys[i, 0] - 1) - spread
            hi = a ** (k - i) * (ys[i, 0] + 1) + spread
            assert hull.lo[0] == pytest.approx(lo, abs=1e-7) and hull.hi[0] == pytest.approx(hi, abs=1e-7)


def test_observation_set_is_unbounded_along_the_kernel_of_C():
    O = ss.observation_information_set(_example25(), [[1.0]], 0, 0)
    assert O.support([0.0, 1.0]) == np.inf and O.support([1.0, 0.0]) == pytest.approx(2.0, abs=1e-7)


@pytest.mark.parametrize("seed", range(3))
def test_tower_contains_true_state_posterior_and_window(seed):
    system = _example25()
    rng = np.random.default_rng(seed)
    xs, ys = ss.simulate(system, ss.Box([1.0, 1.0], [3.0, 3.0]), 6, rng)
    X0 = ss.Box([0.0, 0.0], [4.0, 4.0])
    posts = ss.classical_filter(system, X0, ys)
    D = rng.standard_normal((16, 2))
    for k in range(1, 7):
        for delta in range(1, k + 1):
            tower = ss.observation_information_tower(system, ys, k, delta)
            assert tower.contains(xs[k])
            h_tower = tower.support_many(D)
            assert np.all(posts[k].support_many(D) <= h_tower + 1e-6)                    # (14)-(15)
            window = ss.filtering_map(system, ss.Reals(2), ys, k - delta, k)
            assert np.all(window.support_many(D) <= h_tower + 1e-6)                      # converse of (11) fails


def test_tower_shrinks_as_delta_grows():
    system = _example25()
    _, ys = ss.simulate(system, ss.Box([1.0, 1.0], [3.0, 3.0]), 5, np.random.default_rng(4))
    D = np.random.default_rng(0).standard_normal((12, 2))
    prev = None
    for delta in range(1, 6):
        h = ss.observation_information_tower(system, ys, 5, delta).support_many(D)
        if prev is not None:
            assert np.all(h <= prev + 1e-6)
        prev = h


@pytest.mark.parametrize("seed", range(4))
def test_tower_diameter_respects_bound_16(seed):
    system = _example25()
    _, ys = ss.simulate(system, ss.Box([1.0, 1.0], [3.0, 3.0]), 8, np.random.default_rng(seed))
    A, B, C = system.A_at(0), system.E_at(0), system.C_at(0)
    for delta in (1, 2, 3):
        bound = analysis.oit_diameter_bound(A, B, C, system.W, system.V, delta)
        for k in (delta, 8):
            tower = ss.observation_information_tower(system, ys, k, delta)
            assert analysis.diameter(tower, 2) <= bound * (1 + 1e-9)


def test_tower_arguments_are_checked():
    system = _example25()
    ys = np.zeros((3, 1))
    with pytest.raises(ValueError, match="delta must satisfy 0 ≤ delta ≤ k = 1"):
        ss.observation_information_tower(system, ys, 1, 2)
    with pytest.raises(ValueError, match="k must satisfy 0 ≤ k ≤ T = 2"):
        ss.observation_information_tower(system, ys, 3, 0)
    with pytest.raises(ValueError, match="k ≥ i = 2"):
        ss.observation_information_set(system, ys, 1, 2)
