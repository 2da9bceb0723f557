"""The LSU paper's filters: LSU-CZ (Algorithm 1), LSUO, LSUP on the LSU model (4)–(6)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import setsmooth as ss
from setsmooth.filters.lsu import lsu_cz_reduction
from setsmooth.filters.lsu.cz import _support_system
from setsmooth.sets.cz_vertices import cz_vertices

A = np.array([[1.0, -0.5, 0.2], [0.5, 0.1, 0.0], [0.3, 0.0, -0.1]])
B = np.array([[0.1], [0.6], [0.3]])
C = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.5]])


def paper_model(K: float) -> ss.LSUModel:
    return ss.LSUModel(A, B, C, 1e-4 * np.ones(3), 10.0 ** -K * np.ones(2), -np.ones(3), np.ones(3))


def data(model, T, seed):
    rng = np.random.default_rng(seed)
    us = rng.standard_normal((T, 1))
    xs, ys = model.simulate(us, rng)
    return us, xs, ys


def test_simulated_noises_lie_in_their_boxes():
    model = paper_model(1.0)
    us, xs, ys = data(model, 50, 0)
    w = xs[1:] - xs[:-1] @ A.T - us[:-1] @ B.T
    v = ys - xs @ C.T
    assert np.all(np.abs(w) <= 1e-4) and np.all(np.abs(v) <= 0.1)
    assert np.all((xs[0] >= -1) & (xs[0] <= 1))


@pytest.mark.parametrize("max_generators, max_constraints", [(5, 1), (9, 2), (12, 3)])
def test_lsu_cz_supports_respect_the_complexity_maxima(max_generators, max_constraints):
    model = paper_model(0.5)
    us, xs, ys = data(model, 12, 1)
    result = ss.lsu_cz_filter(model, ys, us, max_generators=max_generators, max_constraints=max_constraints,
                              estimates=("interval_hull",), std=False)
    assert len(result) == 12 and result.filter == "LSU-CZ"
    assert all(S.ng <= max_generators and S.nc <= max_constraints for S in result.supports)


def test_each_lsu_cz_support_contains_the_exact_cz_posterior():
    # exact ⊆ support ⟺ h_exact(a) ≤ b for every facet a·x ≤ b of the (polytopic) support; the
    # facets come from the support's vertices, h_exact from the exact posterior's LPs.
    for K, seed, maxima in ((0.0, 2, (5, 1)), (2.0, 3, (9, 2))):
        model = paper_model(K)
        us, xs, ys = data(model, 8, seed)
        result = ss.lsu_cz_filter(model, ys, us, max_generators=maxima[0], max_constraints=maxima[1],
                                  estimates=(), std=False)
        exact = ss.classical_filter(_support_system(model, us), model.prior, ys)
        for t in (1, 3, 7):
            hull = ConvexHull(cz_vertices(result.supports[t]))
            normals, offsets = hull.equations[:, :-1], -hull.equations[:, -1]
            h_exact = exact[t].support_many(normals)
            scale = 1.0 + np.abs(offsets)
            assert np.all(h_exact <= offsets + 1e-7 * scale), (K, t)
            # and the reduced support is a strict outer approximation somewhere (it did reduce)
        assert any(S.ng > 0 for S in result.supports)


def inside_vertex_hull(S, x) -> bool:
    """x ∈ S by the facets of the hull of S's enumerated vertices (no LP)."""
    eq = ConvexHull(cz_vertices(S)).equations
    return bool(np.all(eq[:, :-1] @ x + eq[:, -1] <= 1e-12 * (1.0 + np.abs(eq[:, -1]))))


