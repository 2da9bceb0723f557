"""The public extension points of `ConvexSet`: a user set that is exactly a CZ, or has a closed-form
support function, joins the fast paths without touching private hooks (checked by counting calls)."""

import cvxpy as cp
import numpy as np
import pytest

import setsmooth as ss
from setsmooth.papers.smoothing_examples import smoothing_example_31_x0
from tests.estimation_helpers import example_31


class CountingDiamond(ss.ConvexSet):
    """{x ∈ ℝ² : |x₁ − c₁| + |x₂ − c₂| ≤ r}, given by its constraints and by its exact CZ form."""

    def __init__(self, center, radius, cz_form=True):
        self.c, self.r, self.dim = np.asarray(center, dtype=float), float(radius), 2
        self.cz_form = cz_form
        self.calls = {"constraints": 0, "as_constrained_zonotope": 0}

    def constraints(self, x):
        self.calls["constraints"] += 1
        return [cp.norm1(x - self.c) <= self.r]

    def as_constrained_zonotope(self):
        self.calls["as_constrained_zonotope"] += 1
        if not self.cz_form:
            return None
        return ss.Zonotope(self.r / 2 * np.array([[1.0, 1.0], [1.0, -1.0]]), self.c)


class CountingBall(ss.ConvexSet):
    """The Euclidean ball B(c, r), with its support function and support vectors in closed form."""

    def __init__(self, center, radius, vectors=True):
        self.c, self.r = np.asarray(center, dtype=float), float(radius)
        self.dim = self.c.size
        self.vectors = vectors
        self.calls = {"constraints": 0, "support_function": 0}

    def constraints(self, x):
        self.calls["constraints"] += 1
        return [cp.norm(x - self.c, 2) <= self.r]

    def support_function(self, D):
        self.calls["support_function"] += 1
        return D @ self.c + self.r * np.linalg.norm(D, axis=1)

    def support_vectors(self, D):
        if not self.vectors:
            return super().support_vectors(D)
        return self.c + self.r * D / np.linalg.norm(D, axis=1, keepdims=True)


def _diamond_system(cz_form):
    sys31 = example_31()
    return ss.LinearSystem(sys31.A_at(0), None, sys31.C_at(0), F=sys31.F_at(0),
                           W=CountingDiamond([0.0, 0.0], 0.5, cz_form), V=sys31.V), smoothing_example_31_x0()


def test_a_user_set_with_a_cz_form_takes_the_cz_fast_path_in_filter_and_smoother():
    system, x0_set = _diamond_system(cz_form=True)
    _, ys = ss.simulate(system, x0_set, 8, np.random.default_rng(3))
    post = ss.classical_filter(system, x0_set, ys)
    smoothed = ss.optimal_smoother(system, x0_set, ys, posteriors=post)       # recursion (24)
    trajectory = ss.optimal_smoother(system, x0_set, ys, method="trajectory")  # one sparse CZ
    hulls = [S.interval_hull() for S in post + smoothed]
    for a, b in zip(smoothed, trajectory):
        np.testing.assert_allclose(a.interval_hull().lo, b.interval_hull().lo, atol=1e-6)
    W = system.W
    # The CVXPY constraints were never asked for: every program ran on the CZ form.
    assert W.calls == {"constraints": 0, "as_constrained_zonotope": 1}
    assert all(isinstance(S, ss.ConstrainedZonotope) for S in post + smoothed)

    # The same set without the hook goes through CVXPY, and gives the same ranges.
    slow_system, _ = _diamond_system(cz_form=False)
    slow_post = ss.classical_filter(slow_system, x0_set, ys)
    assert slow_system.W.calls["constraints"] > 0
    for fast, slow in zip(hulls, [S.interval_hull() for S in slow_post]):
        np.testing.assert_allclose(fast.lo, slow.lo, atol=1e-6)
        np.testing.assert_allclose(fast.hi, slow.hi, atol=1e-6)


def test_a_cz_form_gives_certified_supports_and_membership_without_cvxpy():
    D = CountingDiamond([1.0, -2.0], 2.0)
    directions = np.array([[1.0, 0.0], [1.0, 1.0], [-0.3, 0.7]])
    exact = directions @ D.c + D.r * np.abs(directions).max(axis=1)  # dual norm of ℓ1 is ℓ∞
    np.testing.assert_allclose(D.support_many(directions, certified=True), exact, atol=1e-9)
    assert [1.0, -0.1] in D and [1.0, 0.1] not in D
    assert D.calls["constraints"] == 0


def test_a_closed_form_support_function_serves_hulls_and_lazy_algebra_without_programs():
    ball = CountingBall([1.0, 2.0, -1.0], 0.5)
    hull = ball.interval_hull()
    np.testing.assert_allclose(hull.lo, ball.c - 0.5)
    np.testing.assert_allclose(hull.hi, ball.c + 0.5)
    M = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, -1.0]])
    image = M @ ball + ss.Box([-1.0, -1.0], [1.0, 1.0])  # lazy: a ball has no CZ form
    d = np.array([0.3, -0.8])
    assert image.support(d) == pytest.approx(ball.support(M.T @ d) + np.abs(d).sum(), abs=1e-12)
    np.testing.assert_allclose(ball.support_point([0.0, 0.0, 2.0]), ball.c + [0, 0, 0.5])
    assert ball.calls["constraints"] == 0 and ball.calls["support_function"] >= 3
    # The generic path still solves the program, and agrees.
    assert ball.support(d @ M, path="generic") == pytest.approx(ball.support(d @ M), abs=1e-7)
    assert ball.calls["constraints"] == 1


def test_support_vectors_default_to_a_program_when_only_values_are_given():
    ball = CountingBall([0.0, 0.0], 2.0, vectors=False)
    point = ball.support_point([3.0, 4.0])
    np.testing.assert_allclose(point, [1.2, 1.6], atol=1e-6)
    assert ball.support([3.0, 4.0]) == 10.0  # the closed form's value, not the program's
    assert ball.vertices_2d().shape[0] > 8  # plotting works: points from the program


def test_the_private_hook_name_still_works_as_an_alias():
    class Old(ss.ConvexSet):
        dim = 2

        def constraints(self, x):
            return [cp.norm(x, "inf") <= 1]

        def _as_constrained_zonotope(self):
            return ss.Box([-1.0, -1.0], [1.0, 1.0]).to_constrained_zonotope()

    assert isinstance(Old().as_constrained_zonotope(), ss.ConstrainedZonotope)
    assert Old()._flat_cz is not None and Old().support([1.0, 1.0], certified=True) >= 2.0


def test_bad_extension_results_are_refused_naming_the_hook():
    class WrongDim(CountingDiamond):
        def as_constrained_zonotope(self):
            return ss.Box([0.0], [1.0])

    with pytest.raises(ValueError, match=r"WrongDim.as_constrained_zonotope\(\) returned a set of dimension 1"):
        WrongDim([0, 0], 1).support([1.0, 0.0])

    class NotACZ(CountingDiamond):
        def as_constrained_zonotope(self):
            return ss.Ellipsoid([0.0, 0.0], np.eye(2))

    with pytest.raises(TypeError, match="not exactly a constrained zonotope"):
        NotACZ([0, 0], 1).support([1.0, 0.0])

    class BadValues(CountingBall):
        def support_function(self, D):
            return np.zeros(D.shape[0] + 1)

    with pytest.raises(ValueError, match="BadValues.support_function must return 2 values"):
        BadValues([0.0], 1.0).support_many([[1.0], [-1.0]])
