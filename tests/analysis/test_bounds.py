"""The OIT diameter bound (16) and Υ∞ (Algorithm 3, Line 1) against direct evaluation."""

import math

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis

A25, B25, C25 = np.array([[1.0, 1.0], [0.0, 1.0]]), np.array([[0.5], [1.0]]), np.array([[1.0, 0.0]])


def test_bound_16_for_example_25_by_hand():
    # δ = 1: O_1 = [C A^{-1}; C] = [[1, -1], [1, 0]], σ_min = (√5 − 1)/2; C A^{-1} B = −0.5.
    d_w = d_v = 2.0
    expected = math.sqrt((d_v + 0.5 * d_w) ** 2 + d_v ** 2) / ((math.sqrt(5) - 1) / 2)
    assert analysis.oit_diameter_bound(A25, B25, C25, d_w, d_v, 1) == pytest.approx(expected, rel=1e-12)
    # Sets give their 2-norm diameters (2√p for the unit box).
    W, V = ss.Box([-1], [1]), ss.Box([-1], [1])
    assert analysis.oit_diameter_bound(A25, B25, C25, W, V, 1) == pytest.approx(expected, rel=1e-9)


def test_minimized_bound_is_the_least_over_the_range_searched():
    best = analysis.minimize_oit_diameter_bound(A25, B25, C25, 2.0, 2.0, delta_max=6)
    values = [analysis.oit_diameter_bound(A25, B25, C25, 2.0, 2.0, d) for d in range(1, 7)]
    assert best.values == pytest.approx(values)
    assert best.delta == 1 and best.value == min(values)


def test_bound_16_refuses_what_theorem_1_excludes():
    with pytest.raises(ValueError, match="observable"):
        analysis.oit_diameter_bound([[0.5, 1.0], [0.0, 1.0]], B25, [[0.0, 1.0]], 2.0, 2.0, 1)
    with pytest.raises(ValueError, match="nonsingular"):
        analysis.oit_diameter_bound([[0.0, 1.0], [0.0, 0.0]], B25, [[1.0, 0.0]], 2.0, 2.0, 2)
    with pytest.raises(ValueError, match="at least mu - 1 = 1"):
        analysis.oit_diameter_bound(A25, B25, C25, 2.0, 2.0, 0)
    with pytest.raises(ValueError, match="W must be"):
        analysis.oit_diameter_bound(A25, B25, C25, -1.0, 2.0, 1)


def _f(M, gamma, K=20000):
    P, best, Mg = np.eye(M.shape[0]), 1.0, M / gamma
    for _ in range(1, K):
        P = P @ Mg
        norm = np.abs(P).sum(axis=1).max()
        best = max(best, norm)
        if norm < 1e-12:
            break
    return best / (1 - gamma)


@pytest.mark.parametrize("M", [
    np.array([[0.5]]),
    np.array([[0.9, 1.0], [0.0, 0.9]]),                      # defective: β blows up near ρ
    np.array([[0.3, 2.0, 0.0], [0.0, -0.4, 3.0], [0.0, 0.0, 0.2]]),
    np.array([[0.0, 1.0], [-0.5, 0.8]]),                     # complex pair
])
def test_upsilon_is_attained_bounds_the_power_sum_and_beats_a_fine_grid(M):
    up = analysis.upsilon_search(M)
    rho = analysis.spectral_radius(M)
    assert rho < up.gamma < 1
    assert up.value == pytest.approx(_f(M, up.gamma), rel=1e-9)          # attained at its γ
    powers = sum(np.abs(np.linalg.matrix_power(M, j)).sum(axis=1).max() for j in range(3000))
    assert up.value >= powers * (1 - 1e-12)                              # Lemma 4
    grid = rho + (1 - rho) * np.linspace(0.05, 0.995, 150)
    assert up.value <= min(_f(M, g) for g in grid) * (1 + 1e-9)


def test_upsilon_of_one_half_is_two_from_above():
    value = analysis.upsilon_inf([[0.5]])
    assert 2.0 <= value < 2.0 + 1e-5           # the authors' grid gives 2.002


def test_upsilon_edge_cases():
    assert analysis.upsilon_inf(np.zeros((0, 0))) == 0.0
    assert analysis.upsilon_inf([[0.0]]) == pytest.approx(1.0, abs=1e-5)
    with pytest.raises(ValueError, match="spectral radius < 1"):
        analysis.upsilon_inf([[1.0]])
