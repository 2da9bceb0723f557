"""Result objects of filters and smoothers: still the list of sets, plus tubes, checks and provenance."""

import pickle
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.sets.empty import EmptySet  # noqa: E402
from tests.estimation_helpers import example_31  # noqa: E402

X0 = ss.Box([-5, -5], [5, 5])


@pytest.fixture(scope="module")
def run():
    system = example_31()
    xs, ys = ss.simulate(system, X0, 12, np.random.default_rng(4))
    filtered = ss.classical_filter(system, X0, ys)
    smoothed = ss.optimal_smoother(system, X0, ys)
    return system, xs, ys, filtered, smoothed


def test_results_still_behave_as_lists_of_sets(run):
    system, _, ys, filtered, smoothed = run
    for result in (filtered, smoothed):
        assert isinstance(result, list) and len(result) == len(ys)
        assert all(isinstance(S, ss.ConvexSet) for S in result)
        assert isinstance(result[2:4], list) and len(result[2:4]) == 2
    assert filtered.kind == "filtered" and smoothed.kind == "smoothed"
    assert filtered.system is system and np.array_equal(filtered.ys, ys)


def test_tubes_are_the_interval_hulls_of_the_sets(run):
    _, _, _, filtered, smoothed = run
    for result in (filtered, smoothed):
        assert result.lo.shape == result.hi.shape == (13, 2)
        for k in (0, 6, 12):
            generic = result[k].interval_hull(path="generic")  # an independent CVXPY computation
            assert np.allclose(result.lo[k], generic.lo, atol=1e-6)
            assert np.allclose(result.hi[k], generic.hi, atol=1e-6)
        assert np.allclose(result.centers, (result.lo + result.hi) / 2)


def test_diameters_in_the_inf_and_2_norms(run):
    _, _, _, filtered, smoothed = run
    assert np.allclose(filtered.diameters(), [S.diameter() for S in filtered])
    assert np.allclose(filtered.diameters(2), np.linalg.norm(filtered.hi - filtered.lo, axis=1))
    assert np.all(filtered.diameters(2) >= filtered.diameters(np.inf) - 1e-12)
    assert np.all(smoothed.diameters() <= filtered.diameters() + 1e-6)
    with pytest.raises(ValueError, match="norm must be inf or 2"):
        filtered.diameters(1)


def test_true_trajectory_is_contained_and_a_shifted_one_is_not(run):
    _, xs, _, filtered, smoothed = run
    assert filtered.contains_trajectory(xs).all() and smoothed.contains_trajectory(xs).all()
    shifted = xs + np.array([0.0, 10.0])
    assert not smoothed.contains_trajectory(shifted).any()
    with pytest.raises(ValueError, match=r"xs must have shape \(13, 2\)"):
        filtered.contains_trajectory(xs[:5])


def test_first_empty_step_of_inconsistent_data():
    system = example_31()
    xs, ys = ss.simulate(system, X0, 8, np.random.default_rng(0))
    assert ss.classical_filter(system, X0, ys).first_empty is None
    ys = ys.copy()
    ys[5] += 100.0  # no state explains this measurement
    filtered = ss.classical_filter(system, X0, ys)
    assert filtered.first_empty == 5
    assert all(isinstance(S, EmptySet) for S in filtered[5:]) and not filtered[4].is_empty()
    assert np.isnan(filtered.lo[5:]).all() and np.isnan(filtered.diameters()[5:]).all()
    assert ss.optimal_smoother(system, X0, ys).first_empty == 0


def test_smoother_refuses_posteriors_of_other_data(run):
    system, _, ys, filtered, smoothed = run
    recursion = ss.optimal_smoother(system, X0, ys, posteriors=filtered)
    assert np.allclose(recursion.hi, smoothed.hi, atol=1e-6)
    other_ys = ys.copy()
    other_ys[3, 0] += 0.1
    with pytest.raises(ValueError, match="other measurements .*k = 3"):
        ss.optimal_smoother(system, X0, other_ys, posteriors=filtered)
    with pytest.raises(ValueError, match="another system"):
        ss.optimal_smoother(example_31(), X0, ys, posteriors=filtered)
    with pytest.raises(ValueError, match="another X0"):
        ss.optimal_smoother(system, ss.Box([-4, -5], [5, 5]), ys, posteriors=filtered)
    # an equal X0 written again is the same prior
    ss.optimal_smoother(system, ss.Box([-5, -5], [5, 5]), ys, posteriors=filtered)
    # a plain list carries no data and is taken on trust, as before
    assert len(ss.optimal_smoother(system, X0, ys, posteriors=list(filtered))) == len(ys)


def test_reduced_filter_results_are_marked_outer_and_so_is_their_smoothing(run):
    system, xs, ys, filtered, _ = run
    reduced = ss.classical_filter(system, X0, ys, reduce=ss.CORA_GIRARD)
    assert reduced.outer and not filtered.outer
    assert np.all(reduced.lo <= filtered.lo + 1e-7) and np.all(reduced.hi >= filtered.hi - 1e-7)
    assert ss.optimal_smoother(system, X0, ys, posteriors=reduced).outer


