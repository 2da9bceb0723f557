"""The set algebra's rounding charges (`setsmooth.sets.rounding`), checked in exact rational arithmetic."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.sets import rounding

F = np.vectorize(Fraction, otypes=[object])


def exact_matmul(M: np.ndarray, X: np.ndarray) -> np.ndarray:
    return F(np.asarray(M)) @ F(np.asarray(X))


def test_two_sum_is_error_free():
    rng = np.random.default_rng(0)
    a = rng.normal(size=200) * 10.0 ** rng.integers(-8, 9, 200)
    b = rng.normal(size=200) * 10.0 ** rng.integers(-8, 9, 200)
    s, e = rounding.two_sum(a, b)
    assert all(Fraction(x) + Fraction(y) == Fraction(p) + Fraction(q) for x, y, p, q in zip(a, b, s, e))
    lo, hi = rounding.sum_down(a, b), rounding.sum_up(a, b)
    assert all(Fraction(p) <= Fraction(x) + Fraction(y) <= Fraction(q)
               for x, y, p, q in zip(a, b, lo, hi))
    assert (lo <= s).all() and (s <= hi).all() and (lo < hi).any()


@pytest.mark.parametrize("sparse", [False, True])
def test_product_error_bounds_the_rounding_of_every_entry(sparse):
    rng = np.random.default_rng(1)
    for _ in range(20):
        M = rng.normal(size=(4, 5)) * 10.0 ** rng.integers(-3, 7)
        X = rng.normal(size=(5, 6))
        X[rng.random(X.shape) < 0.4] = 0.0
        Ms, Xs = (sp.csr_matrix(M), sp.csc_matrix(X)) if sparse else (M, X)
        computed = np.asarray((Ms @ Xs).todense() if sparse else M @ X)
        E = rounding.product_error(Ms, Xs)
        E = np.asarray(E.todense()) if sp.issparse(E) else E
        err = np.abs(F(computed) - exact_matmul(M, X))
        assert (err <= F(E)).all()


def test_products_that_are_exact_are_charged_nothing():
    rng = np.random.default_rng(2)
    M = rng.normal(size=(3, 3))
    selection = np.eye(3)[[2, 0]]
    assert not np.any(rounding.product_error(M, np.eye(3)))           # M·I
    assert not np.any(rounding.product_error(-np.eye(3), M))          # a negation
    assert not np.any(rounding.product_error(selection, M))           # a selection
    assert not np.any(rounding.product_error(0.5 * np.eye(3), M))     # a power of two
    assert np.any(rounding.product_error(M, M))


def test_a_small_sparse_product_is_charged_bit_for_bit_as_by_the_sparse_path(monkeypatch):
    rng = np.random.default_rng(4)

    def draw(shape):
        scale = rng.choice([10.0 ** rng.integers(-5, 6), 1e-160, 0.25])  # 1e-160: products underflow
        A = rng.integers(-8, 9, size=shape) * scale if scale == 0.25 else rng.normal(size=shape) * scale
        A[rng.random(shape) < rng.random()] = 0.0
        return A

    cases = []
    for _ in range(400):
        m, k, n = rng.integers(1, 6, size=3)
        M, X = draw((m, k)), draw((k, rng.integers(1, 40)))
        M = M if rng.random() < 0.5 else sp.csr_matrix(M) if rng.random() < 0.5 else sp.csc_matrix(M)
        X = sp.csr_matrix(X) if rng.random() < 0.5 else sp.csc_matrix(X)
        cases.append((M, X, rounding.product_error(M, X)))
    taken = sum(rounding._small_sparse_product_error(M, X) is not None for M, X, _ in cases)
    assert 0.2 * len(cases) < taken < len(cases)  # rows with three charged entries go the sparse way
    monkeypatch.setattr(rounding, "_SMALL_SPARSE_PRODUCT_TERMS", 0)  # every product the sparse way
    for M, X, E in cases:
        reference = rounding.product_error(M, X)
        assert isinstance(E, sp.csr_matrix)
        assert np.array_equal(E.toarray(), reference.toarray())
        v = rng.random(X.shape[1])
        assert np.array_equal(E @ v, reference @ v)  # the order of a row's entries does not matter


def test_a_box_as_centre_and_radius_keeps_every_point():
    rng = np.random.default_rng(3)
    lo = rng.normal(size=300) * 1e6 + rng.normal(size=300)
    hi = lo + rng.uniform(0.0, 3.0, 300)
    c, r, pad = rounding.box_center_radius(lo, hi)
    pad = np.zeros_like(lo) if pad is None else pad
    for l, h, cc, rr, p in zip(lo, hi, c, r, pad):
        assert Fraction(cc) - Fraction(rr) - Fraction(p) <= Fraction(l)
        assert Fraction(h) <= Fraction(cc) + Fraction(rr) + Fraction(p)
    assert np.count_nonzero(pad) > 0  # 1e6-sized midpoints do round
    assert rounding.box_center_radius(np.array([-1.0, 0.0]), np.array([1.0, 3.0]))[2] is None


def test_box_sums_and_translations_round_outward():
    a, b = ss.Box([0.1, -1e6 - 0.3], [0.3, -1e6 + 0.7]), ss.Box([0.2, 1e-9], [0.7, 3e-9])
    v = np.array([0.2, 1e-9])
    for S, other_lo, other_hi in ((a + b, b.lo, b.hi), (a + v, v, v)):
        assert isinstance(S, ss.Box)
        assert all(Fraction(lo) <= Fraction(x) + Fraction(y) for lo, x, y in zip(S.lo, a.lo, other_lo))
        assert all(Fraction(hi) >= Fraction(x) + Fraction(y) for hi, x, y in zip(S.hi, a.hi, other_hi))


def _exact_zonotope_support(G, c, d) -> Fraction:
    g = F(np.asarray(d)) @ G
    return sum(F(np.asarray(d)) * c) + sum(abs(x) for x in g)


def test_certified_supports_bound_the_exact_result_of_a_chain_of_maps_and_sums():
    """A zonotope 1e6 from the origin through maps, sums and translations, followed in rationals:
    the stored set's own support falls below the exact result's in some direction (so the test can
    fail), the certified one never does, for Zonotopes and their CZ forms alike."""
    rng = np.random.default_rng(4)
    below = 0
    for trial in range(12):
        n = 3
        G0, c0 = rng.normal(size=(n, 4)), rng.normal(size=n) * 1e6
        Z = ss.Zonotope(G0, c0)
        G, c = F(G0), F(c0)
        for step in range(6):
            M = rng.normal(size=(n, n))
            v = rng.normal(size=n) * 1e5
            W0 = rng.normal(size=(n, 2)) * 1e-3
            Z = M @ Z + ss.Zonotope(W0, np.full(n, 0.1)) + v
            G = np.hstack([F(M) @ G, F(W0)])
            c = F(M) @ c + F(np.full(n, 0.1)) + F(v)
        assert isinstance(Z, ss.Zonotope) and Z.pad is not None
        cz = Z.to_constrained_zonotope()
        for d in rng.normal(size=(20, n)):
            exact = _exact_zonotope_support(G, c, d)
            stored = _exact_zonotope_support(F(Z.G), F(Z.c), d)
            below += stored < exact
            assert Fraction(Z.support(d, certified=True)) >= exact
            assert Fraction(cz.support(d, certified=True)) >= exact
        hull = Z.interval_hull(certified=True)
        for i in range(n):
            e = np.eye(n)[i]
            assert Fraction(hull.hi[i]) >= _exact_zonotope_support(G, c, e)
            assert Fraction(hull.lo[i]) <= -_exact_zonotope_support(G, c, -e)
    assert below > 0


def test_generalized_intersection_rows_are_within_their_slack():
    """The new rows R G_z ξ − G_y η = c_y − R c_z as stored differ from the exact ones by at most the
    slack for every ξ, η in the unit box (checked at the vertices that maximize the difference)."""
    rng = np.random.default_rng(5)
    for _ in range(10):
        Z = ss.ConstrainedZonotope(rng.normal(size=(3, 4)), rng.normal(size=3) * 1e6,
                                   A=rng.normal(size=(1, 4)), b=[0.1])
        Y = ss.ConstrainedZonotope(rng.normal(size=(2, 3)), rng.normal(size=2) * 1e6)
        R = rng.normal(size=(2, 3))
        X = Z._generalized_intersection(R, Y)
        rows = slice(Z.nc + Y.nc, X.nc)
        stored_A, stored_b = F(np.asarray(X.A)[rows]), F(X.b[rows])
        exact_A = np.hstack([exact_matmul(R, Z.G), -F(np.asarray(Y.G))])
        exact_b = F(Y.c) - exact_matmul(R, Z.c[:, None]).ravel()
        # max over the unit box of |(stored − exact) ξ − (b_stored − b_exact)|, per row
        diff = stored_A - exact_A
        worst = [sum(abs(x) for x in diff[i]) + abs(stored_b[i] - exact_b[i]) for i in range(2)]
        slack = X.slack[rows]
        assert all(Fraction(s) >= w for s, w in zip(slack, worst))
        assert np.all(slack > 0)


def test_intersection_of_exact_data_is_charged_nothing():
    Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2))
    Y = ss.ConstrainedZonotope([[1.0]], [0.5])
    X = Z._generalized_intersection(np.array([[1.0, 0.0]]), Y)
    assert X.slack is None and X.pad is None


def test_materialized_sets_contain_what_the_charges_cover():
    rng = np.random.default_rng(6)
    Z = ss.ConstrainedZonotope(rng.normal(size=(2, 3)), rng.normal(size=2) * 1e6,
                               A=rng.normal(size=(1, 3)), b=[0.2])
    Y = ss.ConstrainedZonotope(rng.normal(size=(1, 2)), rng.normal(size=1) * 1e6)
    X = (rng.normal(size=(2, 2)) @ Z)._generalized_intersection(rng.normal(size=(1, 2)), Y)
    assert X.pad is not None and X.slack is not None
    M = X.materialized()
    assert M.pad is None and M.slack is None
    assert M.ng == X.ng + np.count_nonzero(X.pad) + np.count_nonzero(X.slack)
    for d in rng.normal(size=(8, 2)):
        # the charged bound of X is for a set inside M's: never above M's plain support by more
        # than the solver's accuracy, and M contains X
        assert M.support(d) >= X.support(d) - 1e-6 * (1 + abs(X.support(d)))


def test_rounded_free_columns_are_charged_per_unit_of_the_free_factors():
    """The observation information set of x_{k+1} = 0.7 x_k + w, y = x + v keeps x as a free factor
    whose column is multiplied by 0.7 at every step (rounded): the charge is carried per unit of
    ‖ξ_F‖∞ and the certified hull, finite, encloses the closed-form interval (rationals)."""
    a = 0.7
    unit = ss.Box([-1.0], [1.0])
    system = ss.LinearSystem([[a]], None, [[1.0]], W=unit, V=unit)
    ys = np.array([[0.3], [0.7], [-0.2], [0.1]])
    for i, k in [(0, 3), (1, 5), (0, 6)]:
        S = ss.observation_information_set(system, ys, k, i)
        assert S.pad_free is not None
        hull = S.interval_hull(certified=True)
        A = Fraction(a)
        spread = sum(A ** (k - 1 - r) for r in range(i, k))
        lo = A ** (k - i) * (Fraction(ys[i, 0]) - 1) - spread
        hi = A ** (k - i) * (Fraction(ys[i, 0]) + 1) + spread
        assert Fraction(hull.lo[0]) <= lo and Fraction(hull.hi[0]) >= hi
        assert float(hi - Fraction(hull.hi[0])) > -1e-12 and float(Fraction(hull.lo[0]) - lo) > -1e-12


# -- regressions from an adversarial review of the charges (each failed before its fix) -----------

ETA = 2.0 ** -1074


def test_closed_forms_of_boxes_and_point_sets_round_their_certified_sums_up():
    exact = Fraction(1) + Fraction(2) ** -60
    assert Fraction(ss.Box([0.0, 0.0], [1.0, 2.0 ** -60]).support([1.0, 1.0], certified=True)) >= exact
    assert Fraction(ss.VPolytope([[1.0, 2.0 ** -60]]).support([1.0, 1.0], certified=True)) >= exact
    # a lazy Minkowski sum (one operand without a CZ form) adds its operands' values rounded up
    W = ss.Box([0.0, -np.inf], [1.0, 0.0]) + ss.Zonotope([[2.0 ** -60], [0.0]], [0.0, 0.0])
    assert Fraction(W.support([1.0, 0.0], certified=True)) >= exact


def test_products_that_underflow_are_charged():
    # direction products below the smallest subnormal, times a large factor bound
    exact = Fraction(1e-200) * Fraction(1e-200) * Fraction(1e300)
    free = ss.ConstrainedZonotope([[1e-200]], [0.0], h=[1e300])
    constrained = ss.ConstrainedZonotope([[1e-200, 0.0]], [0.0], A=[[0.0, 1.0]], b=[0.0],
                                         h=[1e300, 1.0])
    for Z in (free, constrained):
        assert Fraction(Z.support([1e-200], certified=True)) >= exact
    many = ss.Zonotope(np.full((1, 1000), 2.0 ** -538), [0.0])
    assert Fraction(many.support([2.0 ** -538], certified=True)) >= 1000 * Fraction(2) ** -1076
    # a single product that underflows is not exact (Dekker's TwoProduct needs no underflow)
    Y = np.array([[2.0 ** 1000]]) @ (np.array([[2.0 ** -600]]) @ ss.Zonotope([[2.0 ** -500]], [0.0]))
    assert Fraction(Y.support([1.0], certified=True)) >= Fraction(2) ** -100
    # halving a subnormal box width rounds
    B = np.array([[2.0 ** 1000]]) @ ss.Box([0.0], [ETA])
    assert Fraction(B.support([1.0], certified=True)) >= Fraction(2) ** 1000 * Fraction(ETA)


def test_a_free_factor_that_the_rounded_direction_misses_is_not_certified_bounded():
    # computed Gᵀd = 0 but exactly −2⁻⁵⁴: the exact support along the free factor is +∞
    Z = ss.ConstrainedZonotope([[3.0], [1.0]], [0.0, 0.0], h=[np.inf])
    assert Z.support([1 / 3, -1.0], certified=True) == np.inf
    assert 0.0 <= Z.support([1.0, -3.0], certified=True) < 1e-300  # exactly cancelled: bounded
    # a rounded free column (pad_free) seen by the direction
    W = np.array([[1.0, 2.0 ** -60], [1.0, 0.0]]) @ ss.ConstrainedZonotope([[1.0], [1.0]], [0.0, 0.0],
                                                                           h=[np.inf])
    assert W.support([1.0, -1.0], certified=True) == np.inf


def test_a_set_stored_empty_within_its_slack_is_not_certified_empty():
    """1e12 + 0.3 rounds; a point y one ulp off the stored interval but inside the exact one: the
    stored intersection is empty, the exact one is {y}."""
    v, a = 1e12, 0.3
    exact_c = Fraction(a) + Fraction(v)
    stored_c = a + v
    y = stored_c - np.spacing(stored_c) if Fraction(stored_c) > exact_c else stored_c + np.spacing(stored_c)
    g = float(abs(Fraction(y) - exact_c))
    g = g if Fraction(g) >= abs(Fraction(y) - exact_c) else float(np.nextafter(g, np.inf))
    W = (ss.ConstrainedZonotope([[g]], [a]) + v) & ss.Box([y], [y])
    assert not W.is_empty()
    hull = W.interval_hull(certified=True)
    assert Fraction(hull.lo[0]) <= Fraction(y) <= Fraction(hull.hi[0])
    assert isinstance(W.interval_hull(), ss.Box)


def _padded_joint_range():
    s = 1e-12
    a, b = 33354565.389577378, 14289568.381625196
    Z = ss.ConstrainedZonotope(np.diag([s, s, s, s, 1.0]), [a, 3 * a, b, 7 * b, 0.0])
    J = np.array([[3.0, -1.0, 7.0, -1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0]]) @ Z
    cx = 3 * Fraction(a) - Fraction(3 * a) + 7 * Fraction(b) - Fraction(7 * b)
    spread = 12 * Fraction(s)
    return J, cx - spread, cx + spread


def test_the_optimal_filter_and_joint_range_restrictions_keep_the_range_s_rounding():
    J, lo, hi = _padded_joint_range()   # the stored centre is 0.0, the exact one −9.3e-9
    assert J.c[0] == 0.0 and J.pad is not None
    system = ss.LinearSystem([[1.0]], None, [[1.0]], W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    P = ss.optimal_filter(system, ss.JointRange(J, 1, 1, 1, 0), np.array([[0.0]]))[0]
    R = ss.JointRange(J, 1, 1, 1, 0)
    for S in (P, R.restrict([[0.0, 1.0]], [0.5]).set.project([0]),
              R.restrict_halfspaces([[0.0, 1.0]], [0.5]).set.project([0])):
        hull = S.interval_hull(certified=True)
        assert Fraction(hull.lo[0]) <= lo and Fraction(hull.hi[0]) >= hi


def test_the_residual_of_a_nominal_step_is_bounded_to_twice_the_working_precision():
    """A x̄ + B c + u − x̄' with x̄' = fl(A x̄ + B c + u) at states 1e6: the bound holds in rationals and
    exceeds the exact residual by far less than its own size (Dot2), where the plain γ_N bound of
    the sum was about 100 times the residual."""
    rng = np.random.default_rng(8)
    over = []
    for _ in range(100):
        A, B = rng.normal(size=(4, 4)), rng.normal(size=(4, 2))
        x, c, u = rng.normal(size=4) * 1e6, rng.normal(size=2), rng.normal(size=4) * 1e5
        nxt = A @ x + B @ c + u
        bound = rounding.residual_bound([(A, x), (B, c), (np.ones(4), u), (-np.ones(4), nxt)])
        for i in range(4):
            exact = (sum(Fraction(A[i, j]) * Fraction(x[j]) for j in range(4))
                     + sum(Fraction(B[i, j]) * Fraction(c[j]) for j in range(2))
                     + Fraction(u[i]) - Fraction(nxt[i]))
            assert abs(exact) <= Fraction(bound[i])
            over.append(float(Fraction(bound[i]) - abs(exact)))
    assert max(over) < 1e-20


def test_the_extended_precision_residual_bound_holds_in_rationals():
    """`extended_residual_bound` (one product in np.longdouble per pair, several residuals as columns)
    against exact rationals: sound on every row and column, and within a few 2⁻⁶⁴·Σ|terms| of the
    exact residual where the format is wider than binary64."""
    rng = np.random.default_rng(9)
    u_ext = float(np.finfo(np.longdouble).eps) / 2
    for _ in range(40):
        A, B = rng.normal(size=(4, 4)), rng.normal(size=(4, 2))
        X, c = rng.normal(size=(4, 3)) * 1e6, rng.normal(size=(2, 3))
        nxt = A @ X + B @ c
        bound = rounding.extended_residual_bound([(A, X), (B, c), (-np.ones(4), nxt)])
        assert bound.shape == (4, 3)
        for i in range(4):
            for k in range(3):
                exact = (sum(Fraction(A[i, j]) * Fraction(X[j, k]) for j in range(4))
                         + sum(Fraction(B[i, j]) * Fraction(c[j, k]) for j in range(2))
                         - Fraction(nxt[i, k]))
                assert abs(exact) <= Fraction(bound[i, k])
                magnitude = np.abs(A[i]) @ np.abs(X[:, k]) + np.abs(nxt[i, k])
                assert float(Fraction(bound[i, k]) - abs(exact)) <= 64 * max(u_ext, 2.0**-64) * magnitude


@pytest.mark.parametrize("capped", [False, True])
def test_mapped_pad_encloses_the_image_of_the_charges_in_rationals(capped):
    """M·(box(pad) ⊕ Z(P)) ⊆ box(charge) ⊕ Z(P') for `rounding.mapped_pad`'s (P', charge), checked by
    exact support values in random directions; ``capped``: so many generators that the oldest are
    boxed into the charge."""
    rng = np.random.default_rng(7)
    n = 3
    q = (rounding.PAD_GENERATORS_PER_DIM * n + 5) if capped else 4
    for _ in range(10):
        M = rng.normal(size=(n, n)) * 10.0 ** rng.integers(-2, 3)
        pad = np.abs(rng.normal(size=n)) * 1e-10
        pad[rng.integers(n)] = 0.0
        P = rng.normal(size=(n, q)) * 1e-10
        image, charge = rounding.mapped_pad(M, pad, P)
        assert image.shape[1] <= rounding.PAD_GENERATORS_PER_DIM * n
        assert not capped or image.shape[1] < q + n
        for d in rng.normal(size=(15, n)):
            Md = F(M).T @ F(d)
            exact = sum(abs(v) * Fraction(p) for v, p in zip(Md, pad)) + sum(
                abs(v) for v in F(P).T @ Md)
            stored = sum(abs(Fraction(x)) * Fraction(r) for x, r in zip(d, charge)) + sum(
                abs(v) for v in F(image).T @ F(d))
            assert stored >= exact


def test_a_hand_written_recursion_keeps_its_certified_hull_at_the_solvers_value():
    """The exact filter written by hand with `predict`/`update` on a 10-state system: carried as
    pad generators, the algebra's rounding stays at its own size, where a pad boxed at every linear
    map grew like ‖|A|‖^k (certified radius 1.4e10 at k = 30 against a solver value of 2.7). At
    k = 30 the certified hull encloses the independent trajectory-LP oracle's and is within 1e-6 of
    its width; at k = 100 it is within 1e-6 of the width of the solver's own values and holds the
    true state."""
    from setsmooth.analysis.random_systems import random_observable_system
    from setsmooth.filters.steps import predict, update
    from setsmooth.reliability.compare import TrajectoryOracle

    n, T = 10, 100
    rng = np.random.default_rng(2034)
    plant = random_observable_system(rng, n, n, n)
    box = ss.Box(-np.ones(n), np.ones(n))
    system = ss.LinearSystem(plant.A, None, plant.C, E=plant.B, W=box, V=box)
    X0 = ss.Box(-10 * np.ones(n), 10 * np.ones(n))
    xs, ys = ss.simulate(system, X0, T, rng)
    post = None
    for k, y in enumerate(ys):
        post = update(system, k, X0 if k == 0 else predict(system, k - 1, post), y)
        if k == 30:
            hull = post.interval_hull(certified=True)
            lo, hi = TrajectoryOracle(system, X0, ys[:k + 1]).hull(k)
            width = hi - lo
            assert np.all(hull.lo <= lo + 1e-9 * width) and np.all(hull.hi >= hi - 1e-9 * width)
            assert np.all(lo - hull.lo <= 1e-6 * width) and np.all(hull.hi - hi <= 1e-6 * width)
    certified, plain = post.interval_hull(certified=True), post.interval_hull(certified=False)
    width = plain.hi - plain.lo
    assert np.all(certified.lo <= plain.lo) and np.all(certified.hi >= plain.hi)
    assert np.all(plain.lo - certified.lo <= 1e-6 * width)
    assert np.all(certified.hi - plain.hi <= 1e-6 * width)
    assert np.all(certified.lo <= xs[T]) and np.all(xs[T] <= certified.hi)
