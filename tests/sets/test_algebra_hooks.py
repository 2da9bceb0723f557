"""The set-algebra hooks are declared on ConvexSet, and widening does not depend on the operand order."""

from __future__ import annotations

import importlib
import inspect
import itertools
import pkgutil

import numpy as np
import pytest

import setsmooth
import setsmooth as ss
from setsmooth.sets import algebra
from setsmooth.sets.base import ConvexSet
from setsmooth.sets.hooks import ALGEBRA_HOOKS


def _all_convex_set_classes():
    for info in pkgutil.walk_packages(setsmooth.__path__, "setsmooth."):
        importlib.import_module(info.name)
    seen, todo = set(), [ConvexSet]
    while todo:
        cls = todo.pop()
        for sub in cls.__subclasses__():
            if sub not in seen and sub.__module__.startswith("setsmooth."):
                seen.add(sub)
                todo.append(sub)
    return sorted(seen, key=lambda c: c.__qualname__)


@pytest.mark.parametrize("name", ["_closed_intersecton", "_closedsum", "_close_sum", "_closed_prodcut",
                                  "_clsoed_translate", "_closed_union"])
def test_a_misspelt_or_undeclared_hook_is_refused_when_the_class_is_defined(name):
    with pytest.raises(TypeError, match=f"{name} looks like a set-algebra hook"):
        type("Misspelt", (ss.Box,), {name: lambda self, other: NotImplemented})


def test_the_cz_operations_and_other_private_names_are_not_taken_for_hooks():
    names = ["_linear_map", "_translate", "_minkowski_sum", "_generalized_intersection",
             "_cartesian_product", "_closest_point", "_project", "_support"]
    Fine = type("Fine", (ss.Box,), {name: lambda self, *args: NotImplemented for name in names})
    assert issubclass(Fine, ConvexSet)


def test_every_closed_name_of_every_set_class_is_a_declared_hook():
    classes = _all_convex_set_classes()
    assert {ss.Box, ss.Zonotope, ss.ConstrainedZonotope, ss.HPolytope, ss.Ellipsoid} <= set(classes)
    for cls in classes:
        undeclared = {name for name in vars(cls) if name.startswith("_closed_")} - ALGEBRA_HOOKS
        assert not undeclared, f"{cls.__name__} defines undeclared hooks {undeclared}"


def test_every_declared_hook_has_a_not_implemented_default_and_is_called_by_the_algebra():
    source = inspect.getsource(algebra)
    assert ALGEBRA_HOOKS >= {"_closed_linear_map", "_closed_translate", "_closed_sum",
                             "_closed_intersection", "_closed_generalized_intersection",
                             "_closed_reflected_generalized_intersection", "_closed_product",
                             "_closed_reflected_product"}
    for hook in ALGEBRA_HOOKS:
        assert f".{hook}(" in source, f"{hook} is declared but never called by the algebra"
        n_args = len(inspect.signature(getattr(ConvexSet, hook)).parameters) - 1
        assert getattr(ConvexSet, hook)(ss.Box([0.0], [1.0]), *([None] * n_args)) is NotImplemented
    assert "getattr" not in source  # hooks are called directly, never looked up by string


# Every representation, each containing the origin in its interior so every intersection is solid.
REPRESENTATIONS = {
    "Box": lambda: ss.Box([-1.0, -0.5], [1.0, 1.5]),
    "Zonotope": lambda: ss.Zonotope([[1.0, 0.5, 0.0], [0.0, 1.0, 0.3]], [0.1, 0.0]),
    "CZ": lambda: ss.ConstrainedZonotope([[1.0, 0.0, 0.4], [0.0, 1.0, 0.4]], [0.0, 0.1],
                                         A=[[1.0, 1.0, -1.0]], b=[0.2]),
    "HPolytope": lambda: ss.HPolytope([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0], [-1.0, 0.5]],
                                      [1.2, 1.0, 1.0, 1.5]),
    "Ellipsoid": lambda: ss.Ellipsoid([0.0, 0.1], [[1.5, 0.3], [0.3, 0.8]]),
    "Reals": lambda: ss.Reals(2),
}
HPOLY_FAMILY = {"Box", "HPolytope", "Reals"}
CZ_FAMILY = {"Box", "Zonotope", "CZ", "Reals"}


def _expected_generalized_intersection_type(a: str, b: str):
    """The widened type of a ∩_R b for a general square R: a function of the unordered pair."""
    pair = {a, b}
    if pair <= HPOLY_FAMILY and "HPolytope" in pair:
        return ss.HPolytope
    if pair <= CZ_FAMILY:
        return ss.ConstrainedZonotope
    return ss.GeneralizedIntersection


PAIRS = list(itertools.combinations_with_replacement(sorted(REPRESENTATIONS), 2))
R = np.array([[1.0, 0.5], [-0.3, 1.0]])
DIRECTIONS = np.vstack([np.eye(2), -np.eye(2), np.random.default_rng(3).standard_normal((4, 2))])


@pytest.mark.parametrize("a,b", PAIRS, ids=[f"{a}-{b}" for a, b in PAIRS])
def test_generalized_intersection_widens_the_same_in_both_orders(a, b):
    S, Y = REPRESENTATIONS[a](), REPRESENTATIONS[b]()
    forward = S.intersect_preimage(R, Y)                       # {s ∈ S : R s ∈ Y}
    backward = Y.intersect_preimage(np.linalg.inv(R), S)       # {y ∈ Y : R⁻¹y ∈ S} = R·forward
    expected = _expected_generalized_intersection_type(a, b)
    assert type(forward) is expected and type(backward) is expected
    if a == b == "Reals":
        return  # ℝ² both ways: nothing bounded to compare
    # h_{R·F}(d) = h_F(Rᵀd): the two orders are the same set up to the map R.
    np.testing.assert_allclose(backward.support_many(DIRECTIONS), forward.support_many(DIRECTIONS @ R),
                               rtol=1e-6, atol=1e-6)
    # ... and each equals the CVXPY program of the lazy generalized intersection.
    generic = ss.GeneralizedIntersection(S, R, Y).support_many(DIRECTIONS, path="generic")
    np.testing.assert_allclose(forward.support_many(DIRECTIONS), generic, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("a,b", PAIRS, ids=[f"{a}-{b}" for a, b in PAIRS])
def test_intersection_widens_the_same_in_both_orders(a, b):
    S, T = REPRESENTATIONS[a](), REPRESENTATIONS[b]()
    forward, backward = S & T, T & S
    assert type(forward) is type(backward)
    if a == b == "Reals":
        return
    np.testing.assert_allclose(forward.support_many(DIRECTIONS), backward.support_many(DIRECTIONS),
                               rtol=1e-6, atol=1e-6)


ALL_ORDERED_PAIRS = list(itertools.product(sorted(REPRESENTATIONS), repeat=2))


@pytest.mark.parametrize("a,b", ALL_ORDERED_PAIRS, ids=[f"{a}-{b}" for a, b in ALL_ORDERED_PAIRS])
def test_sums_and_products_widen_to_one_type_whatever_the_order(a, b):
    S, T = REPRESENTATIONS[a](), REPRESENTATIONS[b]()
    assert type(S + T) is type(T + S)
    forward, backward = S * T, T * S
    assert type(forward) is type(backward)
    if "Reals" in (a, b):
        return
    # T × S is S × T with its two blocks of coordinates swapped.
    swap = np.roll(np.eye(4), 2, axis=1)
    D = np.random.default_rng(4).standard_normal((6, 4))
    np.testing.assert_allclose(backward.support_many(D @ swap), forward.support_many(D), rtol=1e-6,
                               atol=1e-6)
