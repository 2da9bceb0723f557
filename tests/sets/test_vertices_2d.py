"""Exact polygons of 2-D sets (`vertices_2d`, `area`) and plotting."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.sets.vertices_2d import polygon_area, vertices_2d  # noqa: E402


def signed_area(v):
    x, y = v[:, 0], v[:, 1]
    return (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2


def same_vertices(a, b, atol=1e-7):
    assert len(a) == len(b)
    for p in b:
        assert np.min(np.linalg.norm(a - p, axis=1)) <= atol


def test_vertices_of_a_box_are_its_four_corners_counter_clockwise():
    v = ss.Box([0, 0], [2, 1]).vertices_2d()
    same_vertices(v, np.array([[0, 0], [2, 0], [2, 1], [0, 1]]))
    assert signed_area(v) == pytest.approx(2.0)


def test_vertices_of_a_triangle_given_by_halfspaces():
    P = ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [1.0, 0.0, 0.0])
    same_vertices(P.vertices_2d(), np.array([[0, 0], [1, 0], [0, 1]]))


def test_collinear_support_points_are_dropped():
    # A zonotope with parallel generators is a parallelogram with 4 vertices, not 6.
    Z = ss.Zonotope([[1.0, 2.0, 0.0], [0.0, 0.0, 1.0]], [0.0, 0.0])
    same_vertices(Z.vertices_2d(), np.array([[-3, -1], [3, -1], [3, 1], [-3, 1]]))
    assert Z.area() == pytest.approx(12.0)


def test_a_point_and_a_segment_have_one_and_two_vertices_and_no_area():
    point = ss.Zonotope(np.zeros((2, 0)), [1.0, 1.0])
    segment = ss.Zonotope([[1.0], [1.0]], [0.0, 0.0])
    assert point.vertices_2d().shape == (1, 2) and point.area() == 0.0
    same_vertices(segment.vertices_2d(), np.array([[1, 1], [-1, -1]]))
    assert segment.area() == 0.0


def test_explicit_tolerance_and_vertex_cap_are_honoured():
    E = ss.Ellipsoid([0.0, 0.0], np.eye(2))
    coarse = vertices_2d(E, tol=1e-2)
    fine = vertices_2d(E, max_vertices=64)
    assert len(coarse) < len(fine) <= 128
    assert polygon_area(coarse) < polygon_area(fine) < np.pi


def test_shoelace_area_of_fewer_than_three_points_is_zero():
    assert polygon_area(np.zeros((2, 2))) == 0.0
    assert polygon_area(np.array([[0, 0], [1, 0], [0, 1]], dtype=float)) == 0.5


def test_plot_returns_the_patch_and_draws_on_the_given_axes():
    fig, ax = plt.subplots()
    patch = ss.Box([0, 0], [1, 1]).plot(ax=ax, facecolor="red", label="box")
    assert patch in ax.patches and patch.get_label() == "box"
    assert patch.get_alpha() == 0.4
    plt.close(fig)


def test_plot_of_a_3d_set_draws_the_projection_onto_dims():
    fig, ax = plt.subplots()
    patch = ss.Box([0, 1, 2], [1, 3, 5]).plot(ax=ax, dims=(2, 0))
    xy = patch.get_xy()
    assert xy[:, 0].min() == pytest.approx(2.0) and xy[:, 0].max() == pytest.approx(5.0)
    plt.close(fig)


def test_plot_of_a_segment_is_a_line_and_of_the_empty_set_nothing():
    fig, ax = plt.subplots()
    line = ss.Zonotope([[1.0], [0.0]], [0.0, 0.0]).plot(ax=ax, color="k", facecolor="r")
    assert line in ax.lines
    assert ss.EmptySet(2).plot(ax=ax) is None
    plt.close(fig)



def test_thin_posterior_far_from_the_origin_gives_one_convex_loop():
    """Rethinking example (30) at k = 20 (seeded run 6 of Fig. 3): a posterior about 1 wide at |x| ~ 150
    whose support points come from a CVXPY program; the walk once wound round it 60 times (391 points,
    shoelace area 7.82 for a polygon of area 0.117)."""
    from setsmooth.papers.rethinking_examples import (rethinking_example_30,
                                                      rethinking_example_30_joint_range,
                                                      rethinking_example_30_x0)

    rng = np.random.default_rng(np.random.SeedSequence(0, spawn_key=(6,)))
    system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    x, w, vs = X0.sample(rng, 1)[0], system.W.sample(rng, 1)[0], system.V.sample(rng, 21)
    xs = [x]
    for k in range(20):
        xs.append(system.step(k, xs[-1], w))
    ys = np.array([system.measure(k, xs[k], vs[k]) for k in range(21)])
    S = ss.joint_trajectory_set(system, rethinking_example_30_joint_range(20), ys, 20).project([40, 41])
    v = S.vertices_2d()
    n = len(v)
    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    turns = [cross(v[i] - v[i - 1], v[(i + 1) % n] - v[i]) for i in range(n)]
    assert min(turns) > 0                                          # convex, counter-clockwise
    headings = np.unwrap([np.arctan2(*(v[(i + 1) % n] - v[i % n])[::-1]) for i in range(n + 1)])
    assert headings[-1] - headings[0] == pytest.approx(2 * np.pi, abs=1e-6)   # exactly one turn
    D = np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 48)), np.sin(np.linspace(0, 2 * np.pi, 48))])
    np.testing.assert_allclose((v @ D.T).max(axis=0), S.support_many(D), atol=1e-6)


def test_the_walk_returns_vertices_2d_and_support_half_planes_that_hold_on_the_set():
    from setsmooth.sets.vertices_2d import boundary_walk

    for S in (ss.Box([149.0, -1.0], [150.0, 0.0]), ss.Ellipsoid([1.0, 2.0], np.diag([4.0, 0.25])),
              ss.Zonotope([[1.0, 2.0, 0.5], [0.0, 1.0, -1.0]], [3.0, -2.0]),
              ss.Zonotope([[1.0], [1.0]], [0.0, 0.0])):
        V, N, h = boundary_walk(S)
        assert np.array_equal(V, vertices_2d(S))
        assert np.allclose(np.linalg.norm(N, axis=1), 1.0) and len(N) >= 8
        assert np.allclose(h, S.support_many(N), rtol=0, atol=1e-9 * (1 + np.abs(h).max()))
    V, N, h = boundary_walk(ss.EmptySet(2))
    assert V.shape == N.shape == (0, 2) and h.shape == (0,)


def test_support_bound_of_the_walks_half_planes_is_the_polytopes_support_and_never_below_it():
    from setsmooth.sets.vertices_2d import boundary_walk, support_bound_2d

    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    D = np.column_stack([np.cos(t), np.sin(t)])
    for S in (ss.Box([149.0, -1.0], [150.0, 0.0]),
              ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [1.0, 0.0, 0.0]),
              ss.Zonotope([[1.0, 2.0, 0.5], [0.0, 1.0, -1.0]], [3.0, -2.0])):
        _, N, h = boundary_walk(S)
        exact = S.support_many(D)
        # to the solver's accuracy (the triangle's values come from an interior-point solver)
        assert support_bound_2d(N, h, D) == pytest.approx(exact, rel=0, abs=1e-9 * np.abs(exact).max())
    # Half-planes of a square alone, its corners never asked for: the bound is the square's support,
    # from the half-planes, not from points (a walk short of a corner cannot lower it).
    N = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    bound = support_bound_2d(N, np.ones(4), D)
    assert bound == pytest.approx(np.abs(D).sum(axis=1), rel=1e-15)
    # Directions that do not span the plane bound nothing across the gap.
    assert np.isinf(support_bound_2d(N[:2], np.ones(2), np.array([[-1.0, -1.0]]))).all()
