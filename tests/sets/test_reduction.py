"""Order reduction: exact methods keep the set, outer methods contain it, counts are as asked.

Exactness and containment are checked on support values in random directions (hypothesis strategies
of every representation, sparse and extended CZs included) and against 2-D vertex enumeration of the
input; containment also on the certified values of the reduced set.
"""

from fractions import Fraction

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import setsmooth as ss
from setsmooth.sets.reduction.propagation import propagate
from tests.sets.strategies import (assert_supports_close, constrained_zonotopes, dims, ellipsoids,
                                   hpolytopes, rngs, sets, support_scale, zonotopes)

EXACT = [ss.DropZeros(), ss.DropDependentConstraints(), ss.MergeParallelGenerators(),
         ss.Rescale("iter"), ss.Rescale("exact")]
OUTER = [ss.EliminateConstraints(1), ss.EliminateConstraints(0), ss.Girard(1), ss.Girard(2.5),
         ss.Combastel(1), ss.Combastel(1.5), ss.IntervalHull(), ss.CORA_GIRARD, ss.CORA_COMBASTEL]

PROPERTY = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
FEW = settings(PROPERTY, max_examples=12)


def _label(m):
    return repr(m) if isinstance(m, ss.ReductionMethod) else "+".join(repr(x) for x in m)


def _random_directions(rng, n, k):
    return np.vstack([rng.standard_normal((k, n)), np.eye(n), -np.eye(n)])


def _assert_superset(S, R, D, rel=1e-7):
    """h_R(d) ≥ h_S(d) in every direction, up to the solver's accuracy on h_S."""
    hs = S.support_many(D)
    hr = R.support_many(D)
    scale = support_scale(hs, hr)
    assert np.all(hr >= hs - rel * scale), (hs - hr).max() / scale


def _lifted_with_sparse_and_parallel(rng, n, ng, nc, infinite=0):
    """A CZ with sparse storage, a duplicated (parallel) column and a zero factor: every exact method
    has something to do."""
    G = rng.standard_normal((n, ng))
    A = rng.standard_normal((nc, ng))
    G[:, 1], A[:, 1] = -2.0 * G[:, 0], -2.0 * A[:, 0]  # parallel lifted columns
    G[:, 2], A[:, 2] = 0.0, 0.0  # a factor that moves nothing
    h = rng.uniform(0.5, 1.5, ng)
    if infinite:
        h[3:3 + infinite] = np.inf
    xi0 = rng.uniform(-0.5, 0.5, ng) * np.where(np.isfinite(h), h, 1.0)
    A = np.vstack([A, 2.0 * A[:1]])  # a dependent row
    b = A @ xi0
    return ss.ConstrainedZonotope(sp.csc_matrix(G), rng.uniform(-1, 1, n), A=sp.csc_matrix(A), b=b, h=h)


# --------------------------------------------------------------------------------------------------
# Exact methods keep every support value
# --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("method", EXACT, ids=_label)
@PROPERTY
@given(data=st.data())
def test_exact_method_keeps_every_support_value(method, data):
    n = data.draw(dims(4))
    drawn = data.draw(st.one_of(constrained_zonotopes(n), constrained_zonotopes(n, bounded=False),
                                zonotopes(n)))
    S = drawn.set
    rng = data.draw(rngs())
    D = _random_directions(rng, n, 12)
    R = ss.reduce(S, method)
    assert type(R) is type(S)
    assert_supports_close(R.support_many(D), S.support_many(D), rel=1e-6)


@pytest.mark.parametrize("method", EXACT, ids=_label)
@pytest.mark.parametrize("seed", range(4))
def test_exact_method_keeps_sparse_cz_with_parallel_zero_and_free_factors(method, seed):
    rng = np.random.default_rng(seed)
    S = _lifted_with_sparse_and_parallel(rng, 3, 9, 3, infinite=seed % 2)
    D = _random_directions(rng, 3, 20)
    R = ss.reduce(S, method)
    assert_supports_close(R.support_many(D), S.support_many(D), rel=1e-6)
    assert sp.issparse(R.G) and sp.issparse(R.A)


def test_exact_methods_shrink_the_representation():
    S = _lifted_with_sparse_and_parallel(np.random.default_rng(0), 3, 9, 3)
    assert ss.reduce(S, ss.DropZeros()).ng == S.ng - 1
    assert ss.reduce(S, ss.DropDependentConstraints()).nc == S.nc - 1
    assert ss.reduce(S, ss.MergeParallelGenerators()).ng == S.ng - 1


