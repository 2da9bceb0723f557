"""The arena flags unsound estimators, shows registered ones beside the built-ins, and is reproducible.

Tiny horizons and one or two serial runs: the whole file takes a few seconds.
"""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import arena
from setsmooth.arena.estimators import check_estimators
from setsmooth.runs import cli


def shrunk_exact_filter(system, X0, ys):
    """The exact filter's hulls shrunk by 1 % about their centres: unsound by construction."""
    exact = ss.classical_filter(system, X0, ys)
    centre, radius = (exact.lo + exact.hi) / 2, (exact.hi - exact.lo) / 2
    return SimpleNamespace(lo=centre - 0.99 * radius, hi=centre + 0.99 * radius)


def interval_hull_filter(system, X0, ys):
    """The classical filter reduced to its interval hull at every step: outer bounds."""
    return ss.classical_filter(system, X0, ys, reduce=ss.IntervalHull())


@pytest.fixture
def registered():
    added = [arena.register("shrunk_1pct", shrunk_exact_filter),
             arena.register("interval_hull_filter", interval_hull_filter)]
    yield [e.name for e in added]
    for e in added:
        arena.unregister(e.name)


@pytest.fixture(scope="module")
def small():
    """Two serial runs of example (31) over five steps, with the two estimators registered."""
    arena.register("shrunk_1pct", shrunk_exact_filter)
    arena.register("interval_hull_filter", interval_hull_filter)
    try:
        return arena.run_arena(["example31"], ["exact_filter", "shrunk_1pct", "interval_hull_filter"],
                               runs=2, seed=3, horizon=4, executor="serial", progress=False)
    finally:
        arena.unregister("shrunk_1pct")
        arena.unregister("interval_hull_filter")


def _row(result, estimator):
    return next(r for r in result.rows if r["estimator"] == estimator)


def test_an_estimator_shrinking_the_exact_posterior_by_one_percent_is_flagged_unsound(small):
    shrunk = _row(small, "shrunk_1pct")
    assert shrunk["sound"] is False
    assert shrunk["containment_failures"] == 2              # every run, whatever the truth did
    assert shrunk["containment_gap"] == pytest.approx(0.005, rel=1e-6)   # 1 % of the radius, per side
    assert small.unsound() == [("example31", "shrunk_1pct")]
    assert "**UNSOUND**" in next(line for line in arena.markdown_table(small).splitlines()
                                 if "shrunk_1pct" in line)


def test_the_exact_filter_is_sound_and_its_own_reference(small):
    exact = _row(small, "exact_filter")
    assert exact["sound"] is True and exact["outside"] == 0 and exact["containment_failures"] == 0
    assert exact["volume_ratio"] == pytest.approx(1.0)


def test_a_registered_estimator_appears_in_the_table_beside_the_built_ins(small):
    row = _row(small, "interval_hull_filter")
    assert row["sound"] is True and row["runs"] == 2
    assert row["volume_ratio"] >= 1.0 and row["mean_radius"] >= _row(small, "exact_filter")["mean_radius"]
    table = arena.markdown_table(small)
    assert "| example31 | interval_hull_filter | 2 |" in table
    assert "| example31 | exact_filter | 2 |" in table


def test_registering_a_taken_name_or_a_non_callable_is_refused(registered):
    with pytest.raises(ValueError, match="already registered"):
        arena.register("exact_filter", shrunk_exact_filter)
    with pytest.raises(TypeError, match="callable"):
        arena.register("nothing", None)
    assert set(registered) <= set(arena.ESTIMATORS)


def test_unknown_problem_or_estimator_names_the_argument_and_the_choices():
    with pytest.raises(ValueError, match=r"problems: unknown problem 'nope'; choose from example31"):
        arena.run_arena(["nope"], ["exact_filter"], runs=1)
    with pytest.raises(ValueError, match=r"estimators: unknown estimator 'nope'; choose from exact_filter"):
        arena.run_arena(["example31"], ["nope"], runs=1)


def test_a_problem_is_fixed_by_its_seed():
    a, b = arena.make_problem("cz_noise", 5, horizon=3), arena.make_problem("cz_noise", 5, horizon=3)
    assert np.array_equal(a.xs, b.xs) and np.array_equal(a.ys, b.ys)
    assert np.array_equal(a.system.A_at(0), b.system.A_at(0))
    assert not np.array_equal(a.ys, arena.make_problem("cz_noise", 6, horizon=3).ys)


