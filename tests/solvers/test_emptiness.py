"""Emptiness on flat and nearly empty sets: settled without SolverError, agreeing with the hull."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import tolerances as tol


def gap_intersection(gap: float, dim: int = 2) -> ss.ConstrainedZonotope:
    """[0, 1]^dim ∩ ([1 + gap, 2] × [0, 1]^(dim−1)) as one CZ: empty iff gap > 0."""
    left = ss.ConstrainedZonotope(0.5 * np.eye(dim), 0.5 * np.ones(dim))
    shift = np.full(dim, 0.5)
    shift[0] = 1.5 + gap / 2
    half = 0.5 * np.eye(dim)
    half[0, 0] = 0.5 - gap / 2
    right = ss.ConstrainedZonotope(half, shift)
    return left & right


@pytest.mark.parametrize("gap", [1e-9, 1e-8, 1e-7, 1e-6, 1e-5, -1e-9, -1e-6])
def test_nearly_empty_sets_agree_between_is_empty_and_the_interval_hull(gap):
    Z = gap_intersection(gap)
    empty = Z.is_empty()
    hull = Z.interval_hull()  # never raises
    assert hull.is_empty() == empty
    if gap <= 0:  # an overlap, however thin, is a set
        assert not empty
    if gap >= 1e-6:  # far beyond the solver's accuracy
        assert empty
    if not empty and gap <= 0:  # the certified hull encloses the exact set: x1 ∈ [1 + gap, 1]
        certified = Z.interval_hull(certified=True)
        assert certified.lo[0] <= 1.0 + gap and certified.hi[0] >= 1.0


def test_a_fresh_nearly_empty_set_gives_the_same_verdicts_in_either_order():
    for gap in (1e-9, 3e-8, 1e-7):
        first_hull = gap_intersection(gap)
        hull_empty = first_hull.interval_hull().is_empty()
        assert hull_empty == first_hull.is_empty()
        first_verdict = gap_intersection(gap)
        verdict = first_verdict.is_empty()
        assert first_verdict.interval_hull().is_empty() == verdict


def test_flat_sets_pinned_by_the_data_are_not_empty_and_have_flat_hulls():
    # y = C x with C of rank 1 and no noise in one output: the posterior is a segment.
    prior = ss.ConstrainedZonotope(np.eye(2), np.zeros(2))
    C = np.array([[1.0, 1.0], [2.0, 2.0]])
    V = ss.ConstrainedZonotope(np.array([[1e-3], [2e-3]]), np.zeros(2))  # one noise dim, 2 outputs
    post = prior.generalized_intersection(V + np.array([0.3, 0.6]), C) if hasattr(
        prior, "generalized_intersection") else prior._generalized_intersection(C, V + np.array([0.3, 0.6]))
    assert not post.is_empty()
    hull = post.interval_hull()
    assert not hull.is_empty()
    # x1 + x2 ∈ 0.3 ± 1e-3 within the unit box: x1 ∈ [−0.701, 1]
    assert hull.lo[0] == pytest.approx(-0.701, abs=1e-6) and hull.hi[0] == pytest.approx(1.0, abs=1e-6)


def test_an_exactly_contradictory_dependent_row_means_empty():
    Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0], [2.0, 2.0]], b=[0.5, 1.5])
    assert Z.is_empty() and Z.interval_hull().is_empty()
    assert np.isneginf(Z.support([1.0, 0.0]))


def test_the_phase_one_tolerance_is_above_the_solver_accuracy():
    assert tol.SOLVER_TOL < tol.EMPTINESS_TOL < tol.SOLVER_CHECK_TOL


def triangle_system() -> ss.LinearSystem:
    """Example (31) with B = I and a triangular CZ process noise (issue 8)."""
    s1, c1 = np.sin(1.0), np.cos(1.0)
    W = ss.ConstrainedZonotope([[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], [0.0, 0.0], A=[[1.0, 1.0, 1.0]],
                               b=[1.0])
    return ss.LinearSystem([[s1, c1], [-c1, s1]], None, [[0.5, 0.5], [1.0, 0.3]], W=W,
                           V=ss.Box([-1.0, -1.0], [1.0, 1.0]))


def test_a_filter_with_triangular_cz_noise_runs_100_steps_and_keeps_the_truth():
    # Seed 0 raised SolverError('AlmostSolved') deciding emptiness before the phase-one program.
    system = triangle_system()
    W = system.W
    rng = np.random.default_rng(0)
    x, xs, ys = rng.uniform(-5, 5, 2), [], []
    for k in range(101):
        xs.append(x)
        ys.append(system.C_at(k) @ x + rng.uniform(-1, 1, 2))
        while True:  # a uniform point of the triangle's factor set
            xi = np.append(rng.uniform(-1, 1, 2), 0.0)
            xi[2] = 1.0 - xi[0] - xi[1]
            if abs(xi[2]) <= 1:
                break
        x = system.A_at(k) @ x + W.G @ xi
    posteriors = ss.classical_filter(system, ss.Box([-5, -5], [5, 5]), np.array(ys))
    for k in range(0, 101, 20):
        hull = posteriors[k].interval_hull()
        assert np.all(hull.lo - 1e-7 <= xs[k]) and np.all(xs[k] <= hull.hi + 1e-7)