def test_merging_parallel_zonotope_generators_is_exact():
    G = np.array([[1.0, -2.0, 0.5, 1.0], [1.0, -2.0, 0.0, 3.0]])
    Z = ss.Zonotope(G, [0.3, -0.2])
    R = ss.reduce(Z, ss.MergeParallelGenerators())
    assert R.ng == 3
    D = _random_directions(np.random.default_rng(1), 2, 30)
    assert_supports_close(R.support_many(D), Z.support_many(D), rel=1e-12)


def test_merging_nearly_parallel_generators_never_shrinks_the_set():
    # Four generators 1e-11 apart (relative) along one coordinate: merged (they are within
    # PARALLEL_TOL), but the spread is kept in a box, so no support value decreases, in any direction;
    # the closed-form zonotope support resolves 1e-11 where an LP could not.
    rng = np.random.default_rng(3)
    v = np.array([1.0, 2.0, 0.0])  # the spread is along e3 ⟂ v: one box generator keeps it
    G = np.column_stack([v, -2.0 * v + [0, 0, 2e-11], 0.5 * v + [0, 0, -1e-11], 3.0 * v + [0, 0, 3e-11],
                         rng.standard_normal(3)])
    Z = ss.Zonotope(G, np.zeros(3))
    R = ss.reduce(Z, ss.MergeParallelGenerators())
    assert R.ng < Z.ng
    e3 = np.array([0.0, 0.0, 1.0])  # where the spread shows
    D = np.vstack([_random_directions(rng, 3, 300), e3, -e3])
    hz, hr = Z.support_many(D), R.support_many(D)
    assert np.all(hr >= hz - 4 * np.finfo(float).eps * np.abs(hz).max())
    # The same for the lifted columns of a CZ. LP supports are accurate to ~1e-9 relative, which is
    # more than the spread: the merged set's certified supports (upper bounds) are compared.
    S = ss.ConstrainedZonotope(G, np.zeros(3), A=[[1.0, -2.0, 0.5, 3.0, 1.0]], b=[0.1])
    RS = ss.reduce(S, ss.MergeParallelGenerators())
    assert RS.ng < S.ng
    assert np.all(RS.support_many(D, certified=True) >= S.support_many(D) - 1e-9)


def test_exactly_parallel_generators_merge_without_a_box():
    v = np.array([1.0, 2.0, -0.5])
    Z = ss.Zonotope(np.column_stack([v, -2.0 * v, 0.5 * v]), np.zeros(3))
    R = ss.reduce(Z, ss.MergeParallelGenerators())
    assert R.ng == 1
    # 1 + 2 + 0.5 along v, rounded outward only (no box: nothing is left over).
    assert np.all(np.abs(R.G[:, 0]) >= 3.5 * np.abs(v))
    np.testing.assert_allclose(np.abs(R.G[:, 0]), 3.5 * np.abs(v), rtol=1e-14)


def test_a_free_factor_merged_with_a_parallel_bounded_one_stays_free():
    Z = ss.ConstrainedZonotope([[1.0, 2.0, 0.0]], [0.0], A=[[1.0, 2.0, 1.0]], b=[0.0], h=[np.inf, 1.0, 1.0])
    R = ss.reduce(Z, ss.MergeParallelGenerators())
    assert R.ng == 2 and np.isinf(R.h).sum() == 1
    # x = ξ0 + 2ξ1 = −ξ2 on the constraint: [−1, 1], before and after.
    assert R.support([1.0]) == pytest.approx(1.0, abs=1e-7)
    assert R.support([-1.0]) == pytest.approx(1.0, abs=1e-7)


@pytest.mark.parametrize("seed", range(6))
def test_rescale_exact_makes_every_factor_reach_its_bounds(seed):
    rng = np.random.default_rng(seed)
    ng, nc = 6, 3
    A = rng.standard_normal((nc, ng))
    Z = ss.ConstrainedZonotope(rng.standard_normal((2, ng)), np.zeros(2), A=A,
                               b=A @ rng.uniform(-0.6, 0.6, ng))
    R = ss.reduce(Z, ss.Rescale("exact"))
    factors = ss.ConstrainedZonotope(np.eye(R.ng), np.zeros(R.ng), A=R.A, b=R.b, h=R.h)
    hull = factors.interval_hull()
    # The tightest box, rescaled to [−1, 1] (up to the outward rounding margin).
    np.testing.assert_allclose(hull.hi, 1.0, atol=1e-6)
    np.testing.assert_allclose(hull.lo, -1.0, atol=1e-6)


