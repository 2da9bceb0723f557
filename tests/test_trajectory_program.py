"""The trajectory set of sets without a CZ form (`TrajectorySet`): the recursion's sets, one program."""

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.solvers import generic
from setsmooth.filters.steps import predict, update
from setsmooth.sets.constraint_only import L1Ball, VertexHull
from setsmooth.trajectories import TrajectorySet
from setsmooth.trajectories.generic_program import FilteredState
from tests.estimation_helpers import example_31

DIRECTIONS = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 1.0], [1.0, -2.0]])


def _system(kind):
    base = example_31()
    square = VertexHull([[-1, -1], [1, -1], [1, 1], [-1, 1.2]])
    W, V = {"ellipsoid": (ss.Ellipsoid([0.1], [[0.8]]), base.V),
            "custom": (L1Ball([0.0], 1.0), square),
            "ellipsoid_V": (base.W, ss.Ellipsoid([0.0, 0.1], [[1.0, 0.2], [0.2, 0.5]]))}[kind]
    return ss.LinearSystem(base.A_at(0), None, base.C_at(0), E=base.E_at(0), F=base.F_at(0), W=W, V=V)


def _recursion_filter(sys, X0, ys):
    """The classical filter's recursion (stability (3)–(4)) step by step, through the public steps."""
    posteriors = [update(sys, 0, X0, ys[0])]
    for k in range(1, len(ys)):
        posteriors.append(update(sys, k, predict(sys, k - 1, posteriors[-1]), ys[k]))
    return posteriors


@pytest.mark.parametrize("kind", ["ellipsoid", "custom", "ellipsoid_V"])
def test_trajectory_smoother_of_non_cz_sets_equals_the_recursion(kind):
    sys = _system(kind)
    X0 = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2), [[1.0, 1.0]]]), [3, 3, 3, 3, 4.0])
    xs, ys = ss.simulate(sys, ss.Box([-2, -2], [2, 2]), 5, np.random.default_rng(7))
    traj = ss.optimal_smoother(sys, X0, ys, method="trajectory")
    # The recursion of Algorithm 1 on the recursion filter's posteriors: no trajectory program in it.
    rec = ss.optimal_smoother(sys, X0, ys, method="recursion", posteriors=_recursion_filter(sys, X0, ys))
    for k, (a, r) in enumerate(zip(traj, rec)):
        va, vr = a.support_many(DIRECTIONS), r.support_many(DIRECTIONS)
        assert np.all(np.abs(va - vr) <= 1e-6 * np.maximum(1.0, np.abs(vr))), (k, va, vr)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_true_states_lie_in_the_smoothed_ranges_of_custom_noises(seed):
    sys = _system("custom")
    X0 = ss.Box([-3, -3], [3, 3])
    xs, ys = ss.simulate(sys, X0, 12, np.random.default_rng(seed))
    smoothed = ss.optimal_smoother(sys, X0, ys)
    for k, S in enumerate(smoothed):
        hull = S.interval_hull()
        assert np.all(hull.lo <= xs[k] + 1e-6) and np.all(xs[k] <= hull.hi + 1e-6), k


def test_filtering_map_of_custom_sets_is_the_classical_filter_posterior():
    sys = _system("custom")
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, X0, 4, np.random.default_rng(3))
    posts = ss.classical_filter(sys, X0, ys)
    for k in (0, 2, 4):
        F = ss.filtering_map(sys, X0, ys, 0, k)
        vf, vp = F.support_many(DIRECTIONS), posts[k].support_many(DIRECTIONS)
        assert np.all(np.abs(vf - vp) <= 1e-6 * np.maximum(1.0, np.abs(vp))), k


def test_every_projection_is_answered_by_one_compiled_problem(monkeypatch):
    built = []
    original = generic.GenericProgram.__init__

    def counting(self, convex_set):
        built.append(type(convex_set).__name__)
        original(self, convex_set)

    monkeypatch.setattr(generic.GenericProgram, "__init__", counting)
    sys = _system("ellipsoid")
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, X0, 6, np.random.default_rng(4))
    smoothed = ss.optimal_smoother(sys, X0, ys)
    for S in smoothed:
        S.interval_hull()
    assert built.count("TrajectorySet") == 1
    assert len({id(S.S) for S in smoothed}) == 1


def test_an_unobserved_direction_of_an_unbounded_prior_is_unbounded():
    # x[1] is never measured and never moves x[0]: with X0 = ℝ² its smoothed range is unbounded.
    sys = ss.LinearSystem(np.eye(2), None, [[1.0, 0.0]], W=ss.Ellipsoid([0.0, 0.0], 0.1 * np.eye(2)),
                          V=L1Ball([0.0], 1.0))
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(5))
    smoothed = ss.optimal_smoother(sys, ss.Reals(2), ys)
    values = smoothed[1].support_many(np.array([[1.0, 0.0], [0.0, 1.0]]))
    assert np.isfinite(values[0]) and values[1] == np.inf


