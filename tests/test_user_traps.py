"""The small traps of issue 28: each wrong input a new user is likely to type is refused at the door,
naming the argument and what was expected; each habit from NumPy or python-control is either accepted
(a seed for a Generator) or led to the right call."""

from __future__ import annotations

import pathlib
from concurrent.futures import ProcessPoolExecutor

import cvxpy as cp
import numpy as np
import pytest

import setsmooth as ss
from setsmooth.runs.montecarlo import run


def _system(**kwargs):
    args = dict(W=ss.Box([-0.1, -0.1], [0.1, 0.1]), V=ss.Box([-0.1], [0.1])) | kwargs
    return ss.LinearSystem([[0.9, 0.1], [0.0, 0.8]], None, [[1.0, 0.0]], **args)


X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])


# -- seeds and generators ------------------------------------------------------------------------

def test_simulate_takes_an_int_seed_as_the_generator_it_seeds():
    xs, ys = ss.simulate(_system(), X0, 4, 7)
    xs_rng, ys_rng = ss.simulate(_system(), X0, 4, np.random.default_rng(7))
    assert np.array_equal(xs, xs_rng) and np.array_equal(ys, ys_rng)


@pytest.mark.parametrize("rng, exc", [("7", TypeError), (7.0, TypeError), (True, TypeError),
                                      (np.random.RandomState(7), TypeError), (-1, ValueError)])
def test_simulate_refuses_anything_but_a_seed_or_a_generator_naming_rng(rng, exc):
    with pytest.raises(exc, match="rng must be .*seed or a numpy.random.Generator"):
        ss.simulate(_system(), X0, 2, rng)


def draw(rng):
    return rng.standard_normal(2)


def test_montecarlo_takes_a_generator_and_a_fresh_one_gives_the_runs_of_its_seed():
    from_seed = run(draw, 3, seed=5, executor="serial", progress=False)
    from_generator = run(draw, 3, seed=np.random.default_rng(5), executor="serial", progress=False)
    assert np.array_equal(from_seed, from_generator)


def test_montecarlo_with_one_generator_twice_gives_new_independent_runs():
    rng = np.random.default_rng(5)
    first = run(draw, 3, seed=rng, executor="serial", progress=False)
    second = run(draw, 3, seed=rng, executor="serial", progress=False)
    assert not np.isin(np.ravel(second), np.ravel(first)).any()


def _fresh_entropy_runs(seed):
    return run(draw, 3, seed=seed, executor="serial", progress=False)


@pytest.mark.parametrize("call", [lambda rng: ss.simulate(_system(), X0, 4, rng)[1], _fresh_entropy_runs])
def test_none_means_fresh_entropy_as_in_numpy(call):
    first, second = call(None), call(None)     # numpy.random.default_rng(None): a new root each call
    assert np.all(np.isfinite(first)) and not np.array_equal(first, second)


def fail_with_a_draw(rng):
    raise RuntimeError(f"drew {rng.standard_normal()!r}")


def test_a_run_from_fresh_entropy_can_still_be_replayed():
    with pytest.raises(RuntimeError, match="drew") as info:
        run(fail_with_a_draw, 2, seed=None, executor="serial", progress=False)
    replay = " ".join(info.value.__notes__).split("replay it with trial(", 1)[1][:-1]
    with pytest.raises(RuntimeError, match=f"^{info.value}$"):
        fail_with_a_draw(eval(replay, {"numpy": np}))


@pytest.mark.parametrize("seed", ["5", 5.0, True])
def test_montecarlo_refuses_other_seeds_naming_seed(seed):
    with pytest.raises(TypeError, match="seed must be an integer or a numpy.random.Generator"):
        run(draw, 3, seed=seed, executor="serial", progress=False)


def fail_on_negative(rng):
    if rng.standard_normal() < 0:
        raise RuntimeError("boom")
    return 1


def _first_failing_run(seed, n_runs):
    children = np.random.SeedSequence(seed).spawn(n_runs)
    return next(i for i, child in enumerate(children) if np.random.default_rng(child).standard_normal() < 0)


@pytest.mark.parametrize("executor", ["serial", "process pool"])
def test_a_failing_run_is_reraised_with_its_index_and_its_generator(executor):
    seed = next(s for s in range(100) if _first_failing_run(s, 8) >= 2)  # a failure that is not run 0
    index = _first_failing_run(seed, 8)
    pool = ProcessPoolExecutor(max_workers=1) if executor == "process pool" else executor
    try:
        with pytest.raises(RuntimeError, match="boom") as info:
            run(fail_on_negative, 8, seed=seed, executor=pool, progress=False)
    finally:
        if executor == "process pool":
            pool.shutdown()
    note = " ".join(getattr(info.value, "__notes__", []))
    assert f"in Monte Carlo run {index};" in note
    replay = note.split("replay it with trial(", 1)[1][:-1]  # the generator expression, as printed
    with pytest.raises(RuntimeError, match="boom"):
        fail_on_negative(eval(replay, {"numpy": np}))


