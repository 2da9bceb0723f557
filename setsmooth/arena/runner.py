"""The arena's Monte Carlo: every chosen estimator on every chosen problem, over seeded runs.

Run i draws its problems from the i-th child of the root seed (`setsmooth.montecarlo.run`), and each
problem from a grandchild keyed by the problem's name: a problem's data in run i are the same whichever
other problems and estimators are chosen, so a table can be extended without changing its rows.

Within a run, every estimator of a problem sees the same data, and its sets are compared with those of
the exact estimator of its kind (`REFERENCES`), computed once per run even when it is not itself in the
table. An estimator runs only on the problems it applies to (`Estimator.applies`, from its declared
``applies_to`` and the problem's ``structure``); the other pairs are rows marked not applicable, and a
problem no reference applies to (the nonlinear example (33)) has no exact reference. On 2-D problems
the comparison includes the Hausdorff distance of the sets themselves at `gap_steps`
(`setsmooth.arena.metrics.hausdorff_gap`).
"""

from __future__ import annotations

import functools
import time
import tracemalloc
import zlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.hausdorff import polytope_vertices
from ..runs import montecarlo
from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.empty import EmptySet
from . import metrics
from .estimators import ESTIMATORS, REFERENCES, Estimator, check_estimators, estimated_sets, hull_tubes
from .problems import PROBLEMS, Problem, check_problems, make_problem

__all__ = ["run_arena", "ArenaResult", "arena_trial", "measure", "gap_steps"]


@dataclass
class ArenaResult:
    """The arena's outcome: one row per (problem, estimator), and how it was produced.

    Attributes
    ----------
    rows : list of dict
        Aggregated over runs (see `summarize`): ``problem``, ``estimator``, ``kind``, ``applicable``
        (False: not run, the estimator does not apply to the problem's system), ``runs``, ``errors``,
        ``outside``, ``steps``, ``containment_failures``, ``containment_gap``,
        ``mean_radius``, ``volume_ratio``, ``hausdorff_gap`` (2-D problems), ``cpu_ms_per_step``,
        ``peak_mib``, ``sound``.
    runs : list of dict
        Per run: problem -> estimator -> the metrics of `measure`.
    config : dict
        problems, estimators, runs, seed, horizon.
    seconds : float
        Wall-clock time of the whole arena.
    """

    rows: list[dict]
    runs: list[dict]
    config: dict
    seconds: float = 0.0
    notes: list[str] = field(default_factory=list)

    def unsound(self) -> list[tuple[str, str]]:
        """The (problem, estimator) pairs flagged unsound."""
        return [(r["problem"], r["estimator"]) for r in self.rows if r["sound"] is False]


def run_arena(problems: Any = None, estimators: Any = None, runs: int = 3, seed: int = 0, *,
              horizon: int | None = None, executor: Any = None, workers: int | None = None,
              progress: bool = True, memory: bool = False) -> ArenaResult:
    """Run estimators on problems over seeded Monte Carlo runs and summarize soundness, tightness, time.

    Parameters
    ----------
    problems : sequence of str, optional
        Names from `setsmooth.arena.PROBLEMS`; default every problem not marked heavy.
    estimators : sequence of str, optional
        Names from `setsmooth.arena.ESTIMATORS` (built-ins and those added with `register`); default
        every one not marked heavy.
    runs : int
        Monte Carlo runs (each draws new data, and a new system for the random problems).
    seed : int or numpy.random.Generator
        Root seed: the same seed gives the same data and the same soundness and tightness figures.
    horizon : int, optional
        T for every problem; each problem's own default when None.
    executor, workers, progress
        As in `setsmooth.montecarlo.run` (None: a process pool of ``workers`` processes, in-process
        for a single run; ``'serial'``; an Executor; a Dask client).
    memory : bool
        Also record each estimator's peak Python memory (tracemalloc; it slows the estimators down,
        so their times are then not comparable with a run without it).

    Returns
    -------
    ArenaResult

    Raises
    ------
    ValueError
        For an unknown problem or estimator name (naming the valid choices), or ``runs < 1``.
    """
    problem_names = check_problems(problems, "problems")
    chosen = tuple(ESTIMATORS[name] for name in check_estimators(estimators, "estimators"))
    references = {kind: ESTIMATORS[name] for kind, name in REFERENCES.items()
                  if name in ESTIMATORS and any(e.kind == kind for e in chosen)}
    if horizon is not None and (isinstance(horizon, bool) or not isinstance(horizon, (int, np.integer))
                                or horizon < 0):
        raise ValueError(f"horizon must be a non-negative integer, got {horizon!r}")
    trial = functools.partial(arena_trial, problems=tuple(problem_names), estimators=chosen,
                              references=references, horizon=horizon, memory=bool(memory))
    start = time.perf_counter()
    per_run = montecarlo.run(trial, runs, seed, executor=executor, progress=progress, workers=workers)
    seconds = time.perf_counter() - start
    config = {"problems": problem_names, "estimators": [e.name for e in chosen], "runs": runs,
              "seed": seed if isinstance(seed, (int, np.integer)) else None, "horizon": horizon,
              "memory": bool(memory),
              "references": {kind: e.name for kind, e in references.items()}}
    rows = summarize(per_run, problem_names, chosen)
    return ArenaResult(rows, per_run, config, seconds)


