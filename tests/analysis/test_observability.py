"""Observability decomposition (stability (17)), observability index, detectability, marginal stability.

Oracles: ranks of the observability matrix formed explicitly (well-scaled systems), the PBH test for
detectability, and the growth of ‖M^k‖ for marginal stability.
"""

import numpy as np
import pytest

from setsmooth import analysis


def _obsv(A, C, k):
    return np.vstack([C @ np.linalg.matrix_power(A, j) for j in range(k)]) if k else np.zeros((0, A.shape[0]))


def _rank(M):
    return int(np.linalg.matrix_rank(M, tol=1e-8 * max(1.0, np.abs(M).max()))) if M.size else 0


def _pbh_detectable(A, C):
    n = A.shape[0]
    for lam in np.linalg.eigvals(A):
        if abs(lam) >= 1 - 1e-9:
            M = np.vstack([A - lam * np.eye(n), C.astype(complex)])
            if np.linalg.matrix_rank(M, tol=1e-8) < n:
                return False
    return True


def _random_unobservable(rng, n, n_o, m):
    """(A, C) with an unobservable subspace of dimension n - n_o, hidden by a random rotation."""
    A_t = rng.standard_normal((n, n)) * 0.5
    A_t[:n_o, n_o:] = 0.0
    C_t = np.hstack([rng.standard_normal((m, n_o)), np.zeros((m, n - n_o))])
    Q = np.linalg.qr(rng.standard_normal((n, n)))[0]
    return Q.T @ A_t @ Q, C_t @ Q


@pytest.mark.parametrize("seed", range(12))
def test_decomposition_has_the_block_structure_of_17(seed):
    rng = np.random.default_rng(seed)
    n, m = 6, int(rng.integers(1, 3))
    n_o = int(rng.integers(1, n + 1))
    A, C = _random_unobservable(rng, n, n_o, m)
    B = rng.standard_normal((n, 2))
    dec = analysis.observability_decomposition(A, C, B=B)
    assert dec.n_o == _rank(_obsv(A, C, n)) == n_o
    assert np.allclose(dec.P @ dec.P.T, np.eye(n), atol=1e-12)              # orthogonal
    At = dec.A_tilde
    assert np.allclose(At[:n_o, n_o:], 0.0, atol=1e-10)                    # Ã_12 = 0
    assert np.allclose(C @ dec.U_obar, 0.0, atol=1e-10)                    # C̃_ō = 0
    assert np.allclose(At[:n_o, :n_o], dec.A_o) and np.allclose(At[n_o:, :n_o], dec.A_21)
    assert np.allclose(At[n_o:, n_o:], dec.A_obar)
    assert _rank(_obsv(dec.A_o, dec.C_o, n_o)) == n_o                      # (Ã_o, C̃_o) observable
    B_o, B_obar = dec.split_input(B)
    assert np.allclose(B_o, dec.B_o) and np.allclose(B_obar, dec.B_obar)
    assert np.allclose(dec.from_tilde(np.vstack([B_o, B_obar])), B)


@pytest.mark.parametrize("seed", range(12))
def test_observability_index_is_the_least_k_reaching_full_rank(seed):
    rng = np.random.default_rng(100 + seed)
    n, m = 7, int(rng.integers(1, 4))
    n_o = int(rng.integers(1, n + 1))
    A, C = _random_unobservable(rng, n, n_o, m)
    full = _rank(_obsv(A, C, n))
    mu = next(k for k in range(n + 1) if _rank(_obsv(A, C, k)) == full)
    assert analysis.observability_index(A, C) == mu


def test_paper_examples_25_and_26():
    A25, C25 = np.array([[1.0, 1.0], [0.0, 1.0]]), np.array([[1.0, 0.0]])
    dec = analysis.observability_decomposition(A25, C25)
    assert dec.is_observable and dec.mu_o == 2 and dec.n_obar == 0 and dec.is_detectable
    A26, C26 = np.array([[0.5, 1.0], [0.0, 1.0]]), np.array([[0.0, 1.0]])
    dec = analysis.observability_decomposition(A26, C26, B=[[0.5], [1.0]])
    assert dec.n_o == 1 and dec.mu_o == 1 and dec.is_detectable
    assert np.allclose(np.abs(dec.A_obar), 0.5)
    # MATLAB's obsvf transformation (notes) is accepted as a given P and gives the same Ã_ō.
    matlab = analysis.observability_decomposition(A26, C26, P=[[0.0, 1.0], [-1.0, 0.0]], n_o=1)
    assert np.allclose(matlab.A_obar, 0.5) and np.allclose(matlab.A_21, -1.0)


