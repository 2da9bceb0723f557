"""The exact optimal filter under a joint range (rethinking Theorem 1), checked three independent ways.

* against the paper's state augmentation (33)–(35) (the classical filter of the augmented system);
* against a brute-force polytope oracle: the consistent noise vectors ξ as an explicit polytope, its
  vertices enumerated by solving every square subsystem of active constraints, mapped to x_k by the dense
  trajectory map and hulled with SciPy (no CZ, no LP solver);
* Theorem 2 / Theorem 3: equal to the classical filter under unrelated noises, inside it otherwise, on
  random related-noise systems.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import setsmooth as ss
from setsmooth.papers.rethinking_examples import (rethinking_example_30, rethinking_example_30_joint_range,
                                                  rethinking_example_30_x0)

DIRECTIONS = np.array([[np.cos(t), np.sin(t)] for t in np.linspace(0, 2 * np.pi, 24, endpoint=False)])


def simulate_identical(system, X0, T, rng):
    """One run of (30)–(31): x_0 and the one noise w uniform, v_k uniform."""
    x = X0.sample(rng, 1)[0]
    w = system.W.sample(rng, 1)[0]
    xs = [x]
    for k in range(T):
        xs.append(system.step(k, xs[-1], w))
    xs = np.array(xs)
    ys = np.array([system.measure(k, xs[k], system.V.sample(rng, 1)[0]) for k in range(T + 1)])
    return xs, ys, np.concatenate([xs[0], np.tile(w, T), (ys - xs @ system.C_at(0).T).reshape(-1)])


def supports(sets, directions=DIRECTIONS):
    return np.array([S.support_many(directions) for S in sets])


# -- brute-force polytope oracle ----------------------------------------------------------------------

def trajectory_maps(system, joint, k):
    """Dense Φ_l, ψ_l with x_l = Φ_l ξ (no input) and y_l − ψ_l ξ = 0 for l ≤ k."""
    n, dim = system.n, joint.dim
    Phi = np.zeros((n, dim))
    Phi[:, list(joint.x0_dims())] = np.eye(n)
    maps, meas = [Phi.copy()], []
    for l in range(k + 1):
        M = system.C_at(l) @ Phi
        M[:, list(joint.v_dims(l))] += system.F_at(l)
        meas.append(M)
        if l < k:
            Phi = system.A_at(l) @ Phi
            Phi[:, list(joint.w_dims(l))] += system.E_at(l)
            maps.append(Phi.copy())
    return maps, meas


def oracle_polygon(system, joint, lo, hi, E, e, H, h, ys, k):
    """Vertices of ⟦x_k | y_{0:k}⟧ by vertex enumeration of {ξ ∈ [lo, hi] : Eξ = e, Hξ ≤ h, data}.

    Only the coordinates of ξ that x_0..x_k and y_0..y_k involve (x_0, w_{0:k−1}, v_{0:k}) are kept; the
    relation rows must not involve the others. Every choice of d − r inequality rows active is solved
    with the r equalities (one batched solve of the nonsingular square systems), the feasible solutions
    are the vertices, and their images x_k are hulled.
    """
    maps, meas = trajectory_maps(system, joint, k)
    cols = list(joint.x0_dims()) + [i for l in range(k) for i in joint.w_dims(l)] + \
        [i for l in range(k + 1) for i in joint.v_dims(l)]
    others = np.setdiff1d(np.arange(joint.dim), cols)
    E = E[~np.any(E[:, others] != 0, axis=1)] if E.size else E
    e = e[:E.shape[0]]
    Aeq = np.vstack([E[:, cols]] + [M[:, cols] for M in meas])
    beq = np.concatenate([e] + [ys[l] for l in range(k + 1)])
    dim = len(cols)
    Ain = np.vstack([np.eye(dim), -np.eye(dim), H[:, cols]])
    bin_ = np.concatenate([hi[cols], -lo[cols], h])
    r = Aeq.shape[0]
    combos = np.array(list(itertools.combinations(range(Ain.shape[0]), dim - r)))
    M = np.concatenate([np.broadcast_to(Aeq, (len(combos), r, dim)), Ain[combos]], axis=1)
    rhs = np.concatenate([np.broadcast_to(beq, (len(combos), r)), bin_[combos]], axis=1)
    regular = np.abs(np.linalg.det(M)) > 1e-9
    xi = np.linalg.solve(M[regular], rhs[regular][..., None])[..., 0]
    feasible = np.all(xi @ Ain.T <= bin_ + 1e-9, axis=1)
    points = xi[feasible] @ maps[k][:, cols].T
    return points[ConvexHull(points).vertices]


def oracle_support(vertices, directions=DIRECTIONS):
    return (vertices @ directions.T).max(axis=0)


def identical_noise_data(T):
    """Box bounds and the identical-noise equalities of (30)–(31) in ξ-coordinates."""
    joint = rethinking_example_30_joint_range(T)
    lo = np.concatenate([[-10, -10], -np.ones(T), -np.ones(T + 1)])
    hi = -lo
    E = np.zeros((T - 1, joint.dim))
    for l in range(T - 1):
        E[l, joint.w_dims(l)[0]], E[l, joint.w_dims(l + 1)[0]] = 1, -1
    return joint, lo, hi, E, np.zeros(T - 1)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_optimal_filter_equals_augmentation_and_polytope_oracle(seed):
    T = 3
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    xs, ys, _ = simulate_identical(system, X0, T, np.random.default_rng(seed))
    joint, lo, hi, E, e = identical_noise_data(T)
    optimal = ss.optimal_filter(system, joint, ys)
    augmented, prior = ss.augment_identical_process_noise(system, X0)
    via_augmentation = [P.project([0, 1]) for P in ss.classical_filter(augmented, prior, ys)]
    for k in range(T + 1):
        vertices = oracle_polygon(system, joint, lo, hi, E, e, np.zeros((0, joint.dim)), np.zeros(0), ys, k)
        expected = oracle_support(vertices)
        assert optimal[k].support_many(DIRECTIONS) == pytest.approx(expected, abs=1e-6)
        assert via_augmentation[k].support_many(DIRECTIONS) == pytest.approx(expected, abs=1e-6)
        assert optimal[k].area() == pytest.approx(ConvexHull(vertices).volume, rel=1e-6)
        assert optimal[k].contains(xs[k])


def test_optimal_filter_equals_augmentation_over_twenty_steps():
    T = 20
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    xs, ys, _ = simulate_identical(system, X0, T, np.random.default_rng(7))
    optimal = ss.optimal_filter(system, rethinking_example_30_joint_range(T), ys)
    augmented, prior = ss.augment_identical_process_noise(system, X0)
    via_augmentation = [P.project([0, 1]) for P in ss.classical_filter(augmented, prior, ys)]
    scale = supports(via_augmentation).max()
    assert supports(optimal) == pytest.approx(supports(via_augmentation), abs=1e-7 * scale)
    assert all(P.contains(x) for P, x in zip(optimal, xs))


def test_identical_noise_range_is_the_box_cut_by_a_subspace():
    T = 4
    joint = rethinking_example_30_joint_range(T)
    # The same set written with one shared generator for w (no constraint rows).
    G = np.zeros((joint.dim, 2 + 1 + T + 1))
    G[[0, 1], [0, 1]] = 10
    G[2:2 + T, 2] = 1
    G[2 + T:, 3:] = np.eye(T + 1)
    shared = ss.ConstrainedZonotope(G, np.zeros(joint.dim))
    rng = np.random.default_rng(3)
    D = rng.standard_normal((40, joint.dim))
    assert joint.set.support_many(D) == pytest.approx(shared.support_many(D), abs=1e-7)
    assert joint.marginal(joint.w_dims(3)).interval_hull().hi == pytest.approx([1.0])


def test_optimal_filter_under_unrelated_noises_is_the_classical_filter():
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    T = 6
    xs, ys, _ = simulate_identical(system, X0, T, np.random.default_rng(11))
    optimal = ss.optimal_filter(system, ss.JointRange.unrelated(X0, system.W, system.V, T), ys)
    classical = ss.classical_filter(system, X0, ys)
    assert supports(optimal) == pytest.approx(supports(classical), abs=1e-6)


def test_smoothed_ranges_are_inside_posteriors_and_equal_at_the_end():
    T = 8
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    xs, ys, _ = simulate_identical(system, X0, T, np.random.default_rng(5))
    joint = rethinking_example_30_joint_range(T)
    posteriors = ss.optimal_filter(system, joint, ys)
    smoothed = ss.optimal_joint_smoother(system, joint, ys)
    s, p = supports(smoothed), supports(posteriors)
    assert np.all(s <= p + 1e-6)
    assert s[-1] == pytest.approx(p[-1], abs=1e-6)
    assert np.any(s[:-1] < p[:-1] - 1e-3)     # the later data do tell something about earlier states
    assert all(S.contains(x) for S, x in zip(smoothed, xs))


def test_lazy_joint_range_gives_the_same_sets_as_the_constrained_zonotope():
    T = 2
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    xs, ys, _ = simulate_identical(system, X0, T, np.random.default_rng(2))
    joint = rethinking_example_30_joint_range(T)
    box = ss.Box(*identical_noise_data(T)[1:3])
    as_polytope = ss.HPolytope(np.vstack([np.eye(joint.dim), -np.eye(joint.dim)]),
                               np.concatenate([box.hi, -box.lo]))
    lazy = ss.JointRange(as_polytope, 2, 1, 1, T).restrict(identical_noise_data(T)[3], np.zeros(T - 1))
    assert lazy.set._flat_cz is None
    for k in range(T + 1):
        exact = ss.joint_trajectory_set(system, joint, ys, k)
        generic = ss.joint_trajectory_set(system, lazy, ys, k)
        D = np.random.default_rng(k).standard_normal((6, exact.dim))
        assert generic.support_many(D) == pytest.approx(exact.support_many(D), abs=1e-5)


def test_halfspace_relation_is_exact_as_a_constrained_zonotope():
    rng = np.random.default_rng(4)
    X0, W, V = ss.Box([-1, -2], [1, 2]), ss.Box([-1], [1]), ss.Box([-0.5], [0.5])
    joint = ss.JointRange.unrelated(X0, W, V, 2)
    H, h = rng.standard_normal((3, joint.dim)), rng.uniform(0.2, 1.0, 3)
    cz = joint.restrict_halfspaces(H, h).set
    lazy = joint.set & ss.HPolytope(H, h)
    assert isinstance(cz, ss.ConstrainedZonotope)
    D = rng.standard_normal((20, joint.dim))
    assert cz.support_many(D) == pytest.approx(lazy.support_many(D), abs=1e-6)


# -- Theorem 3 on random related-noise systems ------------------------------------------------------

def random_related_system(rng):
    """A random 2-state system, its marginal boxes, a random relation and a true ξ satisfying it."""
    n, T = 2, 5
    A = rng.standard_normal((n, n))
    A /= max(1.0, np.abs(np.linalg.eigvals(A)).max()) * rng.uniform(0.9, 1.1)
    system = ss.LinearSystem(A, None, rng.standard_normal((1, n)), E=rng.standard_normal((n, 1)),
                             W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    X0 = ss.Box([-3.0, -3.0], [3.0, 3.0])
    joint = ss.JointRange.unrelated(X0, system.W, system.V, T)
    lo = np.concatenate([X0.lo, -np.ones(T), -np.ones(T + 1)])
    xi = rng.uniform(lo, -lo)
    kind = rng.integers(3)
    if kind == 0:      # identical process noise
        xi[2:2 + T] = xi[2]
        joint = ss.JointRange.identical_process_noise(X0, system.W, system.V, T)
    elif kind == 1:    # v_k = α w_{k−1}: the measurement noise follows the previous process noise
        alpha = rng.uniform(-1, 1)
        E = np.zeros((T, joint.dim))
        for k in range(1, T + 1):
            E[k - 1, joint.v_dims(k)[0]], E[k - 1, joint.w_dims(k - 1)[0]] = 1, -alpha
            xi[joint.v_dims(k)[0]] = alpha * xi[joint.w_dims(k - 1)[0]]
        joint = joint.restrict(E, np.zeros(T))
    else:              # random half-spaces through a margin around the true ξ
        H = rng.standard_normal((4, joint.dim))
        joint = joint.restrict_halfspaces(H, H @ xi + rng.uniform(0.1, 1.0, 4))
    xs = [xi[:2]]
    for k in range(T):
        xs.append(system.step(k, xs[-1], xi[joint.w_dims(k)]))
    xs = np.array(xs)
    ys = np.array([system.measure(k, xs[k], xi[joint.v_dims(k)]) for k in range(T + 1)])
    return system, X0, joint, xs, ys


@pytest.mark.parametrize("seed", range(6))
def test_theorem3_classical_posterior_contains_the_optimal_one(seed):
    system, X0, joint, xs, ys = random_related_system(np.random.default_rng(100 + seed))
    optimal = ss.optimal_filter(system, joint, ys)
    classical = ss.classical_filter(system, X0, ys)
    o, c = supports(optimal), supports(classical)
    assert np.all(o <= c + 1e-6 * (1 + np.abs(c)))
    assert all(P.contains(x) for P, x in zip(optimal, xs))
    assert optimal[-1].area() <= classical[-1].area() * (1 + 1e-6)


def test_data_contradicting_the_joint_range_give_empty_posteriors():
    T = 3
    system = rethinking_example_30()
    ys = np.array([[0.0], [0.0], [0.0], [40.0]])    # y_0..y_2 near 0 pin the velocity: 40 is out of reach
    posteriors = ss.optimal_filter(system, rethinking_example_30_joint_range(T), ys)
    assert [isinstance(P, ss.EmptySet) for P in posteriors] == [False, False, False, True]


def test_joint_range_errors_name_the_argument():
    system = rethinking_example_30()
    with pytest.raises(ValueError, match="set must be a ConvexSet of dimension"):
        ss.JointRange(ss.Box([0.0], [1.0]), 2, 1, 1, 3)
    with pytest.raises(ValueError, match="covers only"):
        ss.optimal_filter(system, rethinking_example_30_joint_range(2), np.zeros((4, 1)))
    with pytest.raises(ValueError, match=r"\(n, p, q\)"):
        ss.optimal_filter(system, ss.JointRange.unrelated(ss.Box([0.0], [1.0]), system.W, system.V, 2),
                          np.zeros((3, 1)))
    with pytest.raises(IndexError, match="w_k exists"):
        rethinking_example_30_joint_range(2).w_dims(2)


@pytest.mark.parametrize("seed", [0, 1])
def test_optimal_posterior_under_random_halfspace_relations_matches_the_polytope_oracle(seed):
    """A relation among all of ξ: the oracle is exact at k = T, where no coordinate is left out."""
    rng = np.random.default_rng(200 + seed)
    T = 3
    system = ss.LinearSystem([[1.0, 0.3], [-0.2, 0.9]], None, [[1.0, 0.5]], E=rng.standard_normal((2, 1)),
                             W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    X0 = ss.Box([-3.0, -3.0], [3.0, 3.0])
    joint = ss.JointRange.unrelated(X0, system.W, system.V, T)
    lo = np.concatenate([X0.lo, -np.ones(T), -np.ones(T + 1)])
    xi = rng.uniform(lo, -lo)
    H = rng.standard_normal((3, joint.dim))
    h = H @ xi + rng.uniform(0.1, 0.5, 3)
    related = joint.restrict_halfspaces(H, h)
    xs = [xi[:2]]
    for k in range(T):
        xs.append(system.step(k, xs[-1], xi[joint.w_dims(k)]))
    ys = np.array([system.measure(k, xs[k], xi[joint.v_dims(k)]) for k in range(T + 1)])
    vertices = oracle_polygon(system, joint, lo, -lo, np.zeros((0, joint.dim)), np.zeros(0), H, h, ys, T)
    optimal = ss.optimal_filter(system, related, ys)[T]
    assert optimal.support_many(DIRECTIONS) == pytest.approx(oracle_support(vertices), abs=1e-6)
    assert optimal.contains(xs[T])


def test_the_trajectory_rows_are_scipy_s_sparse_products_bit_for_bit():
    # _assemble forms B·G_J and D·G_J densely; the rows must be the sparse product's, term order included.
    import scipy.sparse as sp

    from setsmooth.filters.optimal import _sparse_product

    rng = np.random.default_rng(5)
    for _ in range(200):
        k = int(rng.integers(1, 7))
        M, X = rng.normal(size=(3, k)) * 10.0 ** rng.integers(-3, 4), rng.normal(size=(k, 9))
        for A in (M, X):
            A[rng.random(A.shape) < 0.4] = 0.0
        if rng.random() < 0.2:
            X[0, 0] = np.inf  # 0·∞ must not appear where the sparse product has no term
        sparse = (sp.csr_matrix(M) @ sp.csr_matrix(X)).toarray()
        dense = _sparse_product(M, X)
        assert np.array_equal(dense, sparse, equal_nan=True)


def _same_arrays(a, b) -> bool:
    """Bit for bit, -0.0 included; sparse matrices by their CSC arrays; None (no slack) only as None."""
    import scipy.sparse as sp

    if a is None or b is None:
        return a is b
    if sp.issparse(a) or sp.issparse(b):
        a, b = sp.csc_matrix(a), sp.csc_matrix(b)
        return a.shape == b.shape and all(np.array_equal(x, y) and x.dtype == y.dtype for x, y in
                                          ((a.indptr, b.indptr), (a.indices, b.indices), (a.data, b.data)))
    return np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b))


@pytest.mark.parametrize("seed", range(6))
def test_trajectory_sets_of_many_stops_are_those_assembled_for_each_stop_bit_for_bit(seed):
    # joint_trajectory_sets computes the rows of times 0..T once and gives stop k the prefix of them,
    # and JointTrajectoryRows keeps the rows that do not depend on the data for several data sets;
    # assembled for stop k alone, the trajectory CZ must be the same, rounding slack included. A
    # time-varying system with an input and related noises (random_related_system's relations:
    # identical, v_k = α w_{k−1}, half-spaces) so that every block differs from the next.
    from setsmooth.filters.optimal import JointTrajectoryRows, joint_trajectory_sets

    rng = np.random.default_rng(300 + seed)
    base, _, joint, _, ys = random_related_system(rng)
    T = ys.shape[0] - 1
    As = [base.A_at(0) * rng.uniform(0.9, 1.1, (2, 2)) for _ in range(T)]
    Cs = [base.C_at(0) * rng.uniform(0.5, 2.0) for _ in range(T + 1)]
    system = ss.LinearSystem(As, np.eye(2), Cs, E=base.E_at(0), W=base.W, V=base.V,
                             u=rng.standard_normal((T + 1, 2)))
    ys = ys + rng.standard_normal(ys.shape)
    stops = [T, 0, 2, T - 1]
    rows = JointTrajectoryRows(system, joint)      # prepared once, completed by two data sets below
    for data in (ys, ys + rng.standard_normal(ys.shape)):
        for some, many in ((stops, joint_trajectory_sets(system, joint, data, stops)),
                           (stops, rows.sets(data, stops)), ([0, 2], rows.sets(data[:T], [0, 2]))):
            for k, Z in zip(some, many):
                alone = ss.joint_trajectory_set(system, joint, data, k)
                assert Z.dim == alone.dim == 2 * (k + 1)
                for name in ("G", "c", "A", "b", "h"):
                    assert _same_arrays(getattr(Z, name), getattr(alone, name)), (k, name)
                for name in ("slack", "slack_free"):
                    assert _same_arrays(getattr(Z.factors, name), getattr(alone.factors, name)), (k, name)
    with pytest.raises(ValueError, match="prepared up to k = 2"):
        JointTrajectoryRows(system, joint, 2).sets(ys, [3])
    # and the filter's posteriors are the projections of those sets
    posteriors = ss.optimal_filter(system, joint, ys, detect_empty=False)
    for k in range(T + 1):
        alone = ss.joint_trajectory_set(system, joint, ys, k).project([2 * k, 2 * k + 1])
        assert _same_arrays(posteriors[k].G, alone.G) and _same_arrays(posteriors[k].A, alone.A)
        assert _same_arrays(posteriors[k].b, alone.b) and _same_arrays(posteriors[k].c, alone.c)
