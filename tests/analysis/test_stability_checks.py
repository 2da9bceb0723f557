"""Theorem 2, Proposition 2 and Corollary 1 verdicts on the paper's designers and on constructed cases."""

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis

TRUE_X0 = ss.Box([1.0, 1.0], [3.0, 3.0])
DESIGNERS = {"Alice": (0.0, 4.0), "Bob": (-4.0, 4.0), "Carol": (-1.0, 1.0), "David": (-2.0, 2.0)}


def _box(lo, hi):
    return ss.Box([lo, lo], [hi, hi])


@pytest.mark.parametrize("name", DESIGNERS)
def test_theorem2_on_example_25_holds_exactly_for_alice_and_bob(name):
    A, C = [[1.0, 1.0], [0.0, 1.0]], [[1.0, 0.0]]
    res = analysis.check_stability_criterion(A, C, _box(*DESIGNERS[name]), TRUE_X0)
    assert res.holds is (name in ("Alice", "Bob"))
    assert res.conditions[1].holds                       # observable: (ii) always
    assert "Theorem 2" in str(res)


@pytest.mark.parametrize("name", DESIGNERS)
def test_corollary1_on_example_26(name):
    A, C = [[0.5, 1.0], [0.0, 1.0]], [[0.0, 1.0]]
    res = analysis.check_egregium(A, C, _box(*DESIGNERS[name]), TRUE_X0)
    assert res.conditions[2].holds                       # detectable, ρ(Ã_ō) = 0.5
    assert res.holds is (name in ("Alice", "Bob"))
    # Only the observable coordinate x2 matters: a box wrong in x1 alone still satisfies (i).
    shifted = ss.Box([-10.0, 0.0], [-9.0, 4.0])
    assert analysis.check_egregium(A, C, shifted, TRUE_X0).holds


def _partial_sums_bounded(A_obar, A_21, K=4000):
    """Bounded when the largest entry seen by K steps is not much above that seen by K/2 (linear or
    faster growth at least doubles it)."""
    S, P, top, half = np.zeros_like(A_21), np.eye(A_obar.shape[0]), 0.0, 0.0
    for k in range(K):
        S = S + P @ A_21
        P = P @ A_obar
        top = max(top, np.abs(S).max(), np.abs(P).max())
        if k == K // 2:
            half = top
    return bool(top < 1.2 * half)


@pytest.mark.parametrize("A_obar, A_21", [
    (np.array([[1.0]]), np.array([[0.0]])),                                    # integrator, no drive
    (np.array([[1.0]]), np.array([[1.0]])),                                    # integrator, driven
    (np.array([[-1.0]]), np.array([[1.0]])),                                   # −1: alternating, bounded
    (np.array([[0.9, 1.0], [0.0, 0.9]]), np.array([[1.0], [1.0]])),            # stable
    (np.array([[1.0, 0.0], [0.0, 0.5]]), np.array([[0.0], [1.0]])),            # drive misses eigenvalue 1
    (np.array([[1.0, 1.0], [0.0, 1.0]]), np.array([[0.0], [0.0]])),            # Jordan block at 1
    (np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]]), np.array([[1.0], [0.0]])),
])
def test_condition_ii_agrees_with_the_growth_of_the_partial_sums(A_obar, A_21):
    n_obar = A_obar.shape[0]
    A_tilde = np.block([[np.array([[0.5]]), np.zeros((1, n_obar))], [A_21, A_obar]])
    Q = np.linalg.qr(np.random.default_rng(0).standard_normal((1 + n_obar, 1 + n_obar)))[0]
    A = Q.T @ A_tilde @ Q
    C = np.hstack([[[1.0]], np.zeros((1, n_obar))]) @ Q
    dec = analysis.observability_decomposition(A, C, P=Q, n_o=1)
    assert analysis.condition_ii(dec).holds is _partial_sums_bounded(A_obar, A_21)


def test_proposition2_says_the_gap_is_unbounded_when_the_unobservable_part_is_unstable():
    A, C = [[0.5, 0.0], [0.0, 1.2]], [[1.0, 0.0]]
    res = analysis.check_bounded_gap_necessary(A, C, _box(0.0, 4.0), TRUE_X0)
    assert not res.holds and "cannot be bounded" in res.conclusion
    ok = analysis.check_bounded_gap_necessary([[0.5, 0.0], [0.0, 1.0]], C, _box(0.0, 4.0), TRUE_X0)
    assert ok.holds and "not sufficient" in ok.conclusion


def test_contains_set_agrees_with_sampled_points():
    rng = np.random.default_rng(1)
    for _ in range(20):
        G = rng.standard_normal((2, 3))
        Z = ss.Zonotope(G, rng.standard_normal(2))
        inner = ss.Box(*np.sort(rng.uniform(-2, 2, (2, 2)), axis=0))
        verdict = analysis.contains_set(Z, inner)
        corners = analysis.polytope_vertices(inner)
        assert verdict == all(Z.contains(c) for c in corners)
        # Through the other route (polygon facets of the outer set) with a non-box inner set.
        assert analysis.contains_set(Z, ss.Zonotope(0.5 * G, Z.c)) is True
        assert analysis.contains_set(Z, ss.Zonotope(1.5 * G, Z.c)) is False


def test_condition_i_rejects_sets_of_the_wrong_dimension():
    with pytest.raises(ValueError, match="initial_condition"):
        analysis.check_stability_criterion([[1.0]], [[1.0]], _box(0, 1), ss.Box([0.0], [1.0]))