@pytest.mark.parametrize("seed", range(10))
def test_propagated_factor_ranges_contain_the_exact_ranges(seed):
    rng = np.random.default_rng(seed)
    ng, nc = int(rng.integers(3, 9)), int(rng.integers(1, 4))
    A = rng.standard_normal((nc, ng)) * 10.0 ** rng.uniform(-3, 3, (nc, 1))
    h = rng.uniform(0.5, 2.0, ng)
    b = A @ (rng.uniform(-0.9, 0.9, ng) * h)
    lo, hi, Rlo, Rhi, crossed = propagate(A, b, h)
    assert not crossed
    exact = ss.ConstrainedZonotope(np.eye(ng), np.zeros(ng), A=A, b=b, h=h).interval_hull()
    scale = 1e-8 * (1 + h.max())
    assert np.all(lo <= exact.lo + scale) and np.all(hi >= exact.hi - scale)
    assert np.all(Rlo <= lo) and np.all(Rhi >= hi)


def _reference_propagate(A, b, h):
    """The propagation as first written (before issue 29's rewrite of its loop): every row through
    an index of its columns, the divisor test inside the row, lists indexing the used pivots."""
    import math

    from setsmooth import tolerances as tol
    from setsmooth.floating import gamma
    from setsmooth.sets.reduction._base import round_down, round_up
    from setsmooth.sets.reduction.propagation import _others_with_infinities

    nc, ng = A.shape
    M = np.hstack([A, np.eye(nc)])
    free = np.abs(A)
    threshold = tol.RANK_TOL * free.max(initial=0.0)
    rows, cols = [], []
    for step in range(min(nc, ng)):
        i, j = divmod(int(free.argmax()), ng)
        if free[i, j] <= threshold:
            break
        M[i] /= M[i, j]
        factor = M[:, j].copy()
        factor[i] = 0.0
        M -= factor[:, None] * M[i]
        rows.append(i)
        cols.append(j)
        free = np.abs(M[:, :ng])
        free[rows] = -1.0
        free[:, cols] = -1.0
    P = M[rows, ng:] / np.abs(M[rows, :ng]).sum(axis=1)[:, None]
    lo, hi = -h.astype(float), h.astype(float)
    Rlo, Rhi = np.full(ng, -np.inf), np.full(ng, np.inf)
    Ap, bp = P @ A, P @ b
    g = 2.0 * gamma(nc + 1)
    dA, db = g * (np.abs(P) @ np.abs(A)), g * (np.abs(P) @ np.abs(b))
    Alo = np.where(dA == 0.0, Ap, round_down(Ap - dA))
    Ahi = np.where(dA == 0.0, Ap, round_up(Ap + dA))
    seen = (Alo != 0.0) | (Ahi != 0.0)
    crossed_any = False
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for i in range(Ap.shape[0]):
            c = seen[i].nonzero()[0]
            alo, ahi, xlo, xhi = Alo[i, c], Ahi[i, c], lo[c], hi[c]
            p1, p2, p3, p4 = alo * xlo, alo * xhi, ahi * xlo, ahi * xhi
            tlo = np.fmin(np.fmin(p1, p2), np.fmin(p3, p4))
            thi = np.fmax(np.fmax(p1, p2), np.fmax(p3, p4))
            slo, shi = tlo.sum(), thi.sum()
            if math.isfinite(slo) and math.isfinite(shi):
                olo, ohi = slo - tlo, shi - thi
                mag = np.abs(tlo).sum() + np.abs(thi).sum()
            else:
                olo, ohi, mag = _others_with_infinities(tlo, thi)
            err = gamma(tlo.size + 4) * (mag + abs(bp[i]) + db[i])
            nlo, nhi = bp[i] - db[i] - ohi - err, bp[i] + db[i] - olo + err
            q1, q2, q3, q4 = nlo / alo, nlo / ahi, nhi / alo, nhi / ahi
            qlo = round_down(np.fmin(np.fmin(q1, q2), np.fmin(q3, q4)))
            qhi = round_up(np.fmax(np.fmax(q1, q2), np.fmax(q3, q4)))
            ok = (alo > 0.0) | (ahi < 0.0)
            qlo = np.maximum(np.where(ok, qlo, -np.inf), Rlo[c])
            qhi = np.minimum(np.where(ok, qhi, np.inf), Rhi[c])
            Rlo[c], Rhi[c] = qlo, qhi
            nlo, nhi = np.maximum(lo[c], qlo), np.minimum(hi[c], qhi)
            crossed = nlo > nhi
            if crossed.any():
                crossed_any = True
                nlo[crossed], nhi[crossed] = nhi[crossed], nlo[crossed]
            lo[c], hi[c] = nlo, nhi
    return lo, hi, Rlo, Rhi, crossed_any


