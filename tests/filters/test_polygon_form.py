"""``classical_filter(form='polygon')`` and the recursion smoother on its Polygons, against HiGHS's LP
over the raw trajectory variables and against the constrained-zonotope paths."""

from __future__ import annotations

import pickle
from fractions import Fraction

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.papers.smoothing_examples import smoothing_example_31, smoothing_example_31_x0
from tests.sets import polygon_reference as ref
from tests.test_posterior_views import highs_support

T = 50
STEPS = (0, 1, 2, 7, 25, 49, 50)
#: Relative agreement with the exact LP optimum: HiGHS's own accuracy, not ours (ours is ~1e-12).
REL_HIGHS = 1e-9
REL_CZ = 1e-7


def certified_hulls(sets):
    hulls = [S.interval_hull(certified=True) for S in sets]
    return np.array([h.lo for h in hulls]), np.array([h.hi for h in hulls])


def assert_encloses_highs(lo, hi, system, X0, ys, last=None):
    """Certified hull faces are ≥ the exact optimum (HiGHS, to its tolerance) and close to it."""
    for k in STEPS:
        for i, d in enumerate(np.eye(2)):
            top = highs_support(system, X0, ys, k, d, last=last)
            bottom = -highs_support(system, X0, ys, k, -d, last=last)
            scale = 1 + max(abs(top), abs(bottom))
            assert hi[k, i] >= top - REL_HIGHS * scale and lo[k, i] <= bottom + REL_HIGHS * scale, k
            assert hi[k, i] - top <= REL_HIGHS * scale and bottom - lo[k, i] <= REL_HIGHS * scale, k


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_polygon_filter_and_smoother_on_example_31_are_the_exact_ranges(seed):
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    filtered = ss.classical_filter(system, X0, ys, form="polygon")
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=filtered)
    assert all(isinstance(S, ss.Polygon) for S in (*filtered, *smoothed))
    f_lo, f_hi = certified_hulls(filtered)
    s_lo, s_hi = certified_hulls(smoothed)
    assert_encloses_highs(f_lo, f_hi, system, X0, ys)
    assert_encloses_highs(s_lo, s_hi, system, X0, ys, last=T)
    # The constrained-zonotope paths (posterior views, trajectory smoother), certified hulls too.
    for (lo, hi), reference in (((f_lo, f_hi), ss.classical_filter(system, X0, ys)),
                                ((s_lo, s_hi), ss.optimal_smoother(system, X0, ys, method="trajectory"))):
        r_lo, r_hi = certified_hulls(reference)
        scale = 1 + np.abs(r_hi - r_lo).max()
        np.testing.assert_allclose(lo, r_lo, atol=REL_CZ * scale)
        np.testing.assert_allclose(hi, r_hi, atol=REL_CZ * scale)
    for lo, hi in ((f_lo, f_hi), (s_lo, s_hi)):
        assert np.all((lo <= xs) & (xs <= hi))
    assert np.all(s_lo >= f_lo - 1e-9) and np.all(s_hi <= f_hi + 1e-9)


def test_polygon_form_with_zonotope_and_vpolytope_noises_and_an_input_matches_the_views():
    base = smoothing_example_31()
    W = ss.VPolytope([[0.4, 0.1], [-0.3, 0.2], [0.1, -0.35]])
    V = ss.Zonotope([[1.0, 0.3, 0.0], [0.0, 0.5, 0.8]], [0.1, -0.2])
    system = ss.LinearSystem(base.A, np.eye(2), base.C, F=base.F, W=W, V=V,
                             u=lambda k: np.array([0.2, -0.1 * k]))
    X0 = ss.Zonotope([[3.0, 1.0], [0.0, 2.0]], [0.5, 0.0])
    xs, ys = ss.simulate(system, X0, 20, np.random.default_rng(5))
    ours = ss.classical_filter(system, X0, ys, form="polygon")
    views = ss.classical_filter(system, X0, ys)
    D = np.vstack([np.eye(2), -np.eye(2), np.random.default_rng(0).standard_normal((8, 2))])
    for k in (0, 3, 20):
        a, b = ours[k].support_many(D), views[k].support_many(D)
        np.testing.assert_allclose(a, b, atol=1e-6 * (1 + np.abs(b).max()))
        assert ours[k].contains(xs[k])
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=ours)
    reference = ss.optimal_smoother(system, X0, ys, method="trajectory")
    for k in (0, 10, 20):
        a, b = smoothed[k].support_many(D), reference[k].support_many(D)
        np.testing.assert_allclose(a, b, atol=1e-6 * (1 + np.abs(b).max()))