# -- simulate, LinearSystem and python-control ---------------------------------------------------

def test_simulate_on_a_flat_noise_set_says_that_ws_avoids_the_draw():
    flat = ss.Zonotope([[0.1], [0.1]], [0.0, 0.0])  # a segment of ℝ²: no interior, no uniform law
    system = _system(W=flat)
    with pytest.raises(ValueError, match=r"no interior.*Pass them as ws= \(shape \(3, 2\)"):
        ss.simulate(system, X0, 3, 0)
    xs, _ = ss.simulate(system, X0, 3, 0, ws=np.full((3, 2), 0.05))
    assert xs.shape == (4, 2)


def test_simulate_on_a_flat_measurement_noise_set_names_vs():
    system = _system(V=ss.Zonotope(np.zeros((1, 1)), [0.0]))
    with pytest.raises(ValueError, match=r"from V: .* vs= \(shape \(3, 1\)"):
        ss.simulate(system, X0, 2, 0)


def test_linear_system_repr_says_what_it_is():
    text = repr(ss.LinearSystem(lambda k: np.eye(2), None, [[1.0, 0.0]], W=ss.Box([-1, -1], [1, 1]),
                                V=ss.Box([-1], [1]), dt=0.1))
    assert text.startswith("LinearSystem(n=2, m=1, W=Box(lo=[-1.0, -1.0]")
    assert "time-varying A: callable of k" in text and "dt=0.1" in text
    assert "constant matrices" in repr(_system())


@pytest.fixture
def plant():
    control = pytest.importorskip("control")
    return control.ss([[0.9, 0.1], [0.0, 0.8]], np.eye(2), [[1.0, 0.0]], 0, True)


@pytest.mark.parametrize("call", [
    lambda P: ss.classical_filter(P, X0, np.zeros((3, 1))),
    lambda P: ss.optimal_smoother(P, X0, np.zeros((3, 1))),
    lambda P: ss.simulate(P, X0, 3, 0),
    lambda P: ss.oit_cz_filter(P, X0, np.zeros((3, 1))),
    lambda P: ss.oit_inspired_filter(P, X0, np.zeros((3, 1))),
    lambda P: ss.trajectory_set(P, X0, np.zeros((3, 1))),
    lambda P: ss.filtering_map(P, X0, np.zeros((3, 1)), 0, 2),
])
def test_a_statespace_where_a_system_is_expected_leads_to_from_statespace(plant, call):
    with pytest.raises(TypeError, match=r"system is a control\.StateSpace.*LinearSystem\.from_statespace"):
        call(plant)


def test_a_callable_A_of_the_wrong_size_is_blamed_not_E():
    with pytest.raises(ValueError, match=r"^A\(0\) has shape \(3, 3\), but E has 2 rows and C has 2 "
                                         r"columns: A must be 2×2"):
        ss.LinearSystem(lambda k: np.eye(3), None, [[1.0, 0.0]], E=np.eye(2), W=ss.Box([-1, -1], [1, 1]),
                        V=ss.Box([-1], [1]))


def test_an_E_of_the_wrong_size_is_still_blamed_on_E():
    with pytest.raises(ValueError, match=r"^E must have shape \(2, any\), got \(3, 2\)"):
        ss.LinearSystem(np.eye(2), None, [[1.0, 0.0]], E=np.ones((3, 2)), W=ss.Box([-1, -1], [1, 1]),
                        V=ss.Box([-1], [1]))


def test_boolean_measurements_are_refused_naming_ys():
    with pytest.raises(TypeError, match="ys must be .*booleans"):
        ss.classical_filter(_system(), X0, np.array([[True], [False]]))


@pytest.mark.parametrize("estimator", [ss.classical_filter, ss.optimal_smoother, ss.oit_cz_filter])
def test_an_X0_of_the_wrong_dimension_is_named_with_both_dimensions(estimator):
    with pytest.raises(ValueError, match=r"^X0 must be a ConvexSet of dimension n = 2, got one of dimension 3$"):
        estimator(_system(), ss.Box([-1, -1, -1], [1, 1, 1]), np.zeros((3, 1)))
    with pytest.raises(ValueError, match=r"^x0_set must be a ConvexSet of dimension n = 2, got one of dimension 1$"):
        ss.simulate(_system(), ss.Box([-1], [1]), 3, 0)


BOUNDS = (np.array([-0.1, -0.1]), np.array([0.1, 0.1]))


