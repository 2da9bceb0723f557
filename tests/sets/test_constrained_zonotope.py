"""Extended constrained zonotopes Z(G, c, A, b, h): closed-form algebra and the sparse LP fast path."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss


def random_cz(seed=0, n=3, ng=7, nc=2, h=None):
    rng = np.random.default_rng(seed)
    G, A = rng.standard_normal((n, ng)), rng.standard_normal((nc, ng))
    h = np.ones(ng) if h is None else np.asarray(h, dtype=float)
    xi0 = rng.uniform(-0.5, 0.5, ng) * np.where(np.isfinite(h), h, 1.0)
    return ss.ConstrainedZonotope(G, rng.uniform(-1, 1, n), A=A, b=A @ xi0, h=h)


def test_the_triangle_cut_from_a_square_by_a_constraint_has_the_expected_supports():
    # ξ ∈ [−1, 1]², ξ1 + ξ2 = 1: the segment from (0, 1) to (1, 0).
    Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.0])
    D = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [1.0, -1.0]])
    np.testing.assert_allclose(Z.support_many(D), [1.0, 0.0, 1.0, 1.0], atol=1e-8)
    np.testing.assert_allclose(Z.support_many(D, path="generic"), [1.0, 0.0, 1.0, 1.0], atol=1e-7)
    np.testing.assert_allclose(Z.vertices_2d()[np.argsort(Z.vertices_2d()[:, 0])],
                               [[0.0, 1.0], [1.0, 0.0]], atol=1e-7)


def test_fast_path_equals_generic_path_on_random_czs():
    for seed in range(5):
        Z = random_cz(seed)
        D = np.random.default_rng(seed).standard_normal((8, 3))
        np.testing.assert_allclose(Z.support_many(D), Z.support_many(D, path="generic"),
                                   atol=1e-6 * (1 + np.abs(Z.support_many(D)).max()))


def test_without_constraints_the_support_is_the_weighted_l1_closed_form():
    rng = np.random.default_rng(1)
    G, h = rng.standard_normal((2, 4)), np.array([0.5, 1.0, 2.0, 0.0])
    Z = ss.ConstrainedZonotope(G, [1.0, -1.0], h=h)
    D = rng.standard_normal((6, 2))
    np.testing.assert_allclose(Z.support_many(D), D @ Z.c + np.abs(D @ G) @ h, atol=1e-12)


def test_a_scalar_h_bounds_every_factor():
    Z = ss.ConstrainedZonotope(np.eye(2), [0, 0], h=0.5)
    assert Z.h.tolist() == [0.5, 0.5]
    assert Z.support([1.0, 1.0]) == 1.0


def test_sparse_and_dense_matrices_describe_the_same_set_and_stay_sparse():
    Z = random_cz(2)
    S = ss.ConstrainedZonotope(sp.csc_matrix(Z.G), Z.c, A=sp.csr_matrix(Z.A), b=Z.b, h=Z.h)
    D = np.random.default_rng(0).standard_normal((6, 3))
    np.testing.assert_allclose(S.support_many(D), Z.support_many(D), atol=1e-7)
    mapped = np.ones((2, 3)) @ S
    assert sp.issparse(mapped.G)
    both = S & ss.Box([-5, -5, -5], [5, 5, 5])
    assert sp.issparse(both.A)
    np.testing.assert_allclose(both.support_many(D), Z.support_many(D), atol=1e-6)


def test_linear_map_is_smoothing_paper_35():
    Z = random_cz(3)
    M = np.random.default_rng(1).standard_normal((2, 3))
    W = M @ Z
    assert isinstance(W, ss.ConstrainedZonotope)
    np.testing.assert_allclose(W.G, M @ Z.G)
    np.testing.assert_allclose(W.c, M @ Z.c)
    np.testing.assert_array_equal(W.A, Z.A)
    np.testing.assert_array_equal(W.b, Z.b)
    np.testing.assert_array_equal(W.h, Z.h)


def test_minkowski_sum_is_smoothing_paper_36():
    Z, W = random_cz(0), random_cz(1, ng=4, nc=1)
    S = Z + W
    assert isinstance(S, ss.ConstrainedZonotope)
    assert (S.ng, S.nc) == (Z.ng + W.ng, Z.nc + W.nc)
    np.testing.assert_allclose(S.G, np.hstack([Z.G, W.G]))
    np.testing.assert_allclose(S.A, scipy.linalg.block_diag(Z.A, W.A))
    np.testing.assert_allclose(S.c, Z.c + W.c)


def test_generalized_intersection_is_smoothing_paper_37():
    Z, Y = random_cz(0), random_cz(1, n=2, ng=4, nc=1)
    R = np.random.default_rng(2).standard_normal((2, 3))
    X = Z.intersect_preimage(R, Y)
    assert isinstance(X, ss.ConstrainedZonotope)
    np.testing.assert_allclose(X.G, np.hstack([Z.G, np.zeros((3, Y.ng))]))
    np.testing.assert_allclose(X.c, Z.c)
    np.testing.assert_allclose(X.A, np.vstack([scipy.linalg.block_diag(Z.A, Y.A),
                                               np.hstack([R @ Z.G, -Y.G])]))
    np.testing.assert_allclose(X.b, np.concatenate([Z.b, Y.b, Y.c - R @ Z.c]))
    np.testing.assert_allclose(X.h, np.concatenate([Z.h, Y.h]))


def test_cartesian_product_is_block_diagonal():
    Z, W = random_cz(0, n=2), random_cz(1, n=1, ng=3, nc=1)
    P = Z * W
    assert isinstance(P, ss.ConstrainedZonotope) and P.dim == 3
    np.testing.assert_allclose(P.G, scipy.linalg.block_diag(Z.G, W.G))
    np.testing.assert_allclose(P.A, scipy.linalg.block_diag(Z.A, W.A))


def test_projection_selects_rows_of_g_and_c():
    Z = random_cz(4)
    P = Z.project([2, 0])
    np.testing.assert_allclose(P.G, Z.G[[2, 0]])
    np.testing.assert_allclose(P.c, Z.c[[2, 0]])
    Zs = ss.ConstrainedZonotope(sp.csc_matrix(Z.G), Z.c, A=Z.A, b=Z.b)
    np.testing.assert_allclose(Zs.project([2, 0]).G.toarray(), Z.G[[2, 0]])


def test_a_zero_bound_pins_its_factor():
    Z = ss.ConstrainedZonotope(np.eye(2), [0, 0], h=[1.0, 0.0])
    assert Z.support([0.0, 1.0]) == 0.0
    assert Z.support([1.0, 1.0]) == 1.0


def test_infinite_bounds_pinned_by_constraints_give_a_bounded_set():
    # ξ1 free, ξ2 ∈ [−1, 1], ξ1 = 2ξ2: the segment x = (2t, t), |t| ≤ 1.
    Z = ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1.0, -2.0]], b=[0.0], h=[np.inf, 1.0])
    D = np.array([[1.0, 0.0], [0.0, -1.0], [1.0, 1.0]])
    for path in ("auto", "generic"):
        np.testing.assert_allclose(Z.support_many(D, path=path), [2.0, 1.0, 3.0], atol=1e-7)
    assert Z.support([1.0, 0.0], certified=True) == pytest.approx(2.0, abs=1e-7)
    assert Z.contains([1.0, 0.5]) and not Z.contains([1.0, 0.0])


def test_free_factors_not_pinned_make_every_unseen_direction_unbounded():
    # ξ1, ξ2 free with ξ1 = ξ2, ξ3 ∈ [−1, 1]: the strip {(s + ξ3, s)}.
    Z = ss.ConstrainedZonotope([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0]], [0, 0],
                               A=[[1.0, -1.0, 0.0]], b=[0.0], h=[np.inf, np.inf, 1.0])
    D = np.array([[1.0, -1.0], [-1.0, 1.0], [1.0, 0.0], [0.0, -1.0]])
    for path in ("auto", "generic"):
        values = Z.support_many(D, path=path)
        np.testing.assert_allclose(values[:2], [1.0, 1.0], atol=1e-7)
        assert values[2:].tolist() == [np.inf, np.inf]
    certified = Z.support_many(D, certified=True)
    assert certified[2:].tolist() == [np.inf, np.inf]
    assert certified[0] >= 1.0 - 1e-9


@pytest.mark.parametrize("seed", range(12))
def test_nested_preimages_of_free_boxes_are_unbounded_exactly_off_their_lineality(seed):
    # Regression: Clarabel stalled (InsufficientProgress, MaxIterations) or reported arbitrary
    # finite optima on these LPs with free factors. Oracle: h(d) = ∞ iff d is not orthogonal to
    # L = G_F null(A_F), the subspace swept by the free factors.
    rng = np.random.default_rng(seed)
    p, m, n = rng.integers(1, 4, size=3)
    lo = rng.uniform(-2, 2, p)
    hi = lo + rng.uniform(0.1, 2, p)
    j = rng.integers(p)
    lo[j], hi[j] = -np.inf, np.inf
    S = ss.Box(lo, hi).preimage(rng.standard_normal((p, m))).preimage(rng.standard_normal((m, n)))
    G = S.G.toarray() if sp.issparse(S.G) else np.asarray(S.G)
    A = S.A.toarray() if sp.issparse(S.A) else np.asarray(S.A)
    free = ~np.isfinite(S.h)
    bounds = [(None, None) if f else (-hj, hj) for f, hj in zip(free, S.h)]
    feasible = linprog(np.zeros(S.ng), A_eq=A, b_eq=S.b, bounds=bounds).status == 0
    if not feasible:  # the range of the maps can miss the box
        assert S.is_empty() and S.is_empty(path="generic")
        assert np.isneginf(S.support_many(np.eye(n))).all()
        return
    L = G[:, free] @ scipy.linalg.null_space(A[:, free])
    D = rng.standard_normal((5, n))
    if L.size:
        Q = scipy.linalg.orth(L)
        D = np.vstack([D, D[:2] - (D[:2] @ Q) @ Q.T])  # two directions orthogonal to L
        unbounded = np.linalg.norm(D @ Q, axis=1) > 1e-9
    else:
        unbounded = np.zeros(len(D), dtype=bool)
    auto, generic = S.support_many(D), S.support_many(D, path="generic")
    assert np.isposinf(auto[unbounded]).all() and np.isposinf(generic[unbounded]).all()
    assert np.isfinite(auto[~unbounded]).all()
    np.testing.assert_allclose(auto[~unbounded], generic[~unbounded],
                               atol=1e-6 * (1 + np.abs(auto[~unbounded]).max(initial=0)))


def test_certified_support_is_at_least_the_solver_value():
    Z = random_cz(5)
    D = np.random.default_rng(5).standard_normal((10, 3))
    certified, solved = Z.support_many(D, certified=True), Z.support_many(D)
    assert np.all(certified >= solved - 1e-9 * (1 + np.abs(solved).max()))
    assert np.all(certified <= solved + 1e-6 * (1 + np.abs(solved).max()))


def test_interval_hull_of_a_cz_is_one_query_of_2n_directions():
    Z = random_cz(6)
    hull = Z.interval_hull()
    np.testing.assert_allclose(hull.hi, Z.support_many(np.eye(3)), atol=1e-9)
    np.testing.assert_allclose(hull.lo, -Z.support_many(-np.eye(3)), atol=1e-9)
    certified = Z.interval_hull(certified=True)
    assert np.all(certified.hi >= hull.hi - 1e-9) and np.all(certified.lo <= hull.lo + 1e-9)


def test_reals_is_the_cz_with_every_factor_free():
    R = ss.Reals(3)
    assert isinstance(R, ss.ConstrainedZonotope)
    assert R.h.tolist() == [np.inf] * 3 and R.nc == 0
    assert repr(R) == "Reals(3)"


def test_repr_and_sizes():
    Z = random_cz(0, ng=7, nc=2)
    assert (Z.ng, Z.nc) == (7, 2)
    assert repr(Z) == "ConstrainedZonotope(dim=3, ng=7, nc=2)"