@pytest.mark.parametrize("seed", range(40))
def test_propagation_equals_its_first_version_bit_for_bit(seed):
    """The propagation's loop, rewritten for speed (issue 29), gives the same bounds bit for bit:
    generator-only (zero) columns, free and fixed factors, dependent and inconsistent rows."""
    rng = np.random.default_rng(seed)
    nc, ng = int(rng.integers(1, 6)), int(rng.integers(2, 20))
    A = rng.standard_normal((nc, ng)) * 10.0 ** rng.uniform(-3, 3, (nc, 1))
    A[:, rng.random(ng) < 0.3] = 0.0                      # factors only in G
    if nc > 1 and seed % 4 == 1:
        A[-1] = 2.0 * A[0]                                 # a dependent row
    h = rng.uniform(0.5, 2.0, ng)
    h[rng.random(ng) < 0.15] = np.inf                      # free factors
    h[rng.random(ng) < 0.1] = 0.0                          # fixed ones
    b = A @ (rng.uniform(-0.9, 0.9, ng) * np.where(np.isfinite(h), h, 3.0))
    if seed % 5 == 2:
        b = b + 10.0 * np.abs(A).sum(axis=1)               # infeasible: crossed bounds
    _assert_propagates_like_the_reference(A, b, h)


def _assert_propagates_like_the_reference(A, b, h):
    """`propagate`'s bounds and crossing flag equal the row-by-row reference sweep's, bit for bit."""
    with np.errstate(invalid="ignore"):
        new = propagate(A, b, h)
    old = _reference_propagate(A, b, h)
    for x, y in zip(new[:4], old[:4]):
        assert x.tobytes() == y.tobytes()
    assert new.crossed == old[4]


def _filter_like_rows(rng, nc, ng, blocks):
    """Constraint rows as a reduced filter makes them: factors only in G (zero columns), and
    ``blocks`` groups of rows on their own factors (rows of one group see the same factors after
    preconditioning, those of the next group others), right-hand sides consistent."""
    A = np.zeros((nc, ng))
    row_groups = np.array_split(np.arange(nc), blocks)
    col_groups = np.array_split(rng.permutation(ng)[: int(0.8 * ng)], blocks)
    for rows, cols in zip(row_groups, col_groups):
        A[np.ix_(rows, cols)] = rng.standard_normal((rows.size, cols.size))
    return A


@pytest.mark.parametrize("seed", range(24))
def test_propagation_in_batches_equals_the_row_by_row_sweep_bit_for_bit(seed):
    """The sweep evaluates stretches of rows at once against the box and keeps them up to the first
    row that changes it (issue 29); its bounds are those of the row-by-row sweep bit for bit, on
    filter-sized data: rows seeing every factor or groups of rows seeing the same ones, boxes that
    change at many rows or at none, unbounded and fixed factors, crossed bounds."""
    rng = np.random.default_rng(seed)
    nc, ng = int(rng.integers(2, 31)), int(rng.integers(40, 151))
    A = _filter_like_rows(rng, nc, ng, blocks=1 + seed % 3)
    h = np.ones(ng) if seed % 2 else rng.uniform(0.5, 2.0, ng)
    if seed % 6 == 5:
        h[rng.random(ng) < 0.1] = np.inf                   # free factors: sums with infinities
    if seed % 8 == 3:
        h[rng.random(ng) < 0.1] = 0.0                      # fixed factors: ±0 products
    xi = rng.uniform(-1.0, 1.0, ng) * np.where(np.isfinite(h), h, 3.0)
    if seed % 4 == 0:
        xi *= 0.05                                         # deep inside: few rows tighten the box
    b = A @ xi
    if seed % 7 == 6:
        b[0] += 10.0 * np.abs(A[0]).sum()                  # infeasible: crossed bounds
    _assert_propagates_like_the_reference(A, b, h)


@pytest.mark.parametrize("seed", range(6))
def test_rows_a_batch_leaves_go_row_by_row_with_the_same_bounds(seed, monkeypatch):
    """A batch stops before a row whose floats it cannot vouch for (unbounded sums, a zero or NaN
    range: rare in practice, so flagged here at random); the rows from there on give the same bounds."""
    from setsmooth.sets.reduction import propagation

    rng = np.random.default_rng(100 + seed)
    vouched = propagation._fine

    def flag_some(*args):
        fine = vouched(*args)
        return np.logical_and.accumulate(fine & (rng.random(fine.size) < 0.7))

    monkeypatch.setattr(propagation, "_fine", flag_some)
    nc, ng = int(rng.integers(5, 25)), int(rng.integers(30, 90))
    A = _filter_like_rows(rng, nc, ng, blocks=1 + seed % 2)
    h = np.ones(ng)
    b = A @ rng.uniform(-1.0, 1.0, ng)
    new = propagate(A, b, h)
    old = _reference_propagate(A, b, h)
    for x, y in zip(new[:4], old[:4]):
        assert x.tobytes() == y.tobytes()
    assert new.crossed == old[4]