@pytest.mark.parametrize("call, name, exc", [
    (lambda: _system(W=BOUNDS), "W", TypeError),
    (lambda: _system(V=(np.array([-0.1]), np.array([0.1]))), "V", TypeError),
    (lambda: ss.classical_filter(_system(), ([-1, -1], [1, 1]), np.zeros((3, 1))), "X0", ValueError),
    (lambda: ss.optimal_smoother(_system(), ([-1, -1], [1, 1]), np.zeros((3, 1))), "X0", ValueError),
    (lambda: ss.simulate(_system(), BOUNDS, 3, 0), "x0_set", ValueError),
])
def test_a_pair_of_bounds_given_for_a_set_is_led_to_box(call, name, exc):
    with pytest.raises(exc, match=rf"^{name} must be a ConvexSet.*, got (tuple|list); for {name} given by its "
                                  r"bounds lo ≤ · ≤ hi use ss\.Box\(lo, hi\)$"):
        call()


# -- sets: shapes said, never guessed ----------------------------------------------------------

@pytest.mark.parametrize("make, exc, match", [
    (lambda: ss.Box([[0, 0]], [[1, 1]]), ValueError, r"^lo must be a vector of shape \(n,\), got .* \(1, 2\)"),
    (lambda: ss.Box([0, 0], [[1], [1]]), ValueError, r"^hi must be a vector of shape \(2,\), got .* \(2, 1\)"),
    (lambda: ss.Box([], []), ValueError, r"^lo and hi must have at least one entry"),
    (lambda: ss.Box(np.array([False, False]), [1, 1]), TypeError, r"^lo must .*booleans"),
    (lambda: ss.Box([0, 0], [True, True]), TypeError, r"^hi must .*booleans"),
    (lambda: ss.VPolytope([0, 1, 2]), ValueError, r"^points must be a 2-D matrix of shape \(k, n\), one "
                                                  r"point per row; got an array of shape \(3,\)"),
    (lambda: ss.VPolytope(np.ones((2, 2), dtype=bool)), TypeError, r"^points must .*booleans"),
    (lambda: ss.Zonotope([1, 2], [0, 0]), ValueError, r"^G must be a 2-D matrix of shape \(n, ng\), one "
                                                      r"generator per column; got an array of shape \(2,\)"),
    (lambda: ss.Zonotope(np.eye(2), [[0], [0]]), ValueError, r"^c must be a vector of shape \(2,\)"),
])
def test_a_set_refuses_what_it_would_have_to_guess(make, exc, match):
    with pytest.raises(exc, match=match):
        make()


@pytest.mark.parametrize("S", [ss.Box([0.0], [1.0]), ss.Zonotope([[1.0]], [0.0]),
                               ss.Ellipsoid([0.0], [[1.0]])], ids=["Box", "Zonotope", "Ellipsoid"])
@pytest.mark.parametrize("size, exc", [(-3, ValueError), (2.5, TypeError), (True, TypeError)])
def test_sample_names_the_count_it_refuses(S, size, exc):
    with pytest.raises(exc, match=rf"^size must be a non-negative integer \(a number of points\), got {size}"):
        S.sample(np.random.default_rng(0), size)


def test_sampling_zero_points_gives_an_empty_array():
    assert ss.Box([0.0, 0.0], [1.0, 1.0]).sample(np.random.default_rng(0), 0).shape == (0, 2)


# -- user-defined sets -------------------------------------------------------------------------

class Ring(ss.ConvexSet):
    """Not convex: 1 ≤ ‖x‖ ≤ 2."""

    dim = 2

    def constraints(self, x):
        return [cp.norm(x) >= 1, cp.norm(x) <= 2]


class Answer(ss.ConvexSet):
    dim = 1

    def constraints(self, x):
        return [True]


@pytest.mark.parametrize("query", [lambda S: S.support([1.0, 0.0]), lambda S: S.contains([1.5, 0.0]),
                                   lambda S: (S + ss.Box([0, 0], [1, 1])).support([1.0, 0.0])],
                         ids=["support", "contains", "inside a lazy sum"])
def test_a_non_convex_user_set_is_named_at_its_first_query(query):
    with pytest.raises(TypeError, match=r"^Ring\.constraints\(x\) returned a constraint that is not convex "
                                        r"under CVXPY's DCP rules: 1\.0 <= "):
        query(Ring())


def test_a_user_set_must_return_cvxpy_constraints():
    with pytest.raises(TypeError, match=r"^Answer\.constraints\(x\) must return CVXPY constraints, got a bool"):
        Answer().support([1.0])


# -- packaging ---------------------------------------------------------------------------------

def test_the_license_is_an_spdx_expression_that_setuptools_reads_without_deprecation():
    tomllib = pytest.importorskip("tomllib")
    config = tomllib.loads((pathlib.Path(__file__).parents[1] / "pyproject.toml").read_text())
    assert config["project"]["license"] == "BSD-3-Clause"
    assert "setuptools>=77" in config["build-system"]["requires"]  # PEP 639 support
