"""`Polygon` against exact rational geometry (`polygon_reference`) and the generic CVXPY path.

Each closed form must return a polygon that contains the exact result of the operation on the
stored floats (support values ≥ the rational optimum, checked as Fractions) and exceeds it only by
rounding (≤ 1e-9 of the set's magnitude along the direction). Random polygons and matrices come
from hypothesis-seeded generators and include singular and badly scaled (1e±6) matrices, points far
from the origin and half-planes nearly parallel to an edge.
"""

from __future__ import annotations

import pickle
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import setsmooth as ss
from setsmooth.sets import _polygon_geometry as geo
from setsmooth.sets.algebra import linear_map
from setsmooth.sets.polygon import Polygon

from . import polygon_reference as ref

REL = 1e-9
ANGLES = np.linspace(0, 2 * np.pi, 24, endpoint=False) + 0.0123
DIRECTIONS = np.vstack([np.eye(2), -np.eye(2), np.column_stack([np.cos(ANGLES), np.sin(ANGLES)])])

seeds = st.integers(0, 2**32 - 1)


def assert_tight_outer(P, exact: list, directions: np.ndarray = DIRECTIONS, rel: float = REL) -> None:
    """P ⊇ conv(exact) (as Fractions) and h_P(d) − h_exact(d) ≤ rel·‖d‖₂·max_p ‖p‖₂ for every d.

    The excess is measured against the set's magnitude, not its extent along d: the pad is a
    Euclidean ball, so a set thinned by a badly scaled map (widths 1e6 and 1e-6) keeps the rounding of
    its long side in its short side too."""
    assert isinstance(P, Polygon), type(P)
    assert ref.is_strictly_convex_ccw(ref.exact_points(P.vertices))
    values = P.support_many(directions, certified=True)
    for d, value in zip(directions, values):
        exact_value = ref.support(exact, d)
        assert Fraction(float(value)) >= exact_value, (d, value, float(exact_value))
        scale = float(np.linalg.norm(d)) * max(float(np.hypot(float(p[0]), float(p[1]))) for p in exact) + 1e-300
        assert value - float(exact_value) <= rel * scale + 1e-280, (d, value - float(exact_value), scale)


def random_points(rng: np.random.Generator, k: int | None = None) -> np.ndarray:
    k = int(rng.integers(1, 10)) if k is None else k
    scale = 10.0 ** rng.uniform(-6, 6)
    offset = rng.standard_normal(2) * scale * rng.choice([0.0, 1.0, 100.0])
    return rng.standard_normal((k, 2)) * scale + offset


def random_matrix(rng: np.random.Generator) -> np.ndarray:
    kind = rng.integers(0, 5)
    M = rng.standard_normal((2, 2))
    if kind == 1:
        return np.outer(rng.standard_normal(2), rng.standard_normal(2))      # rank 1
    if kind == 2:
        return np.zeros((2, 2)) if rng.random() < 0.3 else np.diag([1e6, 1e-6]) @ M
    if kind == 3:
        return M * 10.0 ** rng.uniform(-6, 6)
    return M


# -- construction and conversions -------------------------------------------------------------------

@settings(max_examples=60, deadline=None)
@given(seeds)
def test_polygon_of_points_is_their_exact_hull(seed):
    points = random_points(np.random.default_rng(seed))
    P = Polygon(points)
    assert_tight_outer(P, ref.hull(ref.exact_points(points)))


def test_nearly_collinear_points_dropped_by_the_hull_are_charged_to_the_pad():
    t = np.linspace(0.0, 1.0, 7)
    points = np.column_stack([1e3 + t, 1e3 + t * (1 + 1e-15)])  # collinear up to rounding
    points = np.vstack([points, [[1e3 + 0.5, 1e3 + 0.5 + 3e-14]]])
    P = Polygon(points)
    assert_tight_outer(P, ref.hull(ref.exact_points(points)))


@settings(max_examples=40, deadline=None)
@given(seeds)
def test_zonotope_polygon_contains_every_sign_vertex_exactly(seed):
    rng = np.random.default_rng(seed)
    ng = int(rng.integers(1, 6))
    G, c = random_points(rng, ng).T, random_points(rng, 1)[0]
    Z = ss.Zonotope(G, c)
    exact = [(Fraction(float(c[0])) + sum(s[j] * Fraction(float(G[0, j])) for j in range(ng)),
              Fraction(float(c[1])) + sum(s[j] * Fraction(float(G[1, j])) for j in range(ng)))
             for s in np.array(np.meshgrid(*[[-1, 1]] * ng)).T.reshape(-1, ng).tolist()]
    assert_tight_outer(Polygon.from_set(Z), ref.hull(exact))