def test_the_command_writes_the_json_the_table_and_the_figure(tmp_path, capsys):
    status = cli.main(["arena", "--problems", "example31", "--estimators", "exact_filter,oit_cz",
                       "--runs", "1", "--horizon", "3", "--out", str(tmp_path), "--no-progress"])
    assert status == 0
    record = json.loads((tmp_path / "arena.json").read_text())
    assert [r["estimator"] for r in record["rows"]] == ["exact_filter", "oit_cz"]
    assert all(r["sound"] for r in record["rows"])
    assert (tmp_path / "arena.png").stat().st_size > 0
    assert "| example31 | oit_cz | 1 |" in (tmp_path / "arena.md").read_text()
    assert "| example31 | oit_cz | 1 |" in capsys.readouterr().out


def test_the_command_fails_when_an_estimator_is_unsound(tmp_path, capsys, registered):
    status = cli.main(["arena", "--problems", "example31", "--estimators", "shrunk_1pct",
                       "--runs", "1", "--horizon", "3", "--out", str(tmp_path), "--no-progress",
                       "--workers", "1"])
    assert status == 1
    assert "unsound: shrunk_1pct on example31" in capsys.readouterr().err


def test_a_row_does_not_depend_on_the_other_problems_chosen():
    """Each problem's data come from a generator keyed by its name: adding a problem changes no row."""
    alone = arena.run_arena(["cz_noise"], ["reduced_girard"], runs=1, seed=2, horizon=3,
                            executor="serial", progress=False)
    beside = arena.run_arena(["example31", "cz_noise"], ["reduced_girard"], runs=1, seed=2, horizon=3,
                             executor="serial", progress=False)
    row = _row(alone, "reduced_girard")
    other = next(r for r in beside.rows if r["problem"] == "cz_noise")
    assert (row["mean_radius"], row["volume_ratio"]) == (other["mean_radius"], other["volume_ratio"])


def test_heavy_estimators_and_problems_run_only_when_named():
    default = check_estimators(None)
    assert "recursion_smoother" not in default and "lsup" not in default and "exact_filter" in default
    assert "random30" not in arena.problem_names() and "random30" in arena.problem_names(include_heavy=True)


def test_the_hausdorff_gap_is_zero_for_the_exact_filter_and_positive_for_its_interval_hulls(small):
    assert _row(small, "exact_filter")["hausdorff_gap"] == 0.0
    assert _row(small, "interval_hull_filter")["hausdorff_gap"] > 1e-3    # the boxes reach past the polygons


def test_the_lsu_filters_bound_the_exact_posterior_of_a_linear_system():
    """The LSU model holds the system's noises in boxes, so LSU-CZ/LSUO/LSUP sets are outer bounds."""
    result = arena.run_arena(["lsu41", "stability26"], ["lsu_cz", "lsuo", "lsup"], runs=1, seed=1,
                             horizon=4, executor="serial", progress=False)
    assert all(row["sound"] is True for row in result.rows), arena.markdown_table(result)


def test_rethinking_30_draws_one_process_noise_for_every_step():
    p = arena.make_problem("rethinking30", 4, horizon=6)
    A = p.system.A_at(0)
    pushes = p.xs[1:] - p.xs[:-1] @ A.T              # E w_k, k = 0..5
    assert np.allclose(pushes, pushes[0], atol=1e-12) and np.abs(pushes[0]).max() > 0


def test_the_nonlinear_example_33_runs_with_the_interval_estimators_and_is_sound_on_a_few_seeds():
    result = arena.run_arena(["example33"], ["interval_filter", "interval_smoother"], runs=4, seed=7,
                             horizon=12, executor="serial", progress=False)
    filtered, smoothed = _row(result, "interval_filter"), _row(result, "interval_smoother")
    for row in (filtered, smoothed):
        assert row["applicable"] and row["sound"] is True and row["runs"] == 4 and row["errors"] == 0
        assert row["outside"] == 0 and row["steps"] == 4 * 13
        assert not row["containment_checked"]          # nothing exact is registered for a nonlinear system
    assert 0 < smoothed["mean_radius"] < filtered["mean_radius"] < 0.5    # (34) alone pins x_k to width 1
    assert "| example33 | interval_filter | 4 | 0/52 | no exact reference |" in arena.markdown_table(result)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_interval_filter_holds_the_true_state_of_example_33(seed):
    p = arena.make_problem("example33", seed, horizon=30)
    lo, hi = arena.hull_tubes(arena.ESTIMATORS["interval_filter"](p.system, p.X0, p.ys))
    assert lo.shape == p.xs.shape and np.all(hi - lo > 0)
    assert np.all((lo <= p.xs + 1e-12) & (p.xs <= hi + 1e-12))