def test_inconsistent_measurements_make_every_projection_empty():
    sys = _system("custom")
    ys = np.array([[0.0, 0.0], [50.0, -50.0], [0.0, 0.0]])
    traj = ss.trajectory_set(sys, ss.Box([-1, -1], [1, 1]), ys)
    assert isinstance(traj, TrajectorySet)
    assert traj.state(1).is_empty()
    assert traj.state(2).support([1.0, 0.0]) == -np.inf


def test_sets_with_a_cz_form_keep_the_sparse_cz():
    sys = example_31()
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(6))
    assert isinstance(ss.trajectory_set(sys, ss.Box([-1, -1], [1, 1]), ys), ss.ConstrainedZonotope)


@pytest.mark.parametrize("kind", ["ellipsoid", "custom", "ellipsoid_V"])
def test_filter_of_non_cz_sets_equals_the_recursion(kind):
    sys = _system(kind)
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, ss.Box([-2, -2], [2, 2]), 5, np.random.default_rng(8))
    posteriors = ss.classical_filter(sys, X0, ys)
    assert all(isinstance(P, FilteredState) for P in posteriors)
    for k, (P, R) in enumerate(zip(posteriors, _recursion_filter(sys, X0, ys))):
        vp, vr = P.support_many(DIRECTIONS), R.support_many(DIRECTIONS)
        assert np.all(np.abs(vp - vr) <= 1e-6 * np.maximum(1.0, np.abs(vr))), (k, vp, vr)


def test_all_filtered_ranges_share_one_compiled_program(monkeypatch):
    from setsmooth.trajectories import generic_program

    built = []
    original = generic_program._FilterProgram.__init__

    def counting(self, traj):
        built.append(traj)
        original(self, traj)

    monkeypatch.setattr(generic_program._FilterProgram, "__init__", counting)
    sys = _system("custom")
    X0 = ss.Box([-3, -3], [3, 3])
    xs, ys = ss.simulate(sys, X0, 8, np.random.default_rng(9))
    posteriors = ss.classical_filter(sys, X0, ys)
    for k, P in enumerate(posteriors):
        hull = P.interval_hull()
        assert np.all(hull.lo <= xs[k] + 1e-6) and np.all(xs[k] <= hull.hi + 1e-6), k
    assert len(built) == 1


@pytest.mark.parametrize("bad_step", [0, 3, 5])
def test_filter_finds_the_first_empty_posterior_as_the_recursion_does(bad_step):
    sys = _system("custom")
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 5, np.random.default_rng(10))
    ys = ys.copy()
    ys[bad_step] += 100.0  # no state explains this measurement
    posteriors = ss.classical_filter(sys, X0, ys)
    recursion = _recursion_filter(sys, X0, ys)
    for k, (P, R) in enumerate(zip(posteriors, recursion)):
        assert isinstance(P, ss.EmptySet) == (k >= bad_step), k
        assert R.is_empty() == (k >= bad_step), k
    undetected = ss.classical_filter(sys, X0, ys, detect_empty=False)
    assert all(isinstance(P, FilteredState) for P in undetected)
    assert [P.is_empty() for P in undetected] == [k >= bad_step for k in range(6)]


def test_filter_with_an_unbounded_prior_keeps_the_recursion():
    sys = _system("custom")
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(11))
    posteriors = ss.classical_filter(sys, ss.Reals(2), ys)
    assert not any(isinstance(P, FilteredState) for P in posteriors)
    assert np.isfinite(posteriors[-1].support([1.0, 0.0]))


def test_a_filtered_range_states_its_own_constraints():
    # constraints(x) is the exact set too (used by the set algebra and the generic path).
    sys = _system("ellipsoid")
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 4, np.random.default_rng(12))
    P = ss.classical_filter(sys, X0, ys)[3]
    assert np.allclose(P.support_many(DIRECTIONS), P.support_many(DIRECTIONS, path="generic"),
                       rtol=1e-6, atol=1e-6)
    with pytest.raises(ValueError, match="certified"):
        P.interval_hull(certified=True)


def test_filtered_and_smoothed_ranges_pickle_after_queries():
    import pickle

    sys = _system("ellipsoid")
    X0 = ss.Box([-3, -3], [3, 3])
    _, ys = ss.simulate(sys, ss.Box([-1, -1], [1, 1]), 3, np.random.default_rng(14))
    P = ss.classical_filter(sys, X0, ys)[2]
    S = ss.optimal_smoother(sys, X0, ys)[1]
    for R in (P, S):
        before = R.support_many(DIRECTIONS)
        copy = pickle.loads(pickle.dumps(R))
        assert np.allclose(copy.support_many(DIRECTIONS), before, rtol=1e-7, atol=1e-7)