def test_propagation_pins_a_factor_exactly_determined_by_one_row():
    # ξ0 = 0.3 exactly (row 1), so ξ1 + ξ2 = 0.1·3 − ... every bound stays a rigorous enclosure.
    A = np.array([[3.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    b = np.array([0.9, 0.1])
    lo, hi, _, _, _ = propagate(A, b, np.ones(3))
    assert lo[0] <= 0.3 <= hi[0] and hi[0] - lo[0] < 1e-14


# --------------------------------------------------------------------------------------------------
# Outer methods contain the set
# --------------------------------------------------------------------------------------------------

@FEW
@given(data=st.data())
def test_every_outer_method_contains_the_set_in_200_directions(data):
    n = data.draw(dims(4))
    S = data.draw(st.one_of(constrained_zonotopes(n), zonotopes(n))).set
    rng = data.draw(rngs())
    D = _random_directions(rng, n, 200)
    hs = S.support_many(D)
    for method in OUTER:
        R = ss.reduce(S, method)
        hr = R.support_many(D, certified=isinstance(R, ss.ConstrainedZonotope) and R.nc > 0)
        scale = support_scale(hs, hr)
        assert np.all(hr >= hs - 1e-7 * scale), (_label(method), (hs - hr).max() / scale)


@pytest.mark.parametrize("kind", ["cz", "zonotope"])
@pytest.mark.parametrize("seed", range(5))
def test_outer_methods_contain_the_vertices_of_2d_sets(seed, kind):
    rng = np.random.default_rng(seed)
    ng, nc = 7, 3
    A = rng.standard_normal((nc, ng))
    if kind == "cz":
        S = ss.ConstrainedZonotope(rng.standard_normal((2, ng)), rng.uniform(-1, 1, 2), A=A,
                                   b=A @ rng.uniform(-0.7, 0.7, ng))
    else:
        S = ss.Zonotope(rng.standard_normal((2, ng)), rng.uniform(-1, 1, 2))
    V = S.vertices_2d()
    angles = np.linspace(0, 2 * np.pi, 200, endpoint=False) + 0.05
    D = np.column_stack([np.cos(angles), np.sin(angles)])
    oracle = (D @ V.T).max(axis=1)  # h_S(d) from the vertex enumeration
    for method in OUTER + EXACT:
        R = ss.reduce(S, method)
        hr = R.support_many(D)
        assert np.all(hr >= oracle - 1e-7 * (1 + np.abs(oracle).max())), _label(method)
        if method in EXACT:
            assert_supports_close(hr, oracle, rel=1e-6)


def test_interval_hull_of_a_zonotope_is_rigorous_in_floating_point():
    # Radii are sums of 0.1's, which round; the box must contain the exact rational sum.
    G = np.full((1, 37), 0.1)
    c = np.array([0.3])
    box = ss.reduce(ss.Zonotope(G, c), ss.IntervalHull())
    exact_hi = Fraction(0.3) + 37 * Fraction(0.1)
    exact_lo = Fraction(0.3) - 37 * Fraction(0.1)
    assert Fraction(box.hi[0]) >= exact_hi and Fraction(box.lo[0]) <= exact_lo


def test_girard_box_is_rigorous_in_floating_point():
    G = np.full((1, 40), 0.1)
    R = ss.reduce(ss.Zonotope(G, [0.0]), ss.Girard(1))
    assert R.ng == 1 and Fraction(R.G[0, 0]) >= 40 * Fraction(0.1)


@pytest.mark.parametrize("method", [ss.Girard(1), ss.Combastel(1)])
def test_lifted_box_of_a_cz_with_non_unit_bounds_is_rigorous_in_floating_point(method):
    # Bounds h = 0.1·(1 + j/7): the products |g|·h round. The boxed lifted radius must contain the
    # exact rational sum Σ h_j |L_ij| of whatever was boxed, and every kept column keeps its bound.
    ng = 30
    G = np.full((1, ng), 0.3)
    A = np.full((1, ng), 0.7)
    h = np.array([0.1 * (1 + j / 7) for j in range(ng)])
    Z = ss.ConstrainedZonotope(G, [0.0], A=A, b=[0.0], h=h)
    R = ss.reduce(Z, method)
    exact_g = sum(Fraction(0.3) * Fraction(x) for x in h)
    exact_a = sum(Fraction(0.7) * Fraction(x) for x in h)
    # Everything is boxed here (ng ≫ target 2): one G-row and one A-row radius, bound 1.
    assert R.ng == 2 and np.all(R.h == 1.0)
    assert Fraction(np.abs(R.G).max()) * Fraction(R.h[0]) >= exact_g
    assert Fraction(np.abs(R.A).max()) >= exact_a


def test_interval_hull_of_an_unconstrained_cz_with_non_unit_bounds_is_rigorous():
    h = np.array([0.1 * (1 + j / 7) for j in range(25)])
    Z = ss.ConstrainedZonotope(np.full((1, 25), 0.3), [0.0], h=h)
    box = ss.reduce(Z, ss.IntervalHull())
    assert Fraction(box.hi[0]) >= sum(Fraction(0.3) * Fraction(x) for x in h)


# --------------------------------------------------------------------------------------------------
# Counts after reduction
# --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("order", [1, 1.5, 2, 3.7])
@pytest.mark.parametrize("method", [ss.Girard, ss.Combastel])
def test_generator_reduction_reaches_the_order_asked(order, method):
    rng = np.random.default_rng(0)
    for n in (1, 2, 5):
        Z = ss.Zonotope(rng.standard_normal((n, 6 * n)), np.zeros(n))
        assert ss.reduce(Z, method(order)).ng <= np.floor(order * n)
        ng, nc = 5 * n + 3, n + 1
        A = rng.standard_normal((nc, ng))
        C = ss.ConstrainedZonotope(rng.standard_normal((n, ng)), np.zeros(n), A=A,
                                   b=A @ rng.uniform(-0.5, 0.5, ng))
        R = ss.reduce(C, method(order))
        assert R.nc == nc and R.ng - R.nc <= order * n  # degrees-of-freedom order


@pytest.mark.parametrize("k", [0, 1, 3])
def test_eliminate_constraints_reaches_the_count_asked(k):
    rng = np.random.default_rng(k)
    for n, ng, nc in [(2, 10, 6), (4, 14, 7), (3, 9, 2)]:
        A = rng.standard_normal((nc, ng))
        Z = ss.ConstrainedZonotope(rng.standard_normal((n, ng)), np.zeros(n), A=A,
                                   b=A @ rng.uniform(-0.5, 0.5, ng))
        R = ss.reduce(Z, ss.EliminateConstraints(k))
        # Each elimination removes one factor with its constraint: degrees of freedom never grow.
        assert R.nc <= k and R.ng - R.nc <= Z.ng - Z.nc


def test_cora_pipeline_keeps_one_constraint_and_dof_order_one():
    rng = np.random.default_rng(5)
    n, ng, nc = 4, 20, 8
    A = rng.standard_normal((nc, ng))
    Z = ss.ConstrainedZonotope(rng.standard_normal((n, ng)), np.zeros(n), A=A,
                               b=A @ rng.uniform(-0.5, 0.5, ng))
    for pipeline in (ss.CORA_GIRARD, ss.CORA_COMBASTEL):
        R = ss.reduce(Z, pipeline)
        assert R.nc <= 1 and R.ng - R.nc <= n
    assert ss.CORA_GIRARD == (ss.Rescale("iter"), ss.EliminateConstraints(1), ss.Girard(1))
    assert ss.CORA_COMBASTEL == (ss.Rescale("iter"), ss.EliminateConstraints(1), ss.Combastel(1))


def test_a_pipeline_is_its_methods_applied_one_by_one():
    # reduce(Z, (m1, m2, m3)) applies every method in order: no step is skipped as redundant
    # (skipping Rescale('iter') before EliminateConstraints once left nc = 1 where the rescaled data
    # eliminate exactly to nc = 0, and made the CORA filter 2.7× looser at n = 20).
    rng = np.random.default_rng(8)
    n, ng, nc = 3, 12, 4
    A = rng.standard_normal((nc, ng))
    Z = ss.ConstrainedZonotope(rng.standard_normal((n, ng)), np.zeros(n), A=A,
                               b=A @ rng.uniform(-0.5, 0.5, ng))
    R = ss.reduce(Z, ss.CORA_GIRARD)
    stepwise = Z
    for method in ss.CORA_GIRARD:
        stepwise = ss.reduce(stepwise, method)
    assert (R.ng, R.nc) == (stepwise.ng, stepwise.nc)
    np.testing.assert_array_equal(R.G, stepwise.G)
    np.testing.assert_array_equal(R.A, stepwise.A)
    D = _random_directions(rng, n, 100)
    hz, hr = Z.support_many(D), R.support_many(D)
    assert np.all(hr >= hz - 1e-7 * support_scale(hz, hr))


def test_eliminating_through_a_row_cancels_a_dependent_row_to_nothing():
    # Row 1 = 0.1·row 0 (the data of a set-algebra chain can carry such pairs): substituting factor
    # 2 through row 0 cancels row 1 to rounding noise (~1e-17), which interval propagation would take
    # literally after normalizing the row. It is dropped, not kept as a bogus constraint.
    from setsmooth.sets.reduction._base import CZData
    from setsmooth.sets.reduction.constraints import eliminate_factor
    r0 = np.array([0.7, 0.1, 0.3, 0.9])
    A = np.vstack([r0, 0.1 * r0])
    xi = np.array([0.2, -0.4, 0.1, 0.3])
    Z = ss.ConstrainedZonotope(np.array([[1.0, 0.3, 0.2, 0.0], [0.0, 1.0, -0.5, 0.4]]), np.zeros(2),
                               A=A, b=A @ xi)
    out = eliminate_factor(CZData.of(Z), 2)
    assert out.nc == 0 and out.ng == 3
    R = out.to_set()
    D = _random_directions(np.random.default_rng(0), 2, 50)
    assert np.all(R.support_many(D) >= Z.support_many(D) - 1e-9)


def test_elimination_does_not_call_a_set_empty_when_the_solver_cannot_settle_it(monkeypatch):
    # Propagation finds point-like data a hair infeasible; if the emptiness program then cannot be
    # settled, the set is not declared empty (the result must still contain it).
    import setsmooth.sets.reduction.constraints as constraints
    from setsmooth.sets.reduction.propagation import FactorBounds

    def crossed(A, b, h):
        fb = propagate(A, b, h)
        return FactorBounds(fb.lo, fb.hi, fb.Rlo, fb.Rhi, True)

    def unsettled(self):
        raise ss.SolverError("AlmostPrimalInfeasible", "test")
    monkeypatch.setattr(constraints, "propagate", crossed)
    monkeypatch.setattr(ss.ConstrainedZonotope, "is_empty", unsettled)
    Z = ss.ConstrainedZonotope(np.eye(3), np.zeros(3), A=[[1.0, 1.0, 0.0], [0.0, 1.0, 1.0]], b=[0.5, 0.2])
    R = ss.reduce(Z, ss.EliminateConstraints(1))
    assert isinstance(R, ss.ConstrainedZonotope)


# --------------------------------------------------------------------------------------------------
# Extended CZs, empty sets, unsupported types, bad input
# --------------------------------------------------------------------------------------------------

def test_eliminating_free_factors_loses_nothing():
    # Two free factors in two generic constraints: EliminateConstraints(0) only eliminates free
    # factors, which is exact.
    rng = np.random.default_rng(2)
    ng, nc = 6, 2
    h = np.ones(ng)
    h[:nc] = np.inf
    A = rng.standard_normal((nc, ng))
    Z = ss.ConstrainedZonotope(rng.standard_normal((3, ng)), np.zeros(3), A=A,
                               b=A @ rng.uniform(-0.5, 0.5, ng), h=h)
    R = ss.reduce(Z, ss.EliminateConstraints(0))
    assert R.nc == 0 and np.isfinite(R.h).all()
    D = _random_directions(rng, 3, 30)
    assert_supports_close(R.support_many(D), Z.support_many(D), rel=1e-6)


def test_unbounded_cz_stays_unbounded_in_the_same_directions():
    Z = ss.ConstrainedZonotope([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], [0.0, 0.0], A=[[0.0, 1.0, 1.0]],
                               b=[0.2], h=[np.inf, 1.0, 1.0])
    D = _random_directions(np.random.default_rng(0), 2, 10)
    for method in EXACT + [ss.EliminateConstraints(0), ss.IntervalHull(), ss.Girard(3)]:
        R = ss.reduce(Z, method)
        assert np.array_equal(np.isinf(R.support_many(D)), np.isinf(Z.support_many(D))) or \
            not method.exact, _label(method)
        assert np.all(R.support_many(D) >= Z.support_many(D) - 1e-7)


def test_generator_reduction_refuses_free_factors_it_cannot_keep():
    Z = ss.ConstrainedZonotope(np.eye(2, 4), [0.0, 0.0], A=[[1.0, 1.0, 1.0, 1.0]], b=[0.0],
                               h=[np.inf, 1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="free factors"):
        ss.reduce(Z, ss.Girard(1))


def test_inconsistent_constraints_give_the_empty_set():
    Z = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0], [2.0, 2.0]], b=[0.5, 3.0])
    assert isinstance(ss.reduce(Z, ss.DropDependentConstraints()), ss.EmptySet)
    zero_row = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[0.0, 0.0]], b=[1.0])
    assert isinstance(ss.reduce(zero_row, ss.DropZeros()), ss.EmptySet)
    infeasible = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[3.0])
    assert isinstance(ss.reduce(infeasible, ss.Rescale("iter")), ss.EmptySet)
    assert isinstance(ss.reduce(infeasible, ss.Rescale("exact")), ss.EmptySet)
    assert isinstance(ss.reduce(infeasible, ss.CORA_GIRARD), ss.EmptySet)