calls = []


def linear_only(system, X0, ys):
    """A linear estimator that records its calls: it must never see example (33)."""
    calls.append(type(system).__name__)
    return ss.classical_filter(system, X0, ys)


def test_an_inapplicable_pair_is_reported_as_such_and_never_run():
    arena.register("linear_only", linear_only)
    calls.clear()
    try:
        result = arena.run_arena(["example33", "example31"], ["linear_only", "interval_filter"], runs=1,
                                 seed=0, horizon=3, executor="serial", progress=False)
    finally:
        arena.unregister("linear_only")
    assert calls == ["LinearSystem"]                      # run on example31 only: decided, not caught
    na = [(r["problem"], r["estimator"]) for r in result.rows if not r["applicable"]]
    assert na == [("example33", "linear_only"), ("example31", "interval_filter")]
    row = next(r for r in result.rows if r["problem"] == "example33" and r["estimator"] == "linear_only")
    assert row["sound"] is None and row["error"] is None and row["runs"] == 0
    assert "example33 is scalar_monotone" in row["not_applicable"]
    assert result.unsound() == []
    line = next(line for line in arena.markdown_table(result).splitlines()
                if line.startswith("| example33 | linear_only |"))
    assert "n/a" in line and "error" not in line


def test_the_interval_filter_is_registered_and_bounds_the_exact_filter_of_a_scalar_linear_system():
    assert {"interval_filter", "interval_smoother"} <= set(check_estimators(None))
    assert "example33" in arena.problem_names() and "scalar_linear" in arena.problem_names()
    result = arena.run_arena(["scalar_linear"], ["exact_filter", "interval_filter", "interval_smoother"],
                             runs=2, seed=4, horizon=8, executor="serial", progress=False)
    for name in ("interval_filter", "interval_smoother"):
        row = _row(result, name)
        assert row["sound"] is True and row["outside"] == 0 and row["containment_failures"] == 0
        # exact for a scalar system with A > 0: the exact filter's (smoother's) hulls, up to rounding
        assert row["volume_ratio"] == pytest.approx(1.0, rel=1e-6)
    assert _row(result, "interval_smoother")["mean_radius"] < _row(result, "interval_filter")["mean_radius"]


def test_the_interval_filter_refuses_a_system_it_does_not_apply_to_in_the_users_words():
    p = arena.make_problem("example31", 0, horizon=2)
    with pytest.raises(ValueError, match=r"scalar system \(n = 1\).*got n = 2"):
        arena.ESTIMATORS["interval_filter"](p.system, p.X0, p.ys)
    flipped = ss.LinearSystem([[-0.5]], None, [[1.0]], W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]))
    with pytest.raises(ValueError, match=r"A = -0.5 is not > 0"):
        arena.ESTIMATORS["interval_filter"](flipped, ss.Box([-1.0], [1.0]), np.zeros((3, 1)))


def test_registering_an_unknown_structure_is_refused():
    with pytest.raises(ValueError, match="applies_to must name structures among"):
        arena.register("nowhere", linear_only, applies_to="nonlinear")
    assert "nowhere" not in arena.ESTIMATORS


def test_the_command_lists_an_inapplicable_pair_as_not_applicable(tmp_path, capsys):
    status = cli.main(["arena", "--problems", "example33", "--estimators", "exact_filter,interval_filter",
                       "--runs", "1", "--horizon", "5", "--out", str(tmp_path), "--no-progress"])
    assert status == 0
    rows = json.loads((tmp_path / "arena.json").read_text())["rows"]
    assert [(r["estimator"], r["applicable"]) for r in rows] == [("exact_filter", False),
                                                                 ("interval_filter", True)]
    assert "| example33 | exact_filter | 0 | n/a | n/a |" in capsys.readouterr().out