def test_box_and_vpolytope_convert_exactly_and_other_sets_are_refused():
    B = ss.Box([-1.0, 2.0], [3.0, 2.5])
    P = Polygon.from_set(B)
    assert P.pad == 0 and len(P.vertices) == 4
    hull = P.interval_hull(certified=True)
    assert np.all(hull.lo <= B.lo) and np.all(hull.hi >= B.hi)
    np.testing.assert_allclose(np.r_[hull.lo, hull.hi], np.r_[B.lo, B.hi], rtol=1e-15)
    assert_tight_outer(Polygon.from_set(ss.VPolytope([[0, 0], [1, 0], [0, 1], [0.2, 0.2]])),
                       ref.hull(ref.exact_points([[0, 0], [1, 0], [0, 1]])))
    with pytest.raises(TypeError, match="no polygon closed form"):
        Polygon.from_set(ss.Ellipsoid([0.0, 0.0], np.eye(2)))
    with pytest.raises(TypeError, match="no polygon closed form"):
        Polygon.from_set(ss.Box([0, 0, 0], [1, 1, 1]))


def test_invalid_arguments_are_refused_at_the_door():
    with pytest.raises(ValueError, match="at least one point"):
        Polygon(np.zeros((0, 2)))
    with pytest.raises(ValueError, match="pad"):
        Polygon([[0.0, 0.0]], pad=-1.0)
    with pytest.raises(ValueError):
        Polygon([[0.0, 0.0, 0.0]])


# -- closed-form algebra against exact rational results -------------------------------------------

@settings(max_examples=80, deadline=None)
@given(seeds)
def test_linear_map_encloses_the_exact_image_also_for_singular_and_badly_scaled_maps(seed):
    rng = np.random.default_rng(seed)
    points, M = random_points(rng), random_matrix(rng)
    P = Polygon(points)
    image = M @ P
    assert_tight_outer(image, ref.linear_map(M, ref.exact_points(P.vertices)))


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_minkowski_sum_encloses_the_exact_sum(seed):
    rng = np.random.default_rng(seed)
    P, Q = Polygon(random_points(rng)), Polygon(random_points(rng))
    assert_tight_outer(P + Q, ref.minkowski_sum(*(ref.exact_points(S.vertices) for S in (P, Q))))


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_sums_with_boxes_and_zonotopes_are_polygons(seed):
    rng = np.random.default_rng(seed)
    P = Polygon(random_points(rng))
    lo = random_points(rng, 1)[0]
    B = ss.Box(lo, lo + np.abs(random_points(rng, 1)[0]))
    for other in (B, ss.Zonotope(random_points(rng, 2).T, random_points(rng, 1)[0])):
        exact_other = ref.exact_points(Polygon.from_set(other).vertices) if isinstance(other, ss.Box) else None
        for S in (P + other, other + P):
            assert isinstance(S, Polygon)
        if exact_other is not None:  # a box's corners are exact
            assert_tight_outer(other + P, ref.minkowski_sum(ref.exact_points(P.vertices), exact_other))


@settings(max_examples=80, deadline=None)
@given(seeds)
def test_intersection_with_half_planes_encloses_the_exact_cut(seed):
    rng = np.random.default_rng(seed)
    P = Polygon(random_points(rng, int(rng.integers(3, 10))))
    center = P.vertices.mean(axis=0)
    N = rng.standard_normal((3, 2))
    h = N @ center + np.abs(N) @ np.ptp(P.vertices, axis=0) * rng.uniform(-0.2, 0.4, 3)
    cut = P & ss.HPolytope(N, h)
    exact = ref.preimage_cut(ref.exact_points(P.vertices), np.eye(2), N, h)
    if not exact:
        assert isinstance(cut, ss.EmptySet) or cut.pad >= 0  # emptiness only when certain
        return
    assert_tight_outer(cut, exact, rel=1e-8)