def test_inconsistent_data_give_empty_posteriors_from_the_first_certainly_empty_step():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 10, np.random.default_rng(0))
    ys = ys.copy()
    ys[6] += 100.0
    ours = ss.classical_filter(system, X0, ys, form="polygon")
    reference = ss.classical_filter(system, X0, ys)
    assert [isinstance(S, ss.EmptySet) for S in ours] == [S.is_empty() for S in reference]
    assert isinstance(ours[6], ss.EmptySet) and isinstance(ours[5], ss.Polygon)


def test_polygon_form_refuses_systems_it_does_not_apply_to():
    base = smoothing_example_31()
    _, ys = ss.simulate(base, smoothing_example_31_x0(), 3, np.random.default_rng(0))
    with pytest.raises(ValueError, match="X0 with a polygon form"):
        ss.classical_filter(base, ss.Ellipsoid([0.0, 0.0], np.eye(2)), ys, form="polygon")
    ellipsoid_w = ss.LinearSystem(base.A_at(0), None, base.C_at(0), F=base.F_at(0),
                                  W=ss.Ellipsoid([0.0, 0.0], np.eye(2) * 0.1), V=base.V)
    with pytest.raises(ValueError, match="E W with a polygon form"):
        ss.classical_filter(ellipsoid_w, smoothing_example_31_x0(), ys, form="polygon")
    three = ss.LinearSystem(np.eye(3), None, np.eye(3), W=ss.Box(-np.ones(3), np.ones(3)),
                            V=ss.Box(-np.ones(3), np.ones(3)))
    with pytest.raises(ValueError, match="n = 2"):
        ss.classical_filter(three, ss.Box(-np.ones(3), np.ones(3)), np.zeros((2, 3)), form="polygon")


def test_polygon_posteriors_pickle():
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 5, np.random.default_rng(0))
    P = ss.classical_filter(system, X0, ys, form="polygon")[-1]
    again = pickle.loads(pickle.dumps(P))
    np.testing.assert_array_equal(again.vertices, P.vertices)
    assert again.interval_hull(certified=True).hi.tolist() == P.interval_hull(certified=True).hi.tolist()


def rational_ranges(system, ys):
    """Algorithm 1 on example (31) in rational arithmetic (`polygon_reference`), X0 = [−5, 5]²: the
    posteriors and smoothed ranges as vertex lists, every coordinate rounded to a denominator ≤ 1e45
    after each step (so exact to ~1e-45, far below the 1e-9 the solvers resolve)."""
    A, Bcol, C = (np.asarray(M, dtype=float) for M in (system.A_at(0), system.E_at(0)[:, 0], system.C_at(0)))
    Af = [[Fraction(float(v)) for v in row] for row in A]
    BW = [(Fraction(float(Bcol[0])) * s, Fraction(float(Bcol[1])) * s) for s in (-1, 1)]

    def rounded(P):
        return ref.hull([(x.limit_denominator(10**45), y.limit_denominator(10**45)) for x, y in P])

    def mapped(P):
        return ref.hull([(Af[0][0] * x + Af[0][1] * y, Af[1][0] * x + Af[1][1] * y) for x, y in P])

    posteriors = []
    P = ref.exact_points([[-5, -5], [5, -5], [5, 5], [-5, 5]])
    for k, y in enumerate(ys):
        if k:
            P = ref.minkowski_sum(mapped(posteriors[-1]), BW)
        P = _measured(P, C, y)
        posteriors.append(rounded(P))
    smoothed = [posteriors[-1]]
    for k in range(len(ys) - 2, -1, -1):
        Y = ref.minkowski_sum(smoothed[-1], [(-x, -y) for x, y in BW])
        S = posteriors[k]
        for i in range(len(Y)):
            (x0, y0), (x1, y1) = Y[i], Y[(i + 1) % len(Y)]
            n = (y1 - y0, x0 - x1)
            S = ref.clip(S, (n[0] * Af[0][0] + n[1] * Af[1][0], n[0] * Af[0][1] + n[1] * Af[1][1]),
                         n[0] * x0 + n[1] * y0)
        smoothed.append(rounded(S))
    return posteriors, smoothed[::-1]