def arena_trial(rng: np.random.Generator, problems: tuple[str, ...], estimators: tuple[Estimator, ...],
                references: dict[str, Estimator], horizon: int | None, memory: bool) -> dict:
    """One Monte Carlo run: problem -> estimator -> metrics (module level, so that it pickles)."""
    out: dict[str, dict] = {}
    for name in problems:
        problem = make_problem(name, _problem_generator(rng, name), horizon)
        applicable = [e for e in estimators if e.applies(problem.structure)]
        outputs = {e.name: _run_estimator(e, problem, memory) for e in applicable}
        exact = {}
        for kind, reference in references.items():
            if not reference.applies(problem.structure):
                continue
            result = outputs.get(reference.name) or _run_estimator(reference, problem, False)
            if "error" in result:
                continue
            exact[kind] = dict(result, source=result)
            if problem.xs.shape[1] == 2:       # the exact polygons, once for every estimator of the kind
                exact[kind]["polygons"] = {k: _polygon(_set_at(result, k))
                                           for k in gap_steps(problem.horizon)}
        out[name] = {e.name: measure(outputs[e.name], problem, exact.get(e.kind)) if e.name in outputs
                     else {"not_applicable": True} for e in estimators}
    return out


def gap_steps(horizon: int) -> list[int]:
    """The steps whose sets the Hausdorff gap compares: the middle of the horizon and its end (where
    a filter is judged; a smoother's sets are tightest away from the end)."""
    return sorted({horizon // 2, horizon})


def _problem_generator(rng: np.random.Generator, name: str) -> np.random.Generator:
    # A grandchild of the run's seed keyed by the problem's name (see the module docstring).
    run_seq = rng.bit_generator.seed_seq
    key = zlib.crc32(name.encode("utf-8"))
    return np.random.default_rng(np.random.SeedSequence(run_seq.entropy,
                                                        spawn_key=(*run_seq.spawn_key, key)))


def _run_estimator(estimator: Estimator, problem: Problem, memory: bool) -> dict:
    """Call the estimator, then read its hulls; CPU seconds of each (this process) and peak memory."""
    if memory:
        tracemalloc.start()
    try:
        t0 = time.process_time()
        estimates = estimator(problem.system, problem.X0, problem.ys)
        t1 = time.process_time()
        lo, hi = hull_tubes(estimates)
        t2 = time.process_time()
    except Exception as exc:  # an estimator that cannot run on a problem is a table entry, not a crash
        return {"error": f"{type(exc).__name__}: {exc}"}
    finally:
        peak = tracemalloc.get_traced_memory()[1] if memory else None
        if memory:
            tracemalloc.stop()
    if lo.shape != problem.xs.shape or hi.shape != problem.xs.shape:
        return {"error": f"hull tubes of shape {lo.shape}, expected {problem.xs.shape} (T+1, n)"}
    return {"lo": lo, "hi": hi, "cpu_step": t1 - t0, "cpu_hull": t2 - t1,
            "peak_mib": None if peak is None else peak / 2 ** 20, "estimates": estimates}


def _set_at(result: dict, k: int) -> ConvexSet:
    """The estimator's set at step k: its own, or its hull box when it gave tubes only."""
    sets = estimated_sets(result["estimates"])
    try:
        S = sets[k]
    except (TypeError, IndexError, KeyError):
        S = None
    if isinstance(S, ConvexSet):
        return S
    lo, hi = result["lo"][k], result["hi"][k]
    return EmptySet(lo.size) if np.isnan(lo).any() or np.isnan(hi).any() else Box(lo, hi)


def _polygon(S: ConvexSet) -> np.ndarray:
    """The vertices of a 2-D set, counter-clockwise; none for the empty set."""
    return np.zeros((0, 2)) if S.is_empty() else polytope_vertices(S)


def _hausdorff(S: ConvexSet, exact: np.ndarray) -> float:
    try:
        return metrics.hausdorff_gap(S, exact)
    except ValueError:      # an unbounded set (vertices_2d refuses it): infinitely far from the exact one
        return float("inf")


def measure(result: dict, problem: Problem, reference: dict | None) -> dict:
    """Metrics of one estimator's output on one problem (`setsmooth.arena.metrics`).

    ``reference`` is the exact estimator's output (as `_run_estimator` gives it) with ``source``, that
    output itself, and on 2-D problems ``polygons``, its sets' vertices at `gap_steps`; None when no
    exact estimator of the kind ran.
    """
    if "error" in result:
        return {"error": result["error"]}
    lo, hi = result["lo"], result["hi"]
    row = {"outside": metrics.truth_outside(lo, hi, problem.xs), "steps": problem.horizon + 1,
           "mean_radius": metrics.mean_radius(lo, hi),
           "cpu_per_step": (result["cpu_step"] + result["cpu_hull"]) / (problem.horizon + 1),
           "hull_share": result["cpu_hull"] / max(result["cpu_step"] + result["cpu_hull"], 1e-12),
           "peak_mib": result["peak_mib"], "contains": None, "gap": np.nan, "volume_ratio": np.nan,
           "hausdorff": np.nan}
    if reference is not None:
        ref = (reference["lo"], reference["hi"])
        row["contains"] = metrics.contains_reference(lo, hi, *ref)
        row["gap"] = metrics.containment_gap(lo, hi, *ref)
        row["volume_ratio"] = metrics.volume_ratio(lo, hi, *ref)
        if reference["source"] is result:      # the reference itself
            row["hausdorff"] = 0.0 if "polygons" in reference else np.nan
        elif "polygons" in reference:
            row["hausdorff"] = max(_hausdorff(_set_at(result, k), reference["polygons"][k])
                                   for k in gap_steps(problem.horizon))
    return row


def summarize(per_run: list[dict], problems: list[str], estimators: tuple[Estimator, ...]) -> list[dict]:
    """One row per (problem, estimator), aggregated over runs.

    ``sound`` is False when the truth left a hull in some run or a hull failed to contain the exact
    one; None when every run failed, or when the estimator does not apply to the problem
    (``applicable`` False, ``not_applicable`` says why).
    """
    rows = []
    for problem in problems:
        structure = PROBLEMS[problem].structure
        for e in estimators:
            row = {"problem": problem, "estimator": e.name, "kind": e.kind,
                   "applicable": e.applies(structure)}
            if not row["applicable"]:
                row.update(runs=0, errors=0, error=None, sound=None,
                           not_applicable=f"{e.name} applies to {_listed(e.applies_to)} systems, "
                                          f"{problem} is {_listed(structure)}")
                rows.append(row)
                continue
            results = [run[problem][e.name] for run in per_run]
            ok = [r for r in results if "error" not in r]
            errors = [r["error"] for r in results if "error" in r]
            row.update(runs=len(ok), errors=len(errors), error=errors[0] if errors else None)
            if ok:
                checked = [r["contains"] for r in ok if r["contains"] is not None]
                ratios = np.array([r["volume_ratio"] for r in ok], dtype=float)
                peaks = [r["peak_mib"] for r in ok if r["peak_mib"] is not None]
                row.update(
                    outside=sum(r["outside"] for r in ok), steps=sum(r["steps"] for r in ok),
                    containment_checked=bool(checked),
                    containment_failures=sum(1 for c in checked if not c),
                    containment_gap=float(np.nanmax([r["gap"] for r in ok])) if checked else None,
                    mean_radius=float(np.mean([r["mean_radius"] for r in ok])),
                    volume_ratio=(float(np.exp(np.mean(np.log(ratios)))) if np.all(ratios > 0)
                                  else float("nan")),
                    hausdorff_gap=float(np.mean([r["hausdorff"] for r in ok])),
                    cpu_ms_per_step=1e3 * float(np.mean([r["cpu_per_step"] for r in ok])),
                    hull_share=float(np.mean([r["hull_share"] for r in ok])),
                    peak_mib=max(peaks) if peaks else None)
                row["sound"] = row["outside"] == 0 and row["containment_failures"] == 0
            else:
                row["sound"] = None
            rows.append(row)
    return rows


def _listed(structures) -> str:
    return " or ".join(sorted(structures))
