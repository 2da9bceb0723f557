"""Operators widen to the most specific type closed under the operation (see sets/algebra.py)."""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss

BOX = ss.Box([0.0, 0.0], [1.0, 2.0])
HALF = ss.Box([-np.inf, 0.0], [0.0, 1.0])  # a half-line: no CZ form
FREE = ss.Box([-np.inf, 0.0], [np.inf, 1.0])  # a free coordinate: a CZ with h = ∞
ZONO = ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.0, 0.0])
CZ = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[0.5])
POLY = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
ELL = ss.Ellipsoid([0.0, 0.0], np.eye(2))
REALS = ss.Reals(2)
M = np.array([[1.0, 2.0], [0.0, 1.0]])
R = np.array([[1.0, 1.0]])
Y = ss.Box([0.0], [1.0])

CASES = [
    # Minkowski sums
    ("Box + Box", lambda: BOX + BOX, ss.Box),
    ("Box + Zonotope", lambda: BOX + ZONO, ss.Zonotope),
    ("Zonotope + Box", lambda: ZONO + BOX, ss.Zonotope),
    ("Zonotope + Zonotope", lambda: ZONO + ZONO, ss.Zonotope),
    ("Zonotope + CZ", lambda: ZONO + CZ, ss.ConstrainedZonotope),
    ("Box + Reals", lambda: BOX + REALS, ss.ConstrainedZonotope),
    ("free Box + Zonotope", lambda: FREE + ZONO, ss.ConstrainedZonotope),
    ("half-line Box + Zonotope", lambda: HALF + ZONO, ss.MinkowskiSum),
    ("Ellipsoid + Zonotope", lambda: ELL + ZONO, ss.MinkowskiSum),
    ("HPolytope + Box", lambda: POLY + BOX, ss.MinkowskiSum),
    ("Box - Box", lambda: BOX - BOX, ss.Zonotope),
    # linear maps and translations
    ("M @ Box", lambda: M @ BOX, ss.Zonotope),
    ("M @ Zonotope", lambda: M @ ZONO, ss.Zonotope),
    ("M @ CZ", lambda: M @ CZ, ss.ConstrainedZonotope),
    ("M @ Reals", lambda: M @ REALS, ss.ConstrainedZonotope),
    ("M @ free Box", lambda: M @ FREE, ss.ConstrainedZonotope),
    ("M @ Ellipsoid", lambda: M @ ELL, ss.Ellipsoid),
    ("M @ HPolytope", lambda: M @ POLY, ss.LinearMap),
    ("M @ half-line Box", lambda: M @ HALF, ss.LinearMap),
    ("list @ Box", lambda: [[1.0, 0.0]] @ BOX, ss.Zonotope),
    ("-Box", lambda: -BOX, ss.Zonotope),
    ("Box + v", lambda: BOX + np.ones(2), ss.Box),
    ("v + Box", lambda: np.ones(2) + BOX, ss.Box),
    ("Zonotope + v", lambda: ZONO + np.ones(2), ss.Zonotope),
    ("CZ + v", lambda: CZ + np.ones(2), ss.ConstrainedZonotope),
    ("Ellipsoid + v", lambda: ELL + np.ones(2), ss.Ellipsoid),
    ("HPolytope + v", lambda: POLY + np.ones(2), ss.HPolytope),
    ("Intersection + v", lambda: (ELL & POLY) + np.ones(2), ss.LinearMap),
    # intersections
    ("Box & Box", lambda: BOX & BOX, ss.Box),
    ("Box & Zonotope", lambda: BOX & ZONO, ss.ConstrainedZonotope),
    ("CZ & Box", lambda: CZ & BOX, ss.ConstrainedZonotope),
    ("Zonotope & Zonotope", lambda: ZONO & ZONO, ss.ConstrainedZonotope),
    ("HPolytope & Box", lambda: POLY & BOX, ss.HPolytope),
    ("Box & HPolytope", lambda: BOX & POLY, ss.HPolytope),
    ("half-line Box & HPolytope", lambda: HALF & POLY, ss.HPolytope),
    ("HPolytope & HPolytope", lambda: POLY & POLY, ss.HPolytope),
    ("HPolytope & Zonotope", lambda: POLY & ZONO, ss.Intersection),
    ("Ellipsoid & Box", lambda: ELL & BOX, ss.Intersection),
    ("Reals & CZ", lambda: REALS & CZ, ss.ConstrainedZonotope),
    # generalized intersections and preimages
    ("CZ ∩_R Box", lambda: CZ.intersect_preimage(R, Y), ss.ConstrainedZonotope),
    ("Zonotope ∩_R Box", lambda: ZONO.intersect_preimage(R, Y), ss.ConstrainedZonotope),
    ("HPolytope ∩_R Box", lambda: POLY.intersect_preimage(R, Y), ss.HPolytope),
    ("Ellipsoid ∩_R Box", lambda: ELL.intersect_preimage(R, Y), ss.GeneralizedIntersection),
    ("Box ∩_R Ellipsoid", lambda: BOX.intersect_preimage(R, ss.Ellipsoid([0.0], [[1.0]])),
     ss.GeneralizedIntersection),
    ("Box.preimage", lambda: BOX.preimage(M), ss.ConstrainedZonotope),
    ("Zonotope.preimage(singular)", lambda: ZONO.preimage([[1.0, 1.0], [1.0, 1.0]]),
     ss.ConstrainedZonotope),
    ("HPolytope.preimage", lambda: POLY.preimage(M), ss.HPolytope),
    ("Reals ∩_R HPolytope", lambda: REALS.intersect_preimage(M, POLY), ss.HPolytope),
    ("Box ∩_R HPolytope", lambda: BOX.intersect_preimage([[1.0, 1.0]], ss.HPolytope([[1.0], [-1.0]], [1.0, 0.0])),
     ss.HPolytope),
    # products
    ("Box * Box", lambda: BOX * BOX, ss.Box),
    ("Box * Zonotope", lambda: BOX * ZONO, ss.Zonotope),
    ("Zonotope * Box", lambda: ZONO * BOX, ss.Zonotope),
    ("CZ * Box", lambda: CZ * BOX, ss.ConstrainedZonotope),
    ("HPolytope * HPolytope", lambda: POLY * POLY, ss.HPolytope),
    ("HPolytope * Box", lambda: POLY * BOX, ss.HPolytope),
    ("Box * HPolytope", lambda: BOX * POLY, ss.HPolytope),
    ("Ellipsoid * Box", lambda: ELL * BOX, ss.CartesianProduct),
    # projections
    ("Box.project", lambda: BOX.project([1]), ss.Box),
    ("Zonotope.project", lambda: ZONO.project([1]), ss.Zonotope),
    ("CZ.project", lambda: CZ.project([1]), ss.ConstrainedZonotope),
    ("Ellipsoid.project", lambda: ELL.project([1]), ss.Ellipsoid),
    ("HPolytope.project", lambda: POLY.project([1]), ss.LinearMap),
    ("Reals.project", lambda: REALS.project([1]), ss.ConstrainedZonotope),
]


@pytest.mark.parametrize("name, build, expected", CASES, ids=[c[0] for c in CASES])
def test_operation_widens_to_the_most_specific_closed_type(name, build, expected):
    assert type(build()) is expected


@pytest.mark.parametrize("name, build, expected", CASES, ids=[c[0] for c in CASES])
def test_widened_result_agrees_with_its_generic_program(name, build, expected):
    S = build()
    D = np.random.default_rng(0).standard_normal((4, S.dim))
    auto, generic = S.support_many(D), S.support_many(D, path="generic")
    assert np.array_equal(np.isinf(auto), np.isinf(generic))
    finite = np.isfinite(auto)
    np.testing.assert_allclose(auto[finite], generic[finite],
                               atol=1e-6 * (1 + np.abs(auto[finite]).max(initial=0)))


def test_a_map_of_reals_is_not_reals_but_a_cz():
    S = M @ REALS
    assert type(S) is ss.ConstrainedZonotope and not isinstance(S, ss.Reals)
