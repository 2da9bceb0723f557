"""S ⊆ T against vertex enumeration: S ⊆ T (T convex) exactly when every vertex of S is in T,
decided here by scipy's halfspaces of T's hull (2-D and 3-D), independent of setsmooth."""

import itertools

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import setsmooth as ss
from setsmooth.sets.containment import zonotope_halfspaces
from tests.sets.test_oracles import cz_points, zonotope_points

SEEDS = range(12)


def oracle_subset(S_points, T_points, rel=1e-6):
    """conv(S_points) ⊆ conv(T_points) for full-dimensional T, by T's facet inequalities."""
    eq = ConvexHull(T_points).equations
    scale = np.abs(T_points).max()
    return bool(np.all(S_points @ eq[:, :-1].T + eq[:, -1] <= rel * scale))


def random_zonotope(rng, n, ng, spread=1.0):
    return ss.Zonotope(rng.standard_normal((n, ng)) * spread, rng.standard_normal(n) * 0.3)


def random_cz(rng, n=2, ng=4):
    while True:
        G, c = rng.standard_normal((n, ng)), rng.standard_normal(n) * 0.3
        A, b = rng.standard_normal((1, ng)), rng.uniform(-0.3, 0.3, 1)
        Z = ss.ConstrainedZonotope(G, c, A, b)
        if not Z.is_empty():
            return Z


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", [2, 3])
def test_zonotope_in_zonotope_is_decided_exactly(seed, n):
    rng = np.random.default_rng(seed)
    T = random_zonotope(rng, n, 5)
    S = random_zonotope(rng, n, 3, spread=rng.uniform(0.1, 0.8))
    answer = S.is_subset(T)
    assert answer.exact and answer.method == "zonotope facets"
    assert bool(answer) == oracle_subset(zonotope_points(S.G, S.c), zonotope_points(T.G, T.c))
    # the answer agrees with the violation it reports
    assert (answer.violation <= 1e-9) == bool(answer) or abs(answer.violation) < 1e-6


@pytest.mark.parametrize("seed", SEEDS)
def test_cz_in_box_and_hpolytope_is_exact_and_certified_when_contained(seed):
    rng = np.random.default_rng(seed)
    S = random_cz(rng)
    pts = cz_points(S.G, S.c, S.A, S.b, S.h)
    T_pts = rng.standard_normal((7, 2)) * rng.uniform(2.0, 6.0)
    eq = ConvexHull(T_pts).equations
    P = ss.HPolytope(eq[:, :-1], -eq[:, -1])
    answer = S.is_subset(P)
    assert answer.exact and bool(answer) == oracle_subset(pts, T_pts)
    if answer:
        assert answer.certified
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    assert S <= ss.Box(lo - 1e-6, hi + 1e-6)
    shrunk = S.is_subset(ss.Box(lo + 0.01 * (hi - lo), hi))
    assert not shrunk and shrunk.exact and shrunk.violation > 0


@pytest.mark.parametrize("seed", SEEDS)
def test_the_sufficient_cz_test_never_claims_a_false_containment(seed):
    rng = np.random.default_rng(seed)
    T = random_cz(rng, ng=5)
    T_pts = cz_points(T.G, T.c, T.A, T.b, T.h)
    centre = T_pts.mean(axis=0)
    # a shrunken copy of T about a member (contained), and a random CZ (usually not)
    inner = 0.6 * np.eye(2) @ (T - centre) + centre
    for S in (inner, random_cz(rng)):
        answer = S.is_subset(T)
        truth = oracle_subset(cz_points(S.G, S.c, S.A, S.b, S.h), T_pts)
        if answer:
            assert truth and not answer.exact
        elif answer.exact:
            assert not truth  # refuted exactly only when S leaves T's interval hull
    assert inner.is_subset(T), "the shrunken copy maps factor to factor: the sufficient test finds it"


def test_a_set_is_contained_in_itself_under_each_test():
    rng = np.random.default_rng(4)
    Z = random_zonotope(rng, 3, 6)
    C = random_cz(rng, n=3, ng=6)
    assert Z.is_subset(Z) and Z.is_subset(Z).exact
    assert C.is_subset(C) and not C.is_subset(C).exact  # sufficient: Γ = I
    H = ss.Box([-1, -2], [1, 2]).to_hpolytope()
    assert H <= H and ss.Box([-1, -2], [1, 2]) >= H


def test_empty_and_unbounded_operands():
    box = ss.Box([0, 0], [1, 1])
    assert ss.EmptySet(2) <= box and not box <= ss.EmptySet(2)
    assert box <= ss.Reals(2) and not ss.Reals(2).is_subset(box)
    assert not ss.HPolytope([[1.0, 0.0]], [0.5]).is_subset(box)


def test_degenerate_zonotopes_have_exact_facets_in_their_affine_hull():
    flat = ss.Zonotope([[1.0, 0.5], [1.0, 0.5], [0.0, 1.0]], [0, 0, 0])  # a 2-D parallelogram in ℝ³
    H, k = zonotope_halfspaces(np.asarray(flat.G), np.asarray(flat.c))
    for xi in itertools.product([-1.0, 1.0], repeat=2):
        assert np.all(H @ (flat.G @ np.array(xi)) <= k + 1e-12)
    assert ss.Zonotope(0.5 * np.asarray(flat.G), [0, 0, 0]) <= flat
    off_plane = ss.Zonotope(0.5 * np.asarray(flat.G), [0.0, 1e-3, 0.0])
    answer = off_plane.is_subset(flat)
    assert not answer and answer.exact


def test_containment_of_sets_without_a_test_is_refused_clearly():
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2))
    with pytest.raises(TypeError, match="Ellipsoid is none of these"):
        ss.Box([0, 0], [0.1, 0.1]).is_subset(E)
    cz = ss.Box([-1, -1], [1, 1]).to_constrained_zonotope() & ss.Zonotope([[1.0, 1.0], [0.0, 1.0]], [0, 0])
    with pytest.raises(TypeError, match="Ellipsoid does not"):
        E.is_subset(cz)
    assert (E <= ss.Box([-1, -1], [1, 1])) and not (E <= ss.Box([-0.9, -1], [1, 1]))
    with pytest.raises(ValueError, match="equal dimension"):
        E.is_subset(ss.Box([0], [1]))