def test_true_state_is_inside_every_support_in_1000_seeded_runs():
    # Short horizons (the reduction acts from t = 1 on), every noise level and two complexity budgets.
    # CZ membership by the facets of the vertex hull, and by the membership LP in every 20th run.
    violations = runs = 0
    models = {K: paper_model(K) for K in (4.0, 3.0, 2.0, 1.0, 0.0)}
    for seed in range(1000):
        K = (4.0, 3.0, 2.0, 1.0, 0.0)[seed % 5]
        maxima = ((5, 1), (9, 2))[seed % 2]
        model = models[K]
        us, xs, ys = data(model, 3, seed)
        cz = ss.lsu_cz_filter(model, ys, us, max_generators=maxima[0], max_constraints=maxima[1],
                              estimates=(), std=False)
        box = ss.lsuo_filter(model, ys, us, std=False)
        par = ss.lsup_filter(model, ys, us, std=False)
        for t, x in enumerate(xs):
            P = par.supports[t]
            violations += not inside_vertex_hull(cz.supports[t], x)
            if seed % 20 == 0:
                violations += not cz.supports[t].contains(x, tol=0.0)
            violations += not box.supports[t].contains(x, tol=0.0)
            violations += not np.all(np.abs(np.linalg.solve(P.G, x - P.c)) <= 1.0)
        runs += 1
    assert runs == 1000 and violations == 0


def test_lsuo_boxes_are_the_certified_hulls_of_box_and_strip():
    model = paper_model(1.0)
    us, xs, ys = data(model, 6, 4)
    result = ss.lsuo_filter(model, ys, us)
    prior = model.prior
    for t in range(6):
        if t:
            prior = (A @ result.supports[t - 1] + B @ us[t - 1] + model.W).interval_hull()
        lp = prior.intersect_preimage(C, model.strip(ys[t])).interval_hull(certified=True)
        S = result.supports[t]
        assert np.all(S.lo <= lp.lo + 1e-12) and np.all(S.hi >= lp.hi - 1e-12)   # outer
        np.testing.assert_allclose([S.lo, S.hi], [lp.lo, lp.hi], atol=1e-8)       # and tight
        np.testing.assert_allclose(result.estimates["center"][t], S.midpoint())
        np.testing.assert_allclose(result.std[t], (S.hi - S.lo) / np.sqrt(12))


def test_lsup_supports_are_parallelotopes_of_no_larger_volume_than_the_kept_shape():
    model = paper_model(1.0)
    us, xs, ys = data(model, 10, 5)
    result = ss.lsup_filter(model, ys, us)
    for S in result.supports:
        assert S.ng == 3 and abs(np.linalg.det(S.G)) > 0
    # The data update's choice is the smallest of its candidates, which include the old faces.
    from setsmooth.filters.lsu.parallelotope import parallelotope_predict, parallelotope_update

    P = parallelotope_predict(result.supports[4], A, B @ us[4], model.omega)
    post = parallelotope_update(P, C, model.strip(ys[5]))
    Q = P.intersect_preimage(C, model.strip(ys[5]))
    H = np.linalg.inv(P.G)
    kept = np.prod(Q.support_many(H) + Q.support_many(-H)) / abs(np.linalg.det(H))
    assert abs(np.linalg.det(post.G)) * 8 <= kept * (1 + 1e-4)   # up to the vertex padding
    assert np.all(Q.support_many(np.eye(3)) <= post.support_many(np.eye(3)) + 1e-9)


def test_lsu_cz_low_noise_errors_are_at_the_noise_level_after_the_transient():
    model = paper_model(3.0)
    us, xs, ys = data(model, 40, 6)
    result = ss.lsu_cz_filter(model, ys, us)
    for key in ("interval_hull", "closest", "centroid"):
        assert np.max(np.abs(result.estimates[key][10:] - xs[10:])) < 2e-3, key
    assert result.std.shape == (40, 3) and np.all(result.std[10:] < 1e-3)


def test_lsu_filters_refuse_bad_data_and_impossible_maxima():
    model = paper_model(1.0)
    us, xs, ys = data(model, 5, 7)
    with pytest.raises(ValueError, match="us must have shape"):
        ss.lsu_cz_filter(model, ys, us[:4])
    with pytest.raises(ValueError, match="ys must have shape"):
        ss.lsuo_filter(model, ys[:, :1], us)
    with pytest.raises(ValueError, match="max_generators ≥ n \\+ max_constraints"):
        ss.lsu_cz_filter(model, ys, us, max_generators=3, max_constraints=1)
    with pytest.raises(TypeError, match="max_constraints must be an integer"):
        lsu_cz_reduction(3, 9, 2.0)
    with pytest.raises(ValueError, match="estimates must be among"):
        ss.lsu_cz_filter(model, ys, us, estimates=("mean",))
    with pytest.raises(ValueError, match="omega must hold positive"):
        ss.LSUModel(A, B, C, np.zeros(3), np.ones(2), -np.ones(3), np.ones(3))
    with pytest.raises(ValueError, match="C must have shape"):
        ss.LSUModel(A, B, C.T, np.ones(3), np.ones(2), -np.ones(3), np.ones(3))
    with pytest.raises(TypeError, match="model must be an LSUModel"):
        ss.lsup_filter("model", ys, us)