@pytest.mark.parametrize("tilt", [0.0, 1e-15, 1e-12, -1e-13, 1e-9])
def test_a_half_plane_nearly_parallel_to_an_edge_cuts_soundly(tilt):
    P = Polygon([[1e4, 1e4], [1e4 + 3.0, 1e4 + 1.0], [1e4 + 1.0, 1e4 + 4.0]])
    edge = P.vertices[1] - P.vertices[0]
    a = np.array([edge[1], -edge[0]])                           # outward normal of the first edge
    a = np.array([[np.cos(tilt), -np.sin(tilt)], [np.sin(tilt), np.cos(tilt)]]) @ a
    for depth in (0.0, 1e-13, 0.3):
        h = float(a @ P.vertices[0]) - depth * np.linalg.norm(a)
        cut = P & ss.HPolytope(a[None, :], [h])
        exact = ref.clip(ref.exact_points(P.vertices), tuple(Fraction(float(v)) for v in a), Fraction(h))
        assert exact and isinstance(cut, Polygon)
        assert_tight_outer(cut, exact, rel=1e-8)


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_preimage_of_a_box_of_higher_dimension_encloses_the_exact_cut(seed):
    rng = np.random.default_rng(seed)
    P = Polygon(random_points(rng, int(rng.integers(3, 9))))
    R = rng.standard_normal((3, 2))
    inner = R @ P.vertices[int(rng.integers(len(P.vertices)))]
    Y = ss.Box(inner - rng.uniform(0, 1, 3) * np.abs(inner).max(), inner + rng.uniform(0, 1, 3) * np.abs(inner).max())
    cut = P.intersect_preimage(R, Y)
    H = Y.to_hpolytope()
    assert_tight_outer(cut, ref.preimage_cut(ref.exact_points(P.vertices), R, H.H, H.k), rel=1e-8)


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_preimage_of_a_polygon_encloses_the_exact_cut(seed):
    rng = np.random.default_rng(seed)
    P = Polygon(random_points(rng, 6))
    # Well conditioned: through a nearly singular R a rounding-level pad of Y pulls back to lengths
    # ~ pad/σ_min, as it would for any representation. Y is spread around the image of a vertex
    # of P, so the cut is (almost always) non-empty.
    R = np.eye(2) * 3 + rng.standard_normal((2, 2))
    spread = np.ptp(P.vertices, axis=0).max() + 1e-3 * np.abs(P.vertices).max()
    Y = Polygon(R @ P.vertices[0] + rng.standard_normal((6, 2)) * spread * 3)
    exact_y = ref.exact_points(Y.vertices)
    cut = P.intersect_preimage(R, Y)
    hull_y = ref.hull(exact_y)
    exact = ref.exact_points(P.vertices)
    if len(hull_y) >= 3:  # the exact edge half-planes of Y, rows formed exactly
        Rf = [[Fraction(float(v)) for v in row] for row in R]
        for i in range(len(hull_y)):
            (x0, y0), (x1, y1) = hull_y[i], hull_y[(i + 1) % len(hull_y)]
            n = (y1 - y0, x0 - x1)
            a = (n[0] * Rf[0][0] + n[1] * Rf[1][0], n[0] * Rf[0][1] + n[1] * Rf[1][1])
            exact = ref.clip(exact, a, n[0] * x0 + n[1] * y0)
        if not exact:  # Y's shifted vertex missed R P by rounding: ours may keep a rounding-size sliver
            assert isinstance(cut, ss.EmptySet) or cut.diameter() <= 1e-9 * np.abs(P.vertices).max()
            return
        assert_tight_outer(cut, exact, rel=1e-8)


def test_preimage_of_a_polygon_agrees_with_the_generic_cvxpy_path():
    rng = np.random.default_rng(7)
    P, Y = Polygon(rng.standard_normal((7, 2)) * 3), Polygon(rng.standard_normal((6, 2)) * 2)
    R = np.array([[0.8, -0.4], [0.3, 1.1]])
    cut = P.intersect_preimage(R, Y)
    lazy = ss.GeneralizedIntersection(ss.VPolytope(P.vertices), R, ss.VPolytope(Y.vertices))
    ours, generic = cut.support_many(DIRECTIONS), lazy.support_many(DIRECTIONS, path="generic")
    np.testing.assert_allclose(ours, generic, atol=1e-6 * (1 + np.abs(generic).max()))
    assert np.all(ours >= generic - 1e-6 * (1 + np.abs(generic).max()))


def test_a_polygon_queried_on_the_generic_path_is_the_same_set():
    P = Polygon([[0.0, 0.0], [2.0, 0.1], [1.5, 1.8], [-0.3, 1.0]], pad=0.05)
    generic = P.support_many(DIRECTIONS, path="generic")
    np.testing.assert_allclose(P.support_many(DIRECTIONS), generic, atol=1e-6)


