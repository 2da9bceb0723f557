"""How ``setsmooth figures`` runs its scripts: the longest first, after what they read, W computing at
once, with a progress bar that counts every Monte Carlo run as a task."""

from __future__ import annotations

import functools
import json
import multiprocessing
import queue
import sys
import textwrap

import pytest

from setsmooth import montecarlo
from setsmooth.runs import cli, schedule, slots
from setsmooth.runs.figure_processes import ForwardedBar, Progress, _finish, run_scheduled


def test_scripts_start_in_decreasing_order_of_their_measured_cost_and_unmeasured_ones_last():
    costs = {"fig_a": 3.0, "fig_b": 200.0, "fig_c": 40.0}
    assert schedule.plan(["fig_a", "fig_b", "fig_c", "new_2", "new_1"], costs) == \
        ["fig_b", "fig_c", "fig_a", "new_1", "new_2"]


def test_a_script_starts_after_the_scripts_whose_outputs_it_reads_even_through_unselected_ones():
    costs = {"first": 1.0, "middle": 1.0, "last": 1.0, "big": 100.0}
    after = {"middle": ("first",), "last": ("middle",)}
    # `last` waits for `first` through `middle`, which is not selected.
    assert schedule.prerequisites(["last", "first", "big"], after) == {"last": {"first"}, "first": set(),
                                                                      "big": set()}
    assert schedule.plan(["last", "first", "big"], costs, after) == ["big", "first", "last"]
    # A cheap script with a long chain behind it goes before a dearer one without.
    chain = {"first": 1.0, "last": 90.0, "big": 50.0}
    assert schedule.plan(["last", "first", "big"], chain, {"last": ("first",)}) == ["first", "last", "big"]


def test_a_cycle_of_after_declarations_is_refused():
    with pytest.raises(ValueError, match="cycle"):
        schedule.plan(["a", "b"], {}, {"a": ("b",), "b": ("a",)})


def test_the_paper_figures_run_after_the_figures_they_read_and_their_costs_name_real_scripts():
    figures_dir = cli.find_figures_dir()
    names = cli.discover(figures_dir)
    costs = schedule.read_costs(figures_dir)
    assert costs and set(costs) <= set(names)
    order = schedule.plan(names, costs, schedule.read_after(figures_dir, names))
    position = order.index
    assert position("smoothing_fig3") < position("smoothing_fig5")
    assert position("smoothing_fig4") < position("smoothing_fig5")
    assert position("lsu_fig1") < position("lsu_fig2") < position("lsu_fig3") < position("lsu_tables")
    assert order[0] == max(costs, key=lambda name: schedule.priorities(
        names, costs, schedule.prerequisites(names, schedule.read_after(figures_dir, names)))[name])


def _trial(rng):
    return float(rng.random())


def test_progress_counts_each_script_and_each_monte_carlo_run_as_a_task():
    messages = queue.Queue()
    bar = functools.partial(ForwardedBar, messages=messages, name="fig")
    montecarlo.run(_trial, 5, 0, executor="serial", progress=bar)
    montecarlo.run(_trial, 2, 1, executor="serial", progress=bar)
    progress = Progress(scripts=2, show=False)
    progress.started("fig")
    while not messages.empty():
        _finish(messages.get(), {}, {}, progress, print)
    assert (progress.done, progress.total) == (7, 2 + 7)
    _finish(("done", "fig", 1.0, []), {}, {}, progress, lambda text: None)
    assert (progress.done, progress.total, progress.finished_scripts) == (8, 9, 1)


def test_slots_are_held_by_workers_and_lent_by_their_owner_while_it_waits():
    semaphore = multiprocessing.get_context("spawn").Semaphore(1)
    saved = slots._semaphore, slots._owner
    try:
        slots.install(semaphore)
        semaphore.acquire()                      # the owner's own slot
        with slots.held():                       # in the owner: no second slot taken (no deadlock)
            pass
        with slots.lent():
            assert semaphore.acquire(timeout=0.1)   # a worker can take the lent slot
            semaphore.release()
        assert not semaphore.acquire(timeout=0.01)  # taken back by the owner
    finally:
        slots._semaphore, slots._owner = saved