def test_inconsistent_data_give_empty_supports_and_nan_estimates():
    model = paper_model(3.0)
    us, xs, ys = data(model, 6, 8)
    ys = ys.copy()
    ys[3] += 1.0                       # an output no state can produce
    for f in (ss.lsu_cz_filter, ss.lsuo_filter, ss.lsup_filter):
        result = f(model, ys, us)
        assert all(isinstance(S, ss.EmptySet) for S in result.supports[3:]), f.__name__
        assert not any(isinstance(S, ss.EmptySet) for S in result.supports[:3])
        assert all(np.isnan(v[3:]).all() and np.isfinite(v[:3]).all() for v in result.estimates.values())


def test_kept_shape_lsup_contains_the_truth_and_is_looser_than_the_minimal_volume_choice():
    model = paper_model(0.0)
    us, xs, ys = data(model, 60, 9)
    kept = ss.lsup_filter(model, ys, us, construction="kept_shape")
    best = ss.lsup_filter(model, ys, us)
    assert kept.settings["construction"] == "kept_shape"
    for S, x in zip(kept.supports, xs):
        assert np.all(np.abs(np.linalg.solve(S.G, x - S.c)) <= 1.0)
    volume = [np.abs(np.linalg.det(r.supports[-1].G)) for r in (kept, best)]
    assert volume[1] < volume[0]
    with pytest.raises(ValueError, match="construction must be one of"):
        ss.lsup_filter(model, ys, us, construction="smallest")


def _cz_arrays(Z):
    return [None if a is None else np.asarray(a) for a in (Z.G, Z.c, Z.A, Z.b, Z.h, Z.pad, Z.pad_free,
                                                             Z._slack, Z._slack_free)]


def _same_bits(X, Y):
    for a, b in zip(_cz_arrays(X), _cz_arrays(Y)):
        assert (a is None) == (b is None)
        if a is not None:
            assert a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("by_component", [False, True])
def test_strip_sets_equal_the_strips_cz_forms_bit_for_bit(by_component):
    # Rows with and without a rounding pad (midpoints and radii not representable: 0.1 ± 0.3 etc.),
    # a row of exact zeros and one of huge and tiny values side by side.
    model = ss.LSUModel(A, B, C, 1e-4 * np.ones(3), np.array([0.3, 1e-17]), -np.ones(3), np.ones(3))
    us, xs, ys = data(model, 40, 3)
    ys = np.vstack([ys, [[0.1, 0.7]], [[0.0, 0.0]], [[1e16, -3e-300]], [[0.5, 0.25]]])
    got = model.strip_sets(ys, by_component=by_component)
    assert len(got) == len(ys)
    pads = 0
    for y, sets in zip(ys, got):
        S = model.strip(y)
        expected = [ss.Box(S.lo[j:j + 1], S.hi[j:j + 1])._flat_cz for j in range(model.m)] \
            if by_component else [S._flat_cz]
        for X, Y in zip(sets if by_component else [sets], expected):
            _same_bits(X, Y)
            pads += Y.pad is not None
    assert pads > 0  # the pad path is exercised