def test_emptiness_is_declared_only_when_certain():
    P = Polygon([[1.0, 1.0], [2.0, 1.0], [1.0, 3.0]])
    touching = P & ss.HPolytope([[1.0, 1.0]], [2.0])              # exactly the vertex (1, 1)
    assert isinstance(touching, Polygon)
    assert_tight_outer(touching, [(Fraction(1), Fraction(1))], rel=1e-12)
    assert isinstance(P & ss.HPolytope([[1.0, 1.0]], [1.9]), ss.EmptySet)
    assert isinstance(P & ss.Box([5.0, 5.0], [6.0, 6.0]), ss.EmptySet)


def test_algebra_widens_to_polygons_and_falls_back_without_a_closed_form():
    P = Polygon([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    B = ss.Box([-1.0, -1.0], [1.0, 1.0])
    for S in (P + B, B + P, P & B, B & P, np.array([[1.0, 2.0], [0.0, 1.0]]) @ P, P + [1.0, 2.0],
              B.intersect_preimage(np.eye(2), P), P.intersect_preimage(np.ones((1, 2)), ss.Box([0.0], [0.5]))):
        assert isinstance(S, Polygon), type(S)
    lifted = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]) @ P       # 3-D: no polygon form, lazy
    assert not isinstance(lifted, Polygon)
    np.testing.assert_allclose(lifted.support([0.0, 0.0, 1.0], path="generic"), 1.0, atol=1e-6)
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2))
    assert not isinstance(P & E, Polygon)


def test_a_polygon_pickles_and_stays_immutable():
    P = ss.Polygon([[0.0, 0.0], [2.0, 0.5], [0.5, 2.0]], pad=1e-3)
    P.interval_hull(certified=True)
    again = pickle.loads(pickle.dumps(P))
    np.testing.assert_array_equal(again.vertices, P.vertices)
    assert again.pad == P.pad and not again.vertices.flags.writeable
    np.testing.assert_array_equal(again.support_many(DIRECTIONS), P.support_many(DIRECTIONS))
    Z = ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.0, 0.0])
    Z + P  # keeps Z's polygon form on Z, which is not shipped with it
    assert "_polygon_form" in Z.__dict__ and "_polygon_form" not in pickle.loads(pickle.dumps(Z)).__dict__


def test_the_oracle_catches_a_cut_that_is_too_deep(monkeypatch):
    """The checks can fail: a clip whose offset is lowered by 1e-9 of the set's size is refused."""
    rng = np.random.default_rng(3)
    P = Polygon(rng.standard_normal((8, 2)))
    a, h = np.array([0.6, 0.8]), 0.1
    exact = ref.clip(ref.exact_points(P.vertices), (Fraction(0.6), Fraction(0.8)), Fraction(h))
    assert_tight_outer(P & ss.HPolytope(a[None, :], [h]), exact)
    clip = geo.clip
    monkeypatch.setattr(geo, "clip", lambda H, a, h: clip(H, a, h - 1e-9))
    with pytest.raises(AssertionError):
        assert_tight_outer(P & ss.HPolytope(a[None, :], [h]), exact)


def test_spectral_norm_bound_is_an_upper_bound_and_tight():
    rng = np.random.default_rng(0)
    for M in [np.eye(2), np.array([[np.sin(1), np.cos(1)], [-np.cos(1), np.sin(1)]]),
              *(random_matrix(rng) for _ in range(200))]:
        exact = np.linalg.norm(M, 2)
        bound = geo.spectral_norm_bound(M)
        assert bound >= exact and bound <= exact * (1 + 1e-6) + 1e-280


def test_a_chain_is_certified_only_when_it_is_a_convex_counter_clockwise_polygon():
    angles = 2 * np.pi * np.arange(5) / 5
    pentagon = np.column_stack([np.cos(angles), np.sin(angles)])
    assert geo.is_certified_chain(pentagon)
    assert not geo.is_certified_chain(pentagon[::-1])                  # clockwise
    assert not geo.is_certified_chain(pentagon[[0, 2, 4, 1, 3]])       # a pentagram: left turns, winds twice
    assert not geo.is_certified_chain(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]]))  # collinear


