"""3-D polytopes from support points against brute-force vertex enumeration, and 3-D plots."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from scipy.spatial import ConvexHull  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.sets.vertices_3d import faces_3d, vertices_3d  # noqa: E402
from tests.sets.test_oracles import cz_points, zonotope_points  # noqa: E402


def same_point_sets(A, B, atol=1e-6):
    return len(A) == len(B) and all(np.min(np.linalg.norm(B - a, axis=1)) < atol for a in A)


@pytest.mark.parametrize("seed", range(4))
def test_vertices_3d_of_zonotopes_and_czs_are_the_enumerated_vertices(seed):
    rng = np.random.default_rng(seed)
    G, c = rng.standard_normal((3, 5)), rng.standard_normal(3)
    pts = zonotope_points(G, c)
    expected = pts[ConvexHull(pts).vertices]
    assert same_point_sets(vertices_3d(ss.Zonotope(G, c)), expected)
    Z = ss.ConstrainedZonotope(G, c, rng.standard_normal((1, 5)), [0.2])
    if not Z.is_empty():
        pts = cz_points(Z.G, Z.c, Z.A, Z.b, Z.h)
        found = vertices_3d(Z)
        assert ConvexHull(found).volume == pytest.approx(ConvexHull(pts).volume, rel=1e-6)


def test_vertices_3d_of_flat_and_curved_sets():
    plane = ss.Zonotope([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]], [0.0, 0.0, 1.0])  # a parallelogram
    V = vertices_3d(plane)
    assert same_point_sets(V, zonotope_points(np.asarray(plane.G), np.asarray(plane.c)))
    segment = vertices_3d(ss.Zonotope([[1.0], [2.0], [3.0]], [0.0, 0.0, 0.0]))
    assert same_point_sets(segment, np.array([[1.0, 2, 3], [-1, -2, -3]]))
    E = ss.Ellipsoid(np.zeros(3), np.diag([1.0, 4.0, 9.0]))
    V = vertices_3d(E, max_vertices=300)
    volume = 4 / 3 * np.pi * 6
    assert 0.95 * volume < ConvexHull(V).volume <= volume * (1 + 1e-9)
    assert len(V) <= 300
    with pytest.raises(ValueError, match="needs a 3-D set"):
        vertices_3d(ss.Box([0, 0], [1, 1]))


def test_plot_in_three_dims_draws_the_faces_of_the_projection():
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    box4 = ss.Box([0, 0, 0, 0], [1, 2, 3, 4])
    artist = box4.plot(ax, dims=(0, 2, 3), facecolor="tab:blue")
    assert isinstance(artist, Poly3DCollection)
    fig.canvas.draw()  # the projected faces exist once drawn
    faces = artist.get_paths()
    assert len(faces) == 6 and all(len(f.vertices) >= 4 for f in faces)  # six quadrilaterals
    lims = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])
    assert lims[:, 0].max() <= 0.0 + 1e-9 and np.all(lims[:, 1] >= [1.0, 3.0, 4.0])
    octahedron = ss.VPolytope(np.vstack([np.eye(3), -np.eye(3)]))
    assert len(faces_3d(vertices_3d(octahedron))) == 8
    flat = ss.Zonotope([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]], [0, 0, 0]).plot(ax, dims=(0, 1, 2))
    fig.canvas.draw()
    assert isinstance(flat, Poly3DCollection) and len(flat.get_paths()) == 1
    plt.close(fig)


def test_plot_three_dims_needs_a_3d_axes():
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match="needs a 3-D axes"):
        ss.Box([0, 0, 0], [1, 1, 1]).plot(ax, dims=(0, 1, 2))
    plt.close(fig)