def test_intersection_vertices_equal_those_of_the_charged_intersection_bit_for_bit():
    from setsmooth.filters.lsu._strips import box_form, intersection_vertices
    from setsmooth.sets.algebra import generalized_intersection

    rng = np.random.default_rng(7)
    model = ss.LSUModel(A, B, C, 1e-4 * np.ones(3), np.array([0.3, 0.1]), -np.ones(3), np.ones(3))
    ys = rng.uniform(-1, 1, (30, 2))
    for t, (strip, parts) in enumerate(zip(model.strip_sets(ys), model.strip_sets(ys, by_component=True))):
        Z = ss.Zonotope(rng.standard_normal((3, 3)) * 0.5, rng.uniform(-0.2, 0.2, 3))
        lo = rng.uniform(-1, 0, 3) / 3
        box = ss.Box(lo, lo + rng.uniform(0.1, 1, 3))
        cases = [(Z.G, Z.c, Z, C, strip), (Z.G, Z.c, Z, C[:1], parts[0]), (Z.G, Z.c, Z, C, model.strip(ys[t])),
                 (*box_form(box), box, C, strip)]
        for G, c, S, R, Y in cases:
            got = intersection_vertices(G, c, R, Y)
            expected = cz_vertices(generalized_intersection(S, R, Y))
            assert got.shape == expected.shape and got.tobytes() == expected.tobytes()
    assert box_form(ss.Box([0.0, -np.inf], [1.0, 0.0])) is None


@pytest.mark.parametrize("K", [0.0, 1.0, 3.0])
def test_lsuo_lsup_equal_their_fully_intersected_runs_bit_for_bit(K, monkeypatch):
    import setsmooth.filters.lsu.orthotope as orthotope
    import setsmooth.filters.lsu.parallelotope as parallelotope

    model = paper_model(K)
    us, xs, ys = data(model, 40, 11)
    runs = lambda: [ss.lsuo_filter(model, ys, us), ss.lsup_filter(model, ys, us),
                    ss.lsup_filter(model, ys, us, construction="kept_shape")]
    fast = runs()
    monkeypatch.setattr(orthotope, "intersection_vertices", lambda *args: None)
    monkeypatch.setattr(parallelotope, "intersection_vertices", lambda *args: None)
    full = runs()
    for a, b in zip(fast, full):
        assert a.estimates["center"].tobytes() == b.estimates["center"].tobytes()
        assert a.std.tobytes() == b.std.tobytes()
        for S, T in zip(a.supports, b.supports):
            for name in ("lo", "hi", "G", "c"):
                if hasattr(S, name):
                    assert getattr(S, name).tobytes() == getattr(T, name).tobytes()


def test_the_strips_are_rounded_outward():
    """y ∓ v rounded to nearest can land inside the exact strip (1 − 1e-17 rounds to 1): the strip
    bounds are rounded outward, per step and for the whole sequence alike."""
    from fractions import Fraction

    model = ss.LSUModel([[0.9]], [[1.0]], [[1.0]], [0.1], [1e-17], [-1.0], [1.0])
    ys = np.array([[1.0], [3.0], [-0.3]])
    for y, strip_set in zip(ys, model.strip_sets(ys)):
        strip = model.strip(y)
        lo, hi = Fraction(float(strip.lo[0])), Fraction(float(strip.hi[0]))
        exact_lo, exact_hi = Fraction(float(y[0])) - Fraction(1e-17), Fraction(float(y[0])) + Fraction(1e-17)
        assert lo <= exact_lo and exact_hi <= hi
        assert strip_set.support_many(np.array([[1.0], [-1.0]]), certified=True)[0] >= float(exact_hi)


def test_the_parallelotope_choice_takes_numpys_nanargmin():
    """`_nanargmin` (the minimal-volume choice without np.nanargmin's wrapper) answers as
    np.nanargmin: NaN read as +inf, ties to the first, ValueError when every entry is NaN."""
    from setsmooth.filters.lsu.parallelotope import _nanargmin

    rng = np.random.default_rng(0)
    for _ in range(500):
        v = rng.standard_normal(int(rng.integers(1, 12)))
        v[rng.random(v.size) < 0.3] = np.nan
        v[rng.random(v.size) < 0.1] = np.inf
        if rng.random() < 0.2:
            v[:] = v[0]
        try:
            expected = int(np.nanargmin(v))
        except ValueError:
            with pytest.raises(ValueError):
                _nanargmin(v)
            continue
        assert _nanargmin(v) == expected