@pytest.mark.parametrize("angle", [0.0, 1e-17, 1e-15, 3e-13, np.pi - 1e-16])
def test_zonotope_with_nearly_parallel_generators_is_enclosed(angle):
    G = np.array([[1.0, np.cos(angle) * 2.0, 0.3], [0.0, np.sin(angle) * 2.0, 0.7]]) * 1e3
    c = np.array([5e3, -2e3])
    exact = [(Fraction(float(c[0])) + sum(s * Fraction(float(g)) for s, g in zip(signs, G[0])),
              Fraction(float(c[1])) + sum(s * Fraction(float(g)) for s, g in zip(signs, G[1])))
             for signs in np.array(np.meshgrid(*[[-1, 1]] * 3)).T.reshape(-1, 3).tolist()]
    assert_tight_outer(Polygon.from_set(ss.Zonotope(G, c)), ref.hull(exact))


# -- regressions from the adversarial review ----------------------------------------------------------
def test_a_needle_keeps_its_tip():
    """At a needle's tip the turn is a hairpin, as uncertifiable as a straight turn: the hull step
    dropped the tip itself and charged its distance (1.9) to the pad. Now the point between the
    other two is dropped, which is the needle's middle point, never an end."""
    pts = np.array([[1.1710095898981792, -6.803189504413681], [1.6334268182736131, -8.672457946520598],
                    [-1.7910849580590829, 5.170736900720171]])
    P = Polygon(pts)
    assert P.pad <= 1e-12
    assert_tight_outer(P, ref.exact_points(pts))


def test_a_fat_polygon_keeps_a_vertex_at_a_nearly_straight_turn():
    pts = np.array([[0.0, 0.0], [1e-17, -1.0], [1e-17, 1.0], [5.0, 0.0]])
    P = Polygon(pts)
    assert P.pad <= 1e-12
    assert_tight_outer(P, ref.exact_points(pts))


def test_the_rounding_of_the_noise_image_is_charged():
    """B W computed in floating point (fl(B c) with cancellation) was taken as exact: a point noise
    set whose exact image is (-3.0e-18, 9.7e-18) got certified hulls at (4.6e-19, 1.5e-17)."""
    B = np.array([[0.10490011715303971, -0.535669373161111, -0.13109099775757493],
                  [1.3040000451301372, 0.9470809631292422, -0.0606446583254687]])
    w = np.array([0.1257302210933933, -0.1321048632913019, 0.6404226504432821])
    system = ss.LinearSystem(np.eye(2), None, np.eye(2), E=B, W=ss.Box(w, w),
                             V=ss.Box([-10.0, -10.0], [10.0, 10.0]))
    P = ss.classical_filter(system, ss.Box([0.0, 0.0], [0.0, 0.0]), np.zeros((2, 2)), form="polygon")[1]
    exact = [sum(Fraction(float(b)) * Fraction(float(x)) for b, x in zip(row, w)) for row in B]
    hull = P.interval_hull(certified=True)
    for i in range(2):
        assert Fraction(float(hull.hi[i])) >= exact[i] and Fraction(float(hull.lo[i])) <= exact[i]
        assert hull.hi[i] - hull.lo[i] <= 1e-14


@pytest.mark.parametrize("scale", [1e-100, 1e160])
def test_the_spectral_norm_bound_neither_underflows_nor_overflows(scale):
    M = scale * np.array([[1.0, 1.0], [1.0, 1.0]])
    bound = geo.spectral_norm_bound(M)
    assert np.isfinite(bound) and bound >= 2 * scale
    P = linear_map(M, Polygon(np.array([[0.0, 0.0]]), pad=1.0))
    assert np.isfinite(P.pad) and P.pad >= 2 * scale * (1 - 1e-15)


def test_tiny_polygons_and_directions_do_not_underflow():
    P = Polygon(np.array([[0.0, 0.0], [1e-200, 0.0], [0.0, 1e-200]]))
    assert P.support([0.0, 1.0], certified=True) >= 1e-200
    assert Polygon(np.array([[0.0, 0.0]]), pad=1.0).support([1e-170, 0.0], certified=True) >= 1e-170


@pytest.mark.parametrize("vertices, pad, name", [([1.0, 2.0], 0.0, "vertices"), ([[0.0, 0.0]], "x", "pad"),
                                                 ([[0.0, 0.0]], [1.0, 2.0], "pad"),
                                                 ([[0.0, 0.0]], -1.0, "pad")])
def test_bad_polygon_input_names_the_argument(vertices, pad, name):
    with pytest.raises((TypeError, ValueError), match=name):
        Polygon(vertices, pad=pad)