def test_hull_cache_follows_replaced_entries(run):
    system, _, ys, filtered, _ = run
    copy = ss.SetEstimates(filtered, system=system, X0=X0, ys=ys, kind="filtered")
    before = copy.hi[3].copy()
    copy[3] = ss.Box([0, 0], [1, 1])
    assert np.array_equal(copy.hi[3], [1, 1]) and not np.array_equal(before, [1, 1])


def test_plot_tubes_draws_one_tube_per_coordinate_between_lo_and_hi(run):
    _, xs, _, filtered, smoothed = run
    fig, axes = plt.subplots(2, 1)
    drawn = filtered.plot_tubes(axes, label="filtered")
    assert list(drawn) == list(axes)
    tubes = [a.collections[0] for a in drawn]
    assert smoothed.plot_tubes(drawn, truth=xs) == drawn       # the returned axes take the next tubes
    for i, tube in enumerate(tubes):
        ys_drawn = tube.get_paths()[0].vertices[:, 1]
        assert np.isclose(ys_drawn.min(), filtered.lo[:, i].min())
        assert np.isclose(ys_drawn.max(), filtered.hi[:, i].max())
    labels = axes[0].get_legend_handles_labels()[1]
    assert labels == ["filtered", "smoothed", "true state"]
    one = smoothed.plot_tubes(dims=[1])  # new axes when none are given
    assert len(one) == 1
    with pytest.raises(ValueError, match="one Axes per coordinate"):
        smoothed.plot_tubes(axes[0], dims=[0, 1])
    with pytest.raises(TypeError, match="ax must be a matplotlib Axes"):
        smoothed.plot_tubes(tubes, dims=[0, 1])                # artists are not axes
    with pytest.raises(ValueError, match=r"dims must be coordinates in \[0, 2\)"):
        smoothed.plot_tubes(dims=[2])
    plt.close("all")


def test_results_pickle_with_their_data(run):
    system, _, ys, filtered, _ = run
    filtered.hi  # fill the hull cache: it is dropped, not pickled
    back = pickle.loads(pickle.dumps(filtered))
    assert isinstance(back, ss.SetEstimates) and len(back) == len(filtered)
    assert back.kind == "filtered" and np.array_equal(back.ys, ys)
    assert np.allclose(back.hi, filtered.hi)


def test_references_cover_every_paper_the_code_cites():
    root = Path(__file__).resolve().parents[1]
    text = " ".join(p.read_text(encoding="utf-8") for p in (root / "setsmooth").rglob("*.py"))
    cited = {m.lower() for m in re.findall(r"\b(smoothing|stability|rethinking|LSU) paper\b", text, re.I)}
    assert cited and cited <= set(ss.references.PAPERS)
    readme = " ".join((root / "README.md").read_text(encoding="utf-8").split())  # lines rewrapped
    for ref in ss.references.PAPERS.values():
        assert ref.authors and ref.title and ref.venue and ref.year
        assert ref.title in ss.references.cite(ref.short_name)
        assert ref.title in readme
    with pytest.raises(KeyError, match="known"):
        ss.references.cite("kalman")


def test_interval_hulls_in_threads_are_the_serial_ones_and_kept_on_the_sets():
    """Threads split the projections of one trajectory set; each thread builds its own solver
    instances, so the hulls are those of a serial run, bit for bit, and are kept on the sets."""
    rng = np.random.default_rng(7)
    A = np.array([[0.9, 0.2, 0.0], [-0.2, 0.9, 0.1], [0.0, 0.0, 0.95]])
    B = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, 0.05]])
    W = ss.ConstrainedZonotope(np.array([[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]]), np.zeros(2),
                               A=[[1.0, 1.0, 1.0]], b=[1.0])  # the triangle CZ
    system = ss.LinearSystem(A, None, [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], E=B, W=W,
                             V=ss.Box([-0.5, -0.5], [0.5, 0.5]))
    X0 = ss.Box(-np.ones(3), np.ones(3))
    xs, ys = ss.simulate(system, X0, 30, rng)
    serial = ss.optimal_smoother(system, X0, ys).interval_hulls(certified=True)
    smoothed = ss.optimal_smoother(system, X0, ys)
    threaded = smoothed.interval_hulls(certified=True, workers=3)
    for a, b in zip(serial, threaded):
        assert np.array_equal(a.lo, b.lo) and np.array_equal(a.hi, b.hi)
    assert all(S.interval_hull(certified=True) is h for S, h in zip(smoothed, threaded))
    assert smoothed.contains_trajectory(xs).all()


@pytest.mark.parametrize("workers", [0, -1, 1.5, True, "2"])
def test_interval_hulls_refuses_a_bad_worker_count(run, workers):
    smoothed = run[4]
    with pytest.raises(ValueError, match="workers"):
        smoothed.interval_hulls(workers=workers)


def test_the_hulls_of_many_sets_show_their_progress_on_request(capsys):
    box = ss.Box([-1.0], [1.0])
    system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    ys = [[0.0], [0.5], [1.0]]
    ss.classical_filter(system, ss.Box([-5.0], [5.0]), ys).interval_hulls(progress=True)
    assert "interval hulls" in capsys.readouterr().err
    ss.classical_filter(system, ss.Box([-5.0], [5.0]), ys).interval_hulls(progress=False)
    assert capsys.readouterr().err == ""