@pytest.mark.parametrize("method", EXACT + OUTER, ids=_label)
def test_empty_set_in_gives_empty_set_out(method):
    assert ss.reduce(ss.EmptySet(3), method) == ss.EmptySet(3)


@pytest.mark.parametrize("method", EXACT + OUTER, ids=_label)
def test_a_box_is_already_reduced(method):
    B = ss.Box([-1.0, 0.0], [1.0, 2.0])
    assert ss.reduce(B, method) is B


@settings(max_examples=10, deadline=None)
@given(data=st.data())
def test_unsupported_types_raise_naming_method_and_type(data):
    n = data.draw(dims(3))
    S = data.draw(st.one_of(hpolytopes(n), ellipsoids(n), sets(n, depth=1).filter(
        lambda d: not isinstance(d.set, (ss.Zonotope, ss.ConstrainedZonotope, ss.Box, ss.EmptySet))))).set
    for method in EXACT + [ss.Girard(1), ss.IntervalHull()]:
        with pytest.raises(NotImplementedError, match=type(S).__name__) as err:
            ss.reduce(S, method)
        assert type(method).__name__ in str(err.value)


def test_bad_arguments_are_refused_at_the_door():
    Z = ss.Zonotope(np.eye(2), np.zeros(2))
    with pytest.raises(ValueError, match="order"):
        ss.Girard(0.5)
    with pytest.raises(ValueError, match="order"):
        ss.Combastel(float("nan"))
    with pytest.raises(ValueError, match="'iter' or 'exact'"):
        ss.Rescale("fast")
    with pytest.raises(ValueError, match="max_constraints"):
        ss.EliminateConstraints(-1)
    with pytest.raises(TypeError, match="max_constraints"):
        ss.EliminateConstraints(1.5)
    with pytest.raises(TypeError, match="max_constraints"):
        ss.EliminateConstraints(True)
    with pytest.raises(TypeError, match="order"):
        ss.Girard(True)
    with pytest.raises(TypeError, match="order"):
        ss.Combastel("1")
    with pytest.raises(TypeError, match="method_or_methods"):
        ss.reduce(Z, "girard")
    with pytest.raises(TypeError, match="method_or_methods"):
        ss.reduce(Z, [])
    with pytest.raises(TypeError, match="method_or_methods"):
        ss.reduce(Z, [ss.Girard(1), "girard"])
    with pytest.raises(TypeError, match="ConvexSet"):
        ss.reduce(np.eye(2), ss.Girard(1))