SCRIPT = '''
import json
from setsmooth import montecarlo

NAME = "{name}"
PAPER = "demo"
DEFAULT_RUNS = 3
AFTER = {after!r}


def trial(rng):
    return float(rng.random())


def main(runs=DEFAULT_RUNS, seed=0, out=None, workers=None, progress=True, executor=None):
    for other in AFTER:   # what it reads must be there
        json.loads((out / f"{{other}}.json").read_text())
    values = montecarlo.run(trial, runs, seed, executor=executor, progress=progress, workers=workers)
    (out / f"{{NAME}}.json").write_text(json.dumps(values))
    return {{"rows": [{{"quantity": "first run", "paper": "-", "ours": values[0]}}]}}
'''


POOLED = '''
import json, os
from setsmooth import montecarlo
from setsmooth.runs import slots

NAME = "demo_pooled"
PAPER = "demo"
DEFAULT_RUNS = 4


def trial(rng):
    return [slots.installed(), os.getppid()]


def main(runs=DEFAULT_RUNS, seed=0, out=None, workers=None, progress=True, executor=None):
    seen = montecarlo.run(trial, runs, seed, executor=executor, progress=progress, workers=workers)
    (out / f"{NAME}.json").write_text(json.dumps({"script": os.getpid(), "runs": seen}))
    return {"rows": []}
'''


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="pool workers fork from the script on Linux")
def test_the_monte_carlo_workers_of_a_scheduled_script_are_its_children_and_compute_in_its_slots(tmp_path):
    figures_dir, out = tmp_path / "figures", tmp_path / "out"
    figures_dir.mkdir()
    out.mkdir()
    (figures_dir / "demo_pooled.py").write_text(POOLED)
    (figures_dir / "demo_other.py").write_text(textwrap.dedent(SCRIPT.format(name="demo_other", after=())))
    outcome = run_scheduled(["demo_pooled", "demo_other"], figures_dir, out, None, 0, 2, False, {}, {}, {}, 1,
                            echo=lambda text: None)
    assert all(isinstance(seconds, float) for seconds in outcome.values())
    seen = json.loads((out / "demo_pooled.json").read_text())
    assert seen["runs"] == [[True, seen["script"]]] * 4


def test_scheduled_scripts_run_in_their_own_processes_longest_first_and_after_what_they_read(tmp_path):
    figures_dir, out = tmp_path / "figures", tmp_path / "out"
    figures_dir.mkdir()
    out.mkdir()
    for name, after in (("demo_reads", ("demo_long",)), ("demo_long", ()), ("demo_alone", ())):
        (figures_dir / f"{name}.py").write_text(textwrap.dedent(SCRIPT.format(name=name, after=after)))
    names = ["demo_alone", "demo_long", "demo_reads"]
    lines: list[str] = []
    outcome = run_scheduled(names, figures_dir, out, 4, 0, 2, False, {"demo_long": 9.0, "demo_alone": 1.0},
                            schedule.read_after(figures_dir, names), {}, 1, echo=lines.append)
    assert list(outcome) == ["demo_long", "demo_alone", "demo_reads"]      # the order they started in
    assert all(isinstance(seconds, float) for seconds in outcome.values()), lines
    serial = montecarlo.run(_trial, 4, 0, executor="serial", progress=False)
    assert json.loads((out / "demo_reads.json").read_text()) == serial     # seeds do not depend on processes
    assert any(line.startswith("== demo_reads") and "first run" in line for line in lines)


def test_a_call_records_the_cpu_seconds_of_its_scripts_in_the_format_the_order_reads(tmp_path):
    (tmp_path / "fig_a.json").write_text(json.dumps({"rows": [], "cpu_time_s": 12.345}))
    (tmp_path / "fig_b.json").write_text(json.dumps({"rows": [], "cpu_time_s": None}))   # Windows: unknown
    schedule.record_costs(tmp_path, ["fig_a", "fig_b", "fig_failed"], None)
    assert schedule.read_costs(tmp_path) == {"fig_a": 12.3}
