"""The closest point of a constrained zonotope (LSU paper, Method 2) on the fast path.

Oracles: brute force on the 2-D polygon (the closest point of a convex polygon to an outside point
lies on an edge: a bounded scalar minimization per edge), and the generic CVXPY path.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import setsmooth as ss
from setsmooth.solvers import closest

NORMS = [1, 2, np.inf]


def random_cz(rng, n=2, ng=5, nc=2):
    G, A = rng.standard_normal((n, ng)), rng.standard_normal((nc, ng))
    return ss.ConstrainedZonotope(G, rng.uniform(-1, 1, n), A=A, b=A @ rng.uniform(-0.6, 0.6, ng))


def polygon_distance(vertices, r, p):
    """min over the polygon's edges of ‖x − r‖_p (r outside the polygon)."""
    best = np.inf
    for a, b in zip(vertices, np.roll(vertices, -1, axis=0)):
        f = lambda t: np.linalg.norm(a + t * (b - a) - r, p)  # noqa: E731
        res = minimize_scalar(f, bounds=(0.0, 1.0), method="bounded",
                              options={"xatol": 1e-12})
        best = min(best, res.fun, f(0.0), f(1.0))
    return best


@pytest.mark.parametrize("p", NORMS)
def test_closest_point_of_a_2d_cz_matches_brute_force_and_the_generic_path(p):
    rng = np.random.default_rng(3)
    for _ in range(5):
        Z = random_cz(rng)
        vertices = Z.vertices_2d()
        r = Z.interval_hull().midpoint() + rng.uniform(2, 4, 2) * rng.choice([-1, 1], 2)
        x = Z.center("closest", reference=r, norm=p)
        assert Z.contains(x, tol=1e-7)
        exact = polygon_distance(vertices, r, p)
        assert np.linalg.norm(x - r, p) == pytest.approx(exact, rel=1e-6, abs=1e-9)
        generic = Z._generic.closest_point(r, p)
        assert np.linalg.norm(generic - r, p) == pytest.approx(exact, rel=1e-6, abs=1e-9)
        if p == 2:  # unique: the points themselves agree
            np.testing.assert_allclose(x, generic, atol=1e-6)


def test_a_reference_inside_the_set_is_its_own_closest_point():
    Z = random_cz(np.random.default_rng(5))
    inside = Z.support_point([1.0, 0.3]) * 0.5 + Z.support_point([-1.0, -0.3]) * 0.5
    for p in NORMS:
        np.testing.assert_allclose(Z.center("closest", reference=inside, norm=p), inside, atol=1e-6)


def test_an_empty_cz_has_no_closest_point():
    Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[3.0])  # |ξ| ≤ 1: empty
    for p in NORMS:
        assert np.isnan(Z.center("closest", reference=[0.0, 0.0], norm=p)).all()
    assert np.isnan(ss.EmptySet(2).center("closest", reference=[0.0, 0.0])).all()


def test_the_closest_point_does_not_depend_on_the_scaling_of_rows_and_factors():
    rng = np.random.default_rng(8)
    Z = random_cz(rng, n=3, ng=6, nc=2)
    f, rows = 10.0 ** rng.uniform(-8, 8, Z.ng), 10.0 ** rng.uniform(-8, 8, Z.nc)
    W = ss.ConstrainedZonotope(Z.G * f, Z.c, A=(Z.A * f) * rows[:, None], b=Z.b * rows, h=Z.h / f)
    r = np.array([3.0, -2.0, 1.0])
    np.testing.assert_allclose(W.center("closest", reference=r), Z.center("closest", reference=r),
                               atol=1e-6)


def test_free_factors_are_handled_exactly():
    # The strip {(s + ξ₃, s)}: ξ₁ = ξ₂ free, |ξ₃| ≤ 1; its closest point to (3, 0) in the 2-norm.
    Z = ss.ConstrainedZonotope([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0]], [0, 0],
                               A=[[1.0, -1.0, 0.0]], b=[0.0], h=[np.inf, np.inf, 1.0])
    x = Z.center("closest", reference=[3.0, 0.0])
    # The strip is |x₁ − x₂| ≤ 1: the projection of (3, 0) onto x₁ − x₂ = 1 is (2, 1).
    np.testing.assert_allclose(x, [2.0, 1.0], atol=1e-6)


def test_sets_without_a_cz_form_and_other_norms_use_the_generic_path():
    ball = ss.Ellipsoid([1.0, 0.0], 4.0 * np.eye(2))
    np.testing.assert_allclose(ball.center("closest", reference=[1.0, 5.0]), [1.0, 2.0], atol=1e-5)
    Z = random_cz(np.random.default_rng(2))
    r = np.array([5.0, 5.0])
    x3 = Z.center("closest", reference=r, norm=3)  # no fast program: generic
    assert Z.contains(x3, tol=1e-6)
    assert closest.fast_norm(3) is None and closest.fast_norm("inf") == np.inf
    assert np.linalg.norm(x3 - r, 3) <= np.linalg.norm(Z.center("closest", reference=r) - r, 3) + 1e-6