def _measured(P, C, y):
    """P ∩ {x : |C x − y|∞ ≤ 1}, the offsets y_i ± 1 formed exactly."""
    for i in range(2):
        for sign in (1, -1):
            a = tuple(sign * Fraction(float(v)) for v in C[i])
            P = ref.clip(P, a, sign * Fraction(float(y[i])) + 1)
    return P


def test_polygon_ranges_enclose_algorithm_1_in_rational_arithmetic_to_rounding_level():
    """Independent of every solver: the hulls enclose the exact ranges and exceed them by ≤ 1e-11
    (the CZ paths' certified hulls are ~1e-8 loose on the same data, HiGHS's optimum ~1e-8 off)."""
    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, 30, np.random.default_rng(11))
    exact_f, exact_s = rational_ranges(system, ys)
    filtered = ss.classical_filter(system, X0, ys, form="polygon")
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=filtered)
    for ours, exact in ((filtered, exact_f), (smoothed, exact_s)):
        lo, hi = certified_hulls(ours)
        e_lo = np.array([[float(min(p[i] for p in P)) for i in range(2)] for P in exact])
        e_hi = np.array([[float(max(p[i] for p in P)) for i in range(2)] for P in exact])
        assert np.all(lo <= e_lo + 1e-30) and np.all(hi >= e_hi - 1e-30)
        assert np.abs(lo - e_lo).max() <= 1e-11 and np.abs(hi - e_hi).max() <= 1e-11


def test_form_and_reduce_together_are_refused():
    system = ss.paper_examples.smoothing_example_31()
    with pytest.raises(ValueError, match="reduce"):
        ss.classical_filter(system, ss.Box([-5.0, -5.0], [5.0, 5.0]), np.zeros((3, 2)),
                            reduce=ss.Girard(4), form="polygon")


def test_the_smoother_charges_the_rounding_of_its_noise_image():
    """E W and E(−W) come from the set algebra in floating point: before the filter and the backward
    step charged their rounding, the certified hull of ⟦x_0 | y_0:1⟧ (1e-16 wide) missed the exact
    one by 5e-18 (the filter's charge alone covers this case; the step charges its own image)."""
    B = np.array([[0.10490011715303971, -0.535669373161111, -0.13109099775757493],
                  [1.3040000451301372, 0.9470809631292422, -0.0606446583254687]])
    w = np.array([0.1257302210933933, -0.1321048632913019, 0.6404226504432821])
    system = ss.LinearSystem(np.eye(2), None, np.eye(2), E=B, W=ss.Box(w, w),
                             V=ss.Box([-1e-16, -1e-16], [1e-16, 1e-16]))
    X0 = ss.Box([-1e-15, -1e-15], [1e-15, 1e-15])
    ys = np.zeros((2, 2))
    posteriors = ss.classical_filter(system, X0, ys, form="polygon")
    smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=posteriors)
    bw = [sum(Fraction(float(B[i, j])) * Fraction(float(w[j])) for j in range(3)) for i in range(2)]
    lo = [max(Fraction(-1e-16), Fraction(-1e-16) - bw[i]) for i in range(2)]
    hi = [min(Fraction(1e-16), Fraction(1e-16) - bw[i]) for i in range(2)]
    hull = smoothed[0].interval_hull(certified=True)
    for i in range(2):
        assert Fraction(float(hull.lo[i])) <= lo[i] and Fraction(float(hull.hi[i])) >= hi[i]
