"""Seeded random systems: reproducible, stable, observable / detectable with the n_o asked for."""

import numpy as np
import pytest

from setsmooth import analysis


def test_same_seed_gives_the_same_system_and_another_seed_another():
    a = analysis.random_observable_system(np.random.default_rng(5), 6, 3, 2)
    b = analysis.random_observable_system(np.random.default_rng(5), 6, 3, 2)
    c = analysis.random_observable_system(np.random.default_rng(6), 6, 3, 2)
    assert np.array_equal(a.A, b.A) and np.array_equal(a.B, b.B) and np.array_equal(a.C, b.C)
    assert not np.allclose(a.A, c.A)


def test_the_global_numpy_generator_is_not_touched():
    np.random.seed(0)
    before = np.random.random()
    np.random.seed(0)
    analysis.random_detectable_system(np.random.default_rng(1), 6, 4, 2, 2)
    assert np.random.random() == before


@pytest.mark.parametrize("seed", range(10))
def test_observable_draws_are_observable_with_poles_in_the_closed_unit_disk(seed):
    s = analysis.random_observable_system(np.random.default_rng(seed), 8, 4, 3)
    assert s.A.shape == (8, 8) and s.B.shape == (8, 4) and s.C.shape == (3, 8)
    assert analysis.is_observable(s.A, s.C)
    assert analysis.spectral_radius(s.A) <= 1.0 + 1e-9


def test_integrators_appear_with_the_requested_probability():
    rng = np.random.default_rng(0)
    always = analysis.random_stable_matrix(rng, 5, unit_pole_probability=1.0)
    assert np.allclose(always, np.eye(5))
    never = [analysis.random_stable_matrix(rng, 5, unit_pole_probability=0.0) for _ in range(20)]
    assert max(analysis.spectral_radius(M) for M in never) < 1.0


@pytest.mark.parametrize("n_o", [1, 3, 5])
def test_detectable_draws_have_the_chosen_observable_dimension(n_o):
    rng = np.random.default_rng(10 + n_o)
    s = analysis.random_detectable_system(rng, 6, n_o, 2, 3, s_max=0.5)
    dec = s.decomposition
    assert dec.n_o == n_o and analysis.observability_decomposition(s.A, s.C).n_o == n_o
    assert analysis.is_detectable(s.A, s.C) and analysis.spectral_radius(dec.A_obar) <= 0.5 + 1e-12
    assert np.allclose(dec.P @ dec.P.T, np.eye(6))
    # The blocks put in are the blocks read back: Ã_21 and B̃_ō uniform on [0, 1] entries.
    assert np.all((dec.A_21 > -1e-12) & (dec.A_21 < 1 + 1e-12))
    assert np.all((dec.B_obar > -1e-12) & (dec.B_obar < 1 + 1e-12))
    system = s.linear_system()
    assert (system.n, system.p, system.m) == (6, 2, 3)


def test_bad_arguments_are_named():
    rng = np.random.default_rng(0)
    with pytest.raises(TypeError, match="rng"):
        analysis.random_observable_system(0, 3, 1, 1)
    with pytest.raises(ValueError, match="n_o must be smaller"):
        analysis.random_detectable_system(rng, 3, 3, 1, 1)
    with pytest.raises(ValueError, match="s_max"):
        analysis.random_detectable_system(rng, 3, 2, 1, 1, s_max=1.0)
    with pytest.raises(ValueError, match="unit_pole_probability"):
        analysis.random_stable_matrix(rng, 3, unit_pole_probability=2.0)


def test_systems_and_decompositions_pickle_and_hash():
    import pickle

    s = analysis.random_detectable_system(np.random.default_rng(2), 5, 3, 2, 2)
    t = pickle.loads(pickle.dumps(s))
    assert np.array_equal(t.A, s.A) and np.array_equal(t.decomposition.A_obar, s.decomposition.A_obar)
    assert {s: 1, s.decomposition: 2}[s.decomposition] == 2          # identity-hashed, not array-compared
    with pytest.raises(ValueError, match="read-only"):
        s.decomposition.P[0, 0] = 1.0                                # immutable
