"""Uniform sampling without one LP per proposal: exact (vertex hull simplices) and hit-and-run."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import setsmooth as ss
import scipy.sparse as sp

from setsmooth.sets.sampling import _chord_function, _CZChords, exact_geometry, hit_and_run, uniform_sample
from setsmooth.sets.cz_vertices import cz_vertices, hull_geometry, vertex_candidate_count

# A thin asymmetric quadrilateral as a CZ: a zonotope cut by one constraint.
PENTAGON = ss.ConstrainedZonotope([[1.0, 0.5, 0.2], [0.0, 1.0, 0.7]], [0.3, -0.2],
                                  A=[[1.0, 1.0, 0.5]], b=[0.6])
TRIANGLE = ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [1.0, 0.0, 0.0])


def binomial_bound(p: float, n: int) -> float:
    return 4.5 * np.sqrt(p * (1 - p) / n)


def test_cz_vertices_span_the_same_polygon_as_the_support_function_oracle():
    V = cz_vertices(PENTAGON)
    assert hull_geometry(V).volume == pytest.approx(PENTAGON.area(), rel=1e-7)
    D = np.random.default_rng(0).standard_normal((20, 2))
    np.testing.assert_allclose((V @ D.T).max(axis=0), PENTAGON.support_many(D), rtol=1e-7, atol=1e-9)


def test_cz_vertices_of_a_3d_cz_match_its_interval_hull_and_support_values():
    rng = np.random.default_rng(1)
    Z = ss.ConstrainedZonotope(rng.standard_normal((3, 8)), rng.standard_normal(3),
                               A=rng.standard_normal((2, 8)), b=0.3 * rng.standard_normal(2))
    V = cz_vertices(Z)
    hull = Z.interval_hull(certified=False)
    np.testing.assert_allclose(V.min(axis=0), hull.lo, atol=1e-7)
    np.testing.assert_allclose(V.max(axis=0), hull.hi, atol=1e-7)
    D = rng.standard_normal((30, 3))
    np.testing.assert_allclose((V @ D.T).max(axis=0), Z.support_many(D), rtol=1e-7, atol=1e-7)
    assert vertex_candidate_count(8, 2) == 28 * 64


def test_hull_geometry_moments_of_a_box_and_a_triangle_are_exact():
    box = hull_geometry(np.array([[0, 0], [2, 0], [0, 1], [2, 1], [1, 0.5]], dtype=float))
    assert box.volume == pytest.approx(2.0)
    np.testing.assert_allclose(box.centroid, [1.0, 0.5])
    np.testing.assert_allclose(box.covariance, np.diag([4 / 12, 1 / 12]), atol=1e-12)
    tri = hull_geometry(np.array([[0, 0], [1, 0], [0, 1]], dtype=float))
    np.testing.assert_allclose(tri.centroid, [1 / 3, 1 / 3])
    np.testing.assert_allclose(tri.covariance, [[1 / 18, -1 / 36], [-1 / 36, 1 / 18]], atol=1e-12)


def _parallelotope(edges: np.ndarray, offset: float) -> np.ndarray:
    """The 2^n corners offset + Σ s_i e_i (s_i ∈ {0, 1}) and the centre: exactly representable here."""
    signs = np.array(list(itertools.product([0.0, 1.0], repeat=len(edges))))
    P = signs @ edges + offset
    return np.vstack([P, offset + edges.sum(axis=0) / 2])


@pytest.mark.parametrize("edges, offset", [
    (np.array([[1.0, 1.0], [2.0 ** -18, -(2.0 ** -18)]]), 2.0 ** 33),   # Qhull: initial simplex is flat
    (np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [2.0 ** -18, 2.0 ** -18, -(2.0 ** -18)]]), 2.0 ** 30),
    (np.diag([2.0 ** -10, 2.0 ** -12, 2.0 ** -30]), 0.75),               # 1e-3 wide, 1e-9 thick
])
def test_a_thin_set_far_from_the_origin_or_small_has_its_volume_and_centroid(edges, offset):
    # Each is thin but not flat relative to its own extent (4e-6, 4e-6, 1e-6). The first two, given to
    # Qhull in raw coordinates, raised QhullError (its precision is relative to the largest coordinate);
    # the third the rank test with a floor of 1 called flat.
    geometry = hull_geometry(_parallelotope(edges, offset))
    assert geometry.volume == pytest.approx(abs(np.linalg.det(edges)), rel=1e-9)
    np.testing.assert_allclose(geometry.centroid, offset + edges.sum(axis=0) / 2, rtol=0,
                               atol=8 * np.spacing(offset))


def test_exact_samples_match_exact_area_fractions_in_2d():
    rng = np.random.default_rng(2)
    x = PENTAGON.sample(rng, 4000)
    assert all(PENTAGON.contains(p) for p in x[:20])
    for a in (0.0, 0.4, 0.9):     # the part with x1 ≤ a
        lo = PENTAGON.interval_hull().lo[0]
        part = PENTAGON.intersect_preimage([[1.0, 0.0]], ss.Box([lo - 1], [a]))
        p = part.area() / PENTAGON.area()
        assert np.mean(x[:, 0] <= a) == pytest.approx(p, abs=binomial_bound(p, 4000))


def test_exact_samples_match_exact_volume_fractions_in_3d():
    rng = np.random.default_rng(3)
    Z = ss.ConstrainedZonotope(rng.standard_normal((3, 6)), np.zeros(3), A=rng.standard_normal((1, 6)),
                               b=[0.2])
    x = Z.sample(rng, 4000, method="exact")
    d = np.array([1.0, -0.5, 0.3])
    cut = float(np.median(x @ d))
    lo = -Z.support(-d)
    part = Z.intersect_preimage(d[None, :], ss.Box([lo - 1], [cut]))
    p = hull_geometry(cz_vertices(part)).volume / hull_geometry(cz_vertices(Z)).volume
    assert np.mean(x @ d <= cut) == pytest.approx(p, abs=binomial_bound(p, 4000))
    np.testing.assert_allclose(x.mean(axis=0), exact_geometry(Z).centroid, atol=0.05)


def test_hit_and_run_on_an_h_polytope_matches_area_fractions_without_any_chord_program():
    x = TRIANGLE.sample(np.random.default_rng(4), 3000)       # H-polytope: hit-and-run, closed chords
    assert np.all(x.sum(axis=1) <= 1 + 1e-12) and np.all(x >= -1e-12)
    assert np.mean(x.sum(axis=1) <= 0.5) == pytest.approx(0.25, abs=0.04)
    np.testing.assert_allclose(x.mean(axis=0), [1 / 3, 1 / 3], atol=0.03)


def test_hit_and_run_with_kept_cz_chords_stays_inside_and_is_roughly_uniform():
    # A set without an H-representation: every chord is one program re-solved along the walk.
    fat = ss.ConstrainedZonotope([[1.0, 0.0, 0.5], [0.0, 1.0, 0.5]], [0.0, 0.0], A=[[0.5, 0.5, 1.0]], b=[0.2])
    x = hit_and_run(fat, np.random.default_rng(5), 150, thin=2, burn_in=60)
    assert all(fat.contains(p) for p in x[::15])
    part = fat.intersect_preimage([[1.0, 0.0]], ss.Box([-5.0], [0.0]))
    p = part.area() / fat.area()
    assert np.mean(x[:, 0] <= 0.0) == pytest.approx(p, abs=0.12)


def _chords_compared(Z, rng, moves):
    """Every move's chord from the kept CZ chords against the generic 1-D program's."""
    kept = _chord_function(Z)
    assert isinstance(kept, _CZChords)
    x = Z.support_point(np.ones(Z.dim)) * 0.5 + Z.support_point(-np.ones(Z.dim)) * 0.5
    for _ in range(moves):
        d = rng.standard_normal(Z.dim)
        lo, hi = kept(x, d)
        ref_lo, ref_hi = kept.fallback(x, d)
        scale = 1.0 + abs(ref_lo) + abs(ref_hi)
        assert abs(lo - ref_lo) <= 1e-7 * scale and abs(hi - ref_hi) <= 1e-7 * scale
        x = x + rng.uniform(lo, hi) * d


@pytest.mark.parametrize("seed", range(3))
def test_kept_cz_chords_equal_the_generic_program_chords(seed):
    rng = np.random.default_rng(seed)
    n, ng, nc = 4, 9, 2
    G, A = rng.standard_normal((n, ng)), 0.3 * rng.standard_normal((nc, ng))
    h = np.ones(ng)
    Z = ss.ConstrainedZonotope(G, rng.standard_normal(n), A=A, b=np.zeros(nc), h=h)
    _chords_compared(Z, rng, 40)
    # A free factor pinned by a constraint, and sparse data at a large offset.
    h_free = h.copy()
    h_free[0] = np.inf
    A_free = A.copy()
    A_free[0, 0] = 1.0
    _chords_compared(ss.ConstrainedZonotope(G, np.zeros(n), A=A_free, b=np.zeros(nc), h=h_free), rng, 20)
    _chords_compared(ss.ConstrainedZonotope(sp.csc_matrix(G), 1e4 * np.ones(n), A=sp.csc_matrix(A),
                                            b=np.zeros(nc)), rng, 20)


def test_a_cz_chord_from_a_point_outside_is_the_generic_programs_stay():
    chord = _chord_function(PENTAGON)
    assert chord(np.array([50.0, 50.0]), np.array([1.0, 0.3])) == (0.0, 0.0)


def test_hit_and_run_on_a_set_without_a_cz_form_uses_the_program_chord():
    E = ss.Ellipsoid([1.0, -1.0], np.diag([4.0, 1.0]))
    assert not isinstance(_chord_function(E), _CZChords)
    x = hit_and_run(E, np.random.default_rng(3), 30, thin=2, burn_in=20)
    assert all(E.contains(p) for p in x)


def test_samplers_refuse_empty_flat_and_unknown_requests():
    rng = np.random.default_rng(6)
    with pytest.raises(ValueError, match="empty set"):
        uniform_sample(ss.ConstrainedZonotope(np.eye(1), [0], A=[[1.0]], b=[3.0]), rng)
    with pytest.raises(ValueError, match="no interior"):
        hit_and_run(ss.HPolytope([[1.0, -1.0], [-1.0, 1.0], [1.0, 0.0], [-1.0, 0.0]], [0, 0, 1, 1]), rng, 2)
    with pytest.raises(ValueError, match="method must be one of"):
        PENTAGON.sample(rng, 2, method="gibbs")
    with pytest.raises(ValueError, match="no exact sampler"):
        TRIANGLE.sample(rng, 2, method="exact")


@pytest.mark.parametrize("scale", [1.0, 1e-300, 1e-310, 1e300, 1e200, 0.0])
def test_the_single_row_basis_of_cz_vertices_is_independent_rows_answer(scale):
    """`cz_vertices` answers one finite non-zero row without a QR: as `linalg.independent_rows` does,
    down to the smallest normal norm, for zero, subnormal, huge (overflowing) and NaN rows alike."""
    from setsmooth.linalg import independent_rows
    from setsmooth.sets.cz_vertices import row_basis

    rng = np.random.default_rng(3)
    rows = [scale * rng.standard_normal((1, k)) for k in (1, 3, 9)]
    rows.append(np.array([[np.nan, 1.0]]))
    rows.append(np.array([[np.inf, 1.0]]))
    def answer(f, A, b):
        try:
            basis = f(A, b)
        except ValueError as exc:  # a NaN or infinite row: the QR refuses it, in both
            return str(exc)
        return basis.keep.tolist(), basis.consistent

    with np.errstate(over="ignore", invalid="ignore"):  # the norms of the huge rows overflow
        for A in rows:
            b = rng.standard_normal(1)
            assert answer(row_basis, A, b) == answer(independent_rows, A, b)


def test_the_row_basis_of_clearly_independent_rows_is_independent_rows_answer(monkeypatch):
    """`row_basis` answers several clearly independent rows without a QR, as `linalg.independent_rows`
    does; nearly dependent, dependent, zero and scaled rows give its answer too (through it or not)."""
    import setsmooth.sets.cz_vertices as czv
    from setsmooth.linalg import independent_rows

    rng = np.random.default_rng(5)
    cases = []
    for nc in (2, 3, 4, 5):
        for ng in (nc, nc + 3, 12, 40):
            A = rng.standard_normal((nc, ng))
            cases.append(A)
            cases.append(A * np.array([1e-200, 1.0, 1e150, 1e-3, 7.0])[:nc, None])
            for eps in (1e-2, 1e-4, 1e-6, 1e-9, 1e-12, 0.0):   # row 1 nearly a multiple of row 0
                B = A.copy()
                B[1] = -3.0 * A[0] + eps * rng.standard_normal(ng)
                cases.append(B)
            Z = A.copy()
            Z[-1] = 0.0
            cases.append(Z)

    def answer(f, A, b):
        basis = f(A, b)
        return basis.keep.tolist(), basis.consistent

    fast = 0
    for A in cases:
        for b in (rng.standard_normal(A.shape[0]), np.zeros(A.shape[0])):
            expected = answer(independent_rows, A, b)
            assert answer(czv.row_basis, A, b) == expected
            with monkeypatch.context() as m:
                m.setattr(czv, "independent_rows", lambda *a: None)
                try:
                    assert answer(czv.row_basis, A, b) == expected
                    fast += 1
                except AttributeError:   # went to the QR
                    pass
    assert fast >= 50   # most random rows, for both right-hand sides, took the fast answer


def test_cz_vertices_are_kept_on_the_set_read_only():
    """A second enumeration of the same set returns the first one's array (read-only), equal bit for
    bit to a fresh enumeration; a non-default ``max_candidates`` enumerates anew."""
    from setsmooth.sets.cz_vertices import cz_vertices, vertices_of

    rng = np.random.default_rng(11)
    for nc in (0, 1, 2):
        Z = ss.ConstrainedZonotope(rng.standard_normal((3, 6)), rng.standard_normal(3),
                                   A=rng.standard_normal((nc, 6)), b=0.1 * rng.standard_normal(nc))
        V = cz_vertices(Z)
        assert cz_vertices(Z) is V and not V.flags.writeable
        assert V.tobytes() == vertices_of(Z.G, Z.c, Z.A, Z.b, Z.h, 300_000).tobytes()
        assert cz_vertices(Z, max_candidates=10) is not V


def _reference_vertices(Z):
    """The enumeration as written before issue 29's changes (np.clip, every basis re-indexed, the QR
    row test), for the bit-for-bit comparison below."""
    from setsmooth import tolerances as tol
    from setsmooth.linalg import independent_rows
    from setsmooth.sets.cz_vertices import _bases, _signs

    h = np.asarray(Z.h, dtype=float)
    G, A = np.asarray(Z.G, dtype=float), np.asarray(Z.A, dtype=float)
    b, c = np.asarray(Z.b, dtype=float), np.asarray(Z.c, dtype=float)
    live = np.flatnonzero(h > 0)
    G, A, h = G[:, live], A[:, live], h[live]
    basis = independent_rows(A, b)
    if not basis.consistent:
        return np.zeros((0, c.size))
    A, b, G = A[basis.keep] * h, b[basis.keep], G * h
    norms = np.abs(A).max(axis=1, initial=0.0)
    A, b = A / norms[:, None], b / norms
    ng, nc = h.size, A.shape[0]
    if nc == 0:
        return c + _signs(ng) @ G.T
    slack = tol.VERTEX_FEASIBILITY_TOL * (1.0 + np.abs(b).max(initial=0.0))
    beta, rest = _bases(ng, nc)
    Ab = np.transpose(A[:, beta], (1, 0, 2))
    is_basis = np.abs(np.linalg.det(Ab)) > tol.RANK_TOL
    beta, rest, Ab = beta[is_basis], rest[is_basis], Ab[is_basis]
    if beta.shape[0] == 0:
        return np.zeros((0, c.size))
    S = _signs(ng - nc)
    rhs = b[None, :, None] - np.transpose(A[:, rest], (1, 0, 2)) @ S.T
    eta_beta = np.linalg.solve(Ab, rhs)
    ok = np.all(np.abs(eta_beta) <= 1.0 + slack, axis=1)
    basis_of, pattern = np.nonzero(ok)
    eta_b = np.clip(eta_beta[basis_of, :, pattern], -1.0, 1.0)
    Gb = np.transpose(G[:, beta], (1, 0, 2))
    Gr = np.transpose(G[:, rest], (1, 0, 2))
    return (c + np.einsum("pnc,pc->pn", Gb[basis_of], eta_b)
            + np.einsum("pnk,pk->pn", Gr[basis_of], S[pattern]))


@pytest.mark.parametrize("seed", range(12))
def test_cz_vertices_equal_their_first_version_bit_for_bit(seed):
    """Boxes and parallelotopes cut by strips (singular bases among the choices, as in LSUO), and
    random CZs with fixed factors and dependent rows: the same vertex array, bit for bit."""
    from setsmooth.sets.cz_vertices import vertices_of

    rng = np.random.default_rng(seed)
    n = 3
    C = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.5]])
    box = np.diag(rng.uniform(0.1, 1.0, n))
    par = rng.standard_normal((n, n))
    cases = []
    for G in (box, par):
        for rows in (C[:1], C):
            Gy = np.diag(rng.uniform(0.05, 0.5, rows.shape[0]))
            cases.append((np.hstack([G, np.zeros((n, len(rows)))]), rng.standard_normal(n),
                          np.hstack([rows @ G, -Gy]), 0.3 * rng.standard_normal(len(rows)),
                          np.ones(n + len(rows))))
    ng, nc = 9, int(rng.integers(1, 4))
    A = rng.standard_normal((nc, ng))
    if nc > 1 and seed % 3 == 0:
        A[-1] = -2.0 * A[0]
    h = rng.uniform(0.5, 1.5, ng)
    h[rng.random(ng) < 0.2] = 0.0
    cases.append((rng.standard_normal((n, ng)), rng.standard_normal(n), A,
                  A @ (0.5 * rng.uniform(-1, 1, ng) * h), h))
    for G, c, A, b, h in cases:
        Z = ss.ConstrainedZonotope(G, c, A=A, b=b, h=h)
        assert vertices_of(Z.G, Z.c, Z.A, Z.b, Z.h, 300_000).tobytes() == _reference_vertices(Z).tobytes()