def test_a_given_P_that_is_not_a_decomposition_is_refused():
    A26, C26 = np.array([[0.5, 1.0], [0.0, 1.0]]), np.array([[0.0, 1.0]])
    with pytest.raises(ValueError, match="not an observability decomposition"):
        analysis.observability_decomposition(A26, C26, P=np.eye(2), n_o=1)
    with pytest.raises(ValueError, match="nonsingular"):
        analysis.observability_decomposition(A26, C26, P=[[1.0, 1.0], [1.0, 1.0]], n_o=1)
    with pytest.raises(ValueError, match="n_o = 2"):
        analysis.observability_decomposition(A26, C26, P=np.eye(2), n_o=2)
    with pytest.raises(ValueError, match="C must have shape"):
        analysis.observability_decomposition(A26, [[1.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="B must have shape"):
        analysis.observability_decomposition(A26, C26).split_input(np.ones((3, 1)))


def test_eigenvalues_of_the_unobservable_block_do_not_depend_on_P():
    rng = np.random.default_rng(7)
    A, C = _random_unobservable(rng, 6, 3, 2)
    dec = analysis.observability_decomposition(A, C)
    T = np.eye(6)
    T[:3, :3] = rng.standard_normal((3, 3)) + 3 * np.eye(3)   # any nonsingular change inside each block
    T[3:, 3:] = rng.standard_normal((3, 3)) + 3 * np.eye(3)
    T[3:, :3] = rng.standard_normal((3, 3))                    # lower-triangular coupling keeps (17)
    other = analysis.observability_decomposition(A, C, P=T @ dec.P, n_o=3)
    assert np.allclose(np.sort_complex(np.linalg.eigvals(other.A_obar)),
                       np.sort_complex(np.linalg.eigvals(dec.A_obar)), atol=1e-9)


def test_staircase_keeps_the_rank_where_the_observability_matrix_loses_it():
    # Eigenvalues 1e3 and 1e-3: CA^{n-1} swamps the observability matrix, yet (A, C) is observable.
    n = 6
    A = np.diag([1e3, 1e-3, 0.5, -0.4, 2.0, 0.9])
    C = np.ones((1, n))
    assert np.linalg.matrix_rank(_obsv(A, C, n)) < n
    dec = analysis.observability_decomposition(A, C)
    assert dec.is_observable and dec.mu_o == n


@pytest.mark.parametrize("seed", range(20))
def test_detectability_agrees_with_the_pbh_test(seed):
    rng = np.random.default_rng(200 + seed)
    n, n_o = 5, int(rng.integers(1, 5))
    A, C = _random_unobservable(rng, n, n_o, 1)
    A = A / max(1e-3, analysis.spectral_radius(A)) * rng.choice([0.6, 0.99, 1.2])
    assert analysis.is_detectable(A, C) == _pbh_detectable(A, C)


def _bounded_powers(M, K=3000):
    P, top = np.eye(M.shape[0]), 1.0
    for _ in range(K):
        P = P @ M
        top = max(top, np.abs(P).max())
    return bool(top < 50.0)


@pytest.mark.parametrize("case, expected", [
    (np.eye(2), True),
    (np.array([[1.0, 1.0], [0.0, 1.0]]), False),                              # Jordan block at 1
    (np.array([[np.cos(1), -np.sin(1)], [np.sin(1), np.cos(1)]]), True),      # rotation
    (np.diag([1.0, -1.0, 0.3]), True),
    (np.diag([1.0 + 1e-2, 0.2]), False),
    (np.array([[-1.0, 1.0], [0.0, -1.0]]), False),                            # Jordan block at −1
    (np.zeros((0, 0)), True),
])
def test_marginal_stability_means_bounded_powers(case, expected):
    assert analysis.is_marginally_stable(case) is expected
    if case.size:
        assert _bounded_powers(case) is expected


def test_marginal_stability_survives_a_similarity_transform():
    rng = np.random.default_rng(3)
    S = rng.standard_normal((4, 4)) + 2 * np.eye(4)
    J_defective = np.array([[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 0.5, 0], [0, 0, 0, -0.2]], float)
    J_simple = np.diag([1.0, 1.0, 0.5, -1.0])
    Si = np.linalg.inv(S)
    assert not analysis.is_marginally_stable(S @ J_defective @ Si)
    assert analysis.is_marginally_stable(S @ J_simple @ Si)