def test_methods_are_immutable_values():
    m = ss.Girard(2)
    assert m == ss.Girard(2) and hash(m) == hash(ss.Girard(2)) and m != ss.Combastel(2)
    with pytest.raises(AttributeError):
        m.order = 3


def test_drop_zeros_returns_the_set_itself_when_nothing_is_zero():
    """The fast answer of DropZeros (no zero row, every factor used) is the set itself, as the
    general path gives; a zero row or an unused factor still goes through it."""
    rng = np.random.default_rng(2)
    G, A = rng.standard_normal((2, 4)), rng.standard_normal((2, 4))
    Z = ss.ConstrainedZonotope(G, np.zeros(2), A=A, b=[0.1, 0.2])
    assert ss.reduce(Z, ss.DropZeros()) is Z
    G0 = G.copy()
    G0[:, 3] = 0.0
    A0 = A.copy()
    A0[:, 3] = 0.0
    unused = ss.ConstrainedZonotope(G0, np.zeros(2), A=A0, b=[0.1, 0.2])
    assert ss.reduce(unused, ss.DropZeros()).ng == 3
    zero_row = ss.ConstrainedZonotope(G, np.zeros(2), A=np.vstack([A[:1], np.zeros((1, 4))]), b=[0.1, 0.0])
    assert ss.reduce(zero_row, ss.DropZeros()).nc == 1
