"""Every bad input is refused at the door with a ValueError or TypeError that names the argument."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import setsmooth as ss

Z2 = ss.Zonotope(np.eye(2), np.zeros(2))
BOX2 = ss.Box([0, 0], [1, 1])


# -- constructors -----------------------------------------------------------------------------------

@pytest.mark.parametrize("lo, hi, match", [
    ([0, 0], [1], "hi must have length 2"),
    ([0, np.nan], [1, 1], "lo contains NaN"),
    ([0, 0], [1, np.nan], "hi contains NaN"),
    ([0, 2], [1, 1], r"lo must not exceed hi; lo > hi at indices \[1\]"),
    ([np.inf], [np.inf], "lo cannot be \\+inf"),
    ([-np.inf], [-np.inf], "hi cannot be -inf"),
    ([[0, 0], [1, 1]], [1, 1], "lo must be a vector"),
])
def test_box_refuses_bad_bounds(lo, hi, match):
    with pytest.raises(ValueError, match=match):
        ss.Box(lo, hi)


def test_box_refuses_non_numeric_bounds():
    with pytest.raises(TypeError, match="lo must be array-like"):
        ss.Box(["a"], [1])


@pytest.mark.parametrize("G, c, match", [
    (np.eye(2), [0, 0, 0], "c must have length 2"),
    ([[1, np.nan], [0, 1]], [0, 0], "G contains NaN"),
    ([[1, np.inf], [0, 1]], [0, 0], "G contains NaN or inf"),
    (np.eye(2), [0, np.inf], "c contains inf"),
    (np.ones((2, 2, 2)), [0, 0], "G must be a 2-D matrix"),
])
def test_zonotope_refuses_bad_generators_and_centres(G, c, match):
    with pytest.raises(ValueError, match=match):
        ss.Zonotope(G, c)


@pytest.mark.parametrize("kwargs, match", [
    (dict(G=np.eye(2), c=[0, 0, 0]), "c must have length 2"),
    (dict(G=np.eye(2), c=[0, 0], A=[[1, 1, 1]], b=[0]), r"A must have shape \(any, 2\)"),
    (dict(G=np.eye(2), c=[0, 0], A=[[1, 1]], b=[0, 1]), "b must have length 1"),
    (dict(G=np.eye(2), c=[0, 0], A=np.zeros((0, 2)), b=[1]), "b must have length 0"),
    (dict(G=np.eye(2), c=[0, 0], h=[1, 1, 1]), "h must have length ng = 2"),
    (dict(G=np.eye(2), c=[0, 0], h=[1, -1]), r"h must lie in \[0, inf\]"),
    (dict(G=np.eye(2), c=[0, 0], h=[1, np.nan]), r"h must lie in \[0, inf\]"),
    (dict(G=[[np.nan, 0], [0, 1]], c=[0, 0]), "G contains NaN"),
    (dict(G=np.eye(2), c=[0, 0], A=[[np.inf, 1]], b=[0]), "A contains NaN or inf"),
    (dict(G=np.eye(2), c=[0, 0], A=[[1, 1]], b=[np.nan]), "b contains NaN"),
    (dict(G=np.eye(2), c=[0, 0], A=[[1, 1]], b=[np.inf]), "b contains inf"),
    (dict(G=np.eye(2), c=[0, 0], A=[[1, 1]]), "A and b must be given together"),
    (dict(G=np.eye(2), c=[0, 0], b=[1]), "A and b must be given together"),
    (dict(G=sp.csc_matrix(np.eye(2)), c=[0, 0], A=sp.csc_matrix([[np.nan, 1.0]]), b=[0]),
     "A contains NaN or inf"),
    (dict(G=sp.csc_matrix(np.eye(2)), c=[0, 0], A=sp.csc_matrix(np.ones((1, 3))), b=[0]),
     r"A must have shape \(any, 2\)"),
])
def test_constrained_zonotope_refuses_inconsistent_matrices(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ss.ConstrainedZonotope(**kwargs)


def test_constrained_zonotope_refuses_non_numeric_bounds():
    with pytest.raises(TypeError, match="h must be array-like"):
        ss.ConstrainedZonotope(np.eye(2), [0, 0], h=["a", "b"])


@pytest.mark.parametrize("H, k, match", [
    (np.eye(2), [1, 1, 1], "k must have length 2"),
    ([[1, np.nan]], [1], "H contains NaN"),
    ([[1, 0]], [np.inf], "k contains inf"),
])
def test_hpolytope_refuses_bad_halfspaces(H, k, match):
    with pytest.raises(ValueError, match=match):
        ss.HPolytope(H, k)


@pytest.mark.parametrize("c, Q, match", [
    ([0, 0], [[1, 1], [0, 1]], "Q must be symmetric"),
    ([0, 0], [[1, 0], [0, -1]], "Q must be positive semidefinite"),
    ([0, 0], [[1, 2], [2, 1]], "Q must be positive semidefinite"),
    ([0, 0], np.eye(3), r"Q must have shape \(2, 2\)"),
    ([0, np.nan], np.eye(2), "c contains NaN"),
    ([0, 0], [[1, np.inf], [np.inf, 1]], "Q contains NaN or inf"),
])
def test_ellipsoid_refuses_non_symmetric_indefinite_or_misshapen_q(c, Q, match):
    with pytest.raises(ValueError, match=match):
        ss.Ellipsoid(c, Q)


@pytest.mark.parametrize("cls", [ss.Reals, ss.EmptySet])
@pytest.mark.parametrize("n, exc", [(0, ValueError), (-1, ValueError), (2.0, TypeError),
                                    ("2", TypeError), (True, TypeError)])
def test_reals_and_empty_set_refuse_non_positive_integer_dimensions(cls, n, exc):
    with pytest.raises(exc, match="n must be a positive integer"):
        cls(n)


# -- operations ------------------------------------------------------------------------------------

@pytest.mark.parametrize("op", [
    lambda: BOX2 + ss.Box([0], [1]),
    lambda: Z2 + ss.Ellipsoid([0], [[1.0]]),
    lambda: BOX2 - ss.Box([0], [1]),
])
def test_minkowski_sum_needs_equal_dimensions(op):
    with pytest.raises(ValueError, match="Minkowski sum needs operands of equal dimension"):
        op()


@pytest.mark.parametrize("op", [
    lambda: BOX2 & ss.Box([0], [1]),
    lambda: Z2 & ss.HPolytope([[1.0, 1.0, 1.0]], [1.0]),
])
def test_intersection_needs_equal_dimensions(op):
    with pytest.raises(ValueError, match="intersection needs operands of equal dimension"):
        op()


def test_translation_vector_must_have_the_set_dimension():
    with pytest.raises(ValueError, match="translation vector must have length 2"):
        BOX2 + np.ones(3)
    with pytest.raises(ValueError, match="translation vector contains NaN"):
        BOX2 + np.array([0.0, np.nan])


def test_linear_map_needs_as_many_columns_as_the_set_dimension():
    with pytest.raises(ValueError, match=r"M must have shape \(any, 2\)"):
        np.ones((2, 3)) @ BOX2
    with pytest.raises(ValueError, match="M contains NaN or inf"):
        np.array([[1.0, np.nan]]) @ BOX2


@pytest.mark.parametrize("R, match", [
    (np.ones((2, 2)), r"R must have shape \(1, 2\)"),
    (np.ones((1, 3)), r"R must have shape \(1, 2\)"),
    ([[np.nan, 1.0]], "R contains NaN or inf"),
])
def test_intersect_preimage_needs_r_of_shape_y_dim_by_set_dim(R, match):
    with pytest.raises(ValueError, match=match):
        BOX2.intersect_preimage(R, ss.Box([0], [1]))


def test_intersect_preimage_needs_a_set():
    with pytest.raises(TypeError, match="Y must be a ConvexSet"):
        BOX2.intersect_preimage(np.eye(2), [0, 1])


def test_preimage_needs_as_many_rows_as_the_set_dimension():
    with pytest.raises(ValueError, match=r"M must have shape \(2, any\)"):
        BOX2.preimage(np.ones((3, 2)))


@pytest.mark.parametrize("op", [lambda: BOX2 & [0, 1], lambda: BOX2 * 2, lambda: 2 * BOX2,
                                lambda: BOX2 @ np.eye(2)])
def test_operators_with_non_sets_are_type_errors(op):
    with pytest.raises(TypeError):
        op()


@pytest.mark.parametrize("dims, exc, match", [
    ([2], ValueError, r"dims must be non-empty indices in \[0, 2\)"),
    ([-1], ValueError, "dims must be non-empty indices"),
    ([], ValueError, "dims must be non-empty indices"),
    ([0.7], TypeError, "dims must be a sequence of integers"),
    ([True], TypeError, "dims must be a sequence of integers"),
    (["a"], TypeError, "dims must be a sequence of integers"),
])
@pytest.mark.parametrize("S", [BOX2, Z2, ss.Ellipsoid([0, 0], np.eye(2)),
                               ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
                               ss.Reals(2), ss.EmptySet(2)], ids=lambda S: type(S).__name__)
def test_project_refuses_bad_dims(S, dims, exc, match):
    with pytest.raises(exc, match=match):
        S.project(dims)


# -- lazy constructors (public, so they validate too) -----------------------------------------------

def test_lazy_constructors_validate_their_operands():
    E = ss.Ellipsoid([0, 0], np.eye(2))
    with pytest.raises(ValueError, match=r"M must have shape \(any, 2\)"):
        ss.LinearMap(np.ones((2, 3)), E)
    with pytest.raises(ValueError, match="offset must have length 2"):
        ss.LinearMap(np.eye(2), E, offset=[1, 2, 3])
    with pytest.raises(TypeError, match="S must be a ConvexSet"):
        ss.LinearMap(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="Minkowski sum needs operands of equal dimension"):
        ss.MinkowskiSum(E, ss.Box([0], [1]))
    with pytest.raises(ValueError, match="intersection needs operands of equal dimension"):
        ss.Intersection(E, ss.Box([0], [1]))
    with pytest.raises(TypeError, match="T must be a ConvexSet"):
        ss.CartesianProduct(E, 3)
    with pytest.raises(ValueError, match=r"R must have shape \(1, 2\)"):
        ss.GeneralizedIntersection(E, np.ones((2, 2)), ss.Box([0], [1]))


# -- queries ---------------------------------------------------------------------------------------

QUERY_SETS = [BOX2, Z2, ss.Ellipsoid([0, 0], np.eye(2)), ss.Reals(2), ss.EmptySet(2),
              ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1.0, 1.0]], b=[0.5]),
              ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
              ss.Ellipsoid([0, 0], np.eye(2)) + BOX2]
IDS = [type(S).__name__ for S in QUERY_SETS]


@pytest.mark.parametrize("S", QUERY_SETS, ids=IDS)
def test_bad_solver_path_strings_are_refused_by_every_query(S):
    for query in (lambda: S.support([1, 0], path="fast"),
                  lambda: S.support_many(np.eye(2), path="cvx"),
                  lambda: S.support_point([1, 0], path=""),
                  lambda: S.is_empty(path="exact"),
                  lambda: S.contains([0, 0], path="lp"),
                  lambda: S.interval_hull(path="closed"),
                  lambda: S.diameter(path="closed")):
        with pytest.raises(ValueError, match="path must be one of"):
            query()
    with pytest.raises(ValueError, match="method must be 'interval_hull', 'chebyshev' or 'closest'"):
        S.center(method="mean")


@pytest.mark.parametrize("S", QUERY_SETS, ids=IDS)
def test_certified_values_cannot_come_from_the_generic_path(S):
    with pytest.raises(ValueError, match="certified=True needs the constrained-zonotope fast path"):
        S.support([1, 0], path="generic", certified=True)
    with pytest.raises(ValueError, match="certified=True needs the constrained-zonotope fast path"):
        S.interval_hull(path="generic", certified=True)


@pytest.mark.parametrize("S", [ss.Ellipsoid([0, 0], np.eye(2)),
                               ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
                               ss.Ellipsoid([0, 0], np.eye(2)) & BOX2],
                         ids=["Ellipsoid", "HPolytope", "Intersection"])
def test_certified_values_need_a_set_that_flattens_to_a_cz(S):
    with pytest.raises(ValueError, match="certified support values are not available"):
        S.support([1, 0], certified=True)
    with pytest.raises(ValueError, match="certified support values are not available"):
        S.interval_hull(certified=True)
    with pytest.raises(TypeError, match="has no exact constrained-zonotope form"):
        S.to_constrained_zonotope()


@pytest.mark.parametrize("S", QUERY_SETS, ids=IDS)
def test_directions_and_points_must_match_the_dimension(S):
    with pytest.raises(ValueError, match="d must have length 2"):
        S.support([1, 0, 0])
    with pytest.raises(ValueError, match=r"D must have shape \(k, 2\)"):
        S.support_many(np.ones((3, 3)))
    with pytest.raises(ValueError, match="D contains NaN or inf"):
        S.support_many(np.array([[np.nan, 0.0]]))
    with pytest.raises(ValueError, match="d contains NaN"):
        S.support([np.nan, 0])
    with pytest.raises(ValueError, match="point must have length 2"):
        S.contains([0, 0, 0])
    with pytest.raises(ValueError, match="tol must be a finite non-negative number"):
        S.contains([0, 0], tol=-1e-3)


def test_closest_point_centre_needs_a_reference_of_the_right_length():
    with pytest.raises(ValueError, match="needs a reference point"):
        BOX2.center("closest")
    with pytest.raises(ValueError, match="reference must have length 2"):
        BOX2.center("closest", reference=[1, 2, 3])


def test_chebyshev_centre_needs_an_h_representation_or_a_cz_form():
    lazy = ss.Ellipsoid([0, 0], np.eye(2)) + ss.HPolytope([[1.0, 0.0]], [1.0])
    with pytest.raises(NotImplementedError, match="needs an H-representation or a constrained-zonotope"):
        lazy.center("chebyshev")


@pytest.mark.parametrize("S", [BOX2, ss.Ellipsoid([0, 0], np.eye(2)), Z2],
                         ids=["Box", "Ellipsoid", "Zonotope"])
def test_sampling_needs_a_numpy_generator(S):
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        S.sample(0, size=2)


def test_polygon_queries_need_bounded_2d_sets():
    with pytest.raises(ValueError, match="needs a 2-D set"):
        ss.Box([0, 0, 0], [1, 1, 1]).vertices_2d()
    with pytest.raises(ValueError, match="needs a bounded set"):
        ss.HPolytope([[1.0, 0.0]], [1.0]).area()
    with pytest.raises(ValueError, match="dims must name two coordinates"):
        BOX2.plot(dims=(0, 1, 1, 0))


# -- complex input is refused, never cast to its real part ------------------------------------------

@pytest.mark.parametrize("make", [
    lambda: ss.Ellipsoid([0.0, 0.0], [[2.0, 1j], [-1j, 2.0]]),  # Hermitian PD, its real part is 2 I
    lambda: ss.Box(np.array([0.0, 1e-9j]), [1, 1]),
    lambda: ss.Zonotope(sp.csc_matrix(np.eye(2) * (1 + 0j)), [0, 0]),
    lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], h=np.array([1, 1], dtype=complex)),
    lambda: np.eye(2, dtype=complex) @ BOX2,
    lambda: BOX2.contains([0.5, 0.5], tol=np.complex128(1e-3)),
])
def test_complex_input_is_a_type_error_not_its_real_part(make):
    with pytest.raises(TypeError, match="must be real, got complex|must be real, got a sparse matrix"):
        make()
