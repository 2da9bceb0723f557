"""Reliability benchmark (issue 7): the exact estimators against an independent HiGHS oracle, at scale.

    python benchmarks/reliability.py [--systems N] [--seed S] [--workers W] [--rescaled R]
                                     [--witness K] [--long-horizon L] [--horizon T]
                                     [--T-range MIN MAX] [--n-range MIN MAX] [--start I]
                                     [--time-limit SECONDS] [--estimators filter,recursion,trajectory]
                                     [--log FILE] [--from-log FILE ...]

On a shared machine: ``--start`` splits the systems over several invocations (their counts add up),
``--time-limit`` stops starting tasks after that long and reports the systems that finished.
``--log FILE`` appends one JSON line per finished case, rescaled set and witness check as it
finishes (a run that is killed keeps what it measured); the failing cases are also listed by name
after the tables. ``--from-log FILE`` prints the tables of such logs (several files add up) without
running anything. ``--estimators none`` runs only the rescalings and the witness check.

* N seeded random systems (`setsmooth/reliability/random_systems.py`: five kinds, n = 2..6, p, m = 1..3,
  box and CZ noises, T = 10..40), each in the four regimes (noise scale 1, 1e-6, 1e3; state offset
  1e6), × the three estimators (filter, recursion smoother, trajectory smoother), hulls plain and
  certified, scored against the trajectory-LP oracle (`setsmooth/reliability/compare.py` says exactly what
  counts);
* R rescaled random CZs (1e±12 scalings of rows, factors, coordinates) on the fast and generic paths;
* the witness check (certified supports of the trajectory smoother vs feasible points) on the first K
  systems at unit scale;
* L seeds of issue 8's long-horizon case (example (31), triangle-CZ process noise, T steps);
* threads, pickling and the Monte Carlo guard, once.

Everything is seeded; the counts are reproducible for a given seed and size. The work is spread over
a process pool with a tqdm bar. Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from collections import Counter, defaultdict
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from setsmooth.reliability import compare, concurrency, rescaling, witness  # noqa: E402
from setsmooth.reliability.oracle import OracleError  # noqa: E402
from setsmooth.reliability.random_systems import ALL_NOISES, ALL_REGIMES, REGIMES, base_case, in_regime, triangle_case  # noqa: E402


# -- tasks (module level: they go to worker processes) ------------------------------------------------
def system_task(seed: int, index: int, with_witness: bool, T_range: tuple[int, int],
                n_range: tuple[int, int], estimators: tuple[str, ...] = compare.ESTIMATORS,
                regimes: tuple[str, ...] = REGIMES, noises: tuple[str, ...] | None = None):
    """The ``regimes`` (default all) of system ``index``: (list of CaseResult or ('oracle', name,
    msg)), witness outcome. ``noises`` cycles the noise type with the index (None: `base_case`'s
    box/CZ alternation)."""
    noise = None if noises is None else noises[index % len(noises)]
    base = base_case(seed, index, T_range=T_range, n_range=n_range, noise=noise)
    results = []
    for regime in regimes:
        case = in_regime(base, regime)
        try:
            results.append(compare.compare_case(case, estimators=estimators))
        except OracleError as exc:
            results.append(("oracle", case.name, str(exc)))
    return results, (_witness_outcome(base) if with_witness else None)


def _witness_outcome(base):
    """`witness.witness_check` of ``base``, or ('oracle', name, message) when the oracle fails."""
    try:
        return witness.witness_check(base)
    except OracleError as exc:
        return ("oracle", base.name, str(exc))


def witness_task(seed: int, index: int, T_range: tuple[int, int], n_range: tuple[int, int]):
    """The witness check of system ``index`` alone (``--estimators none``)."""
    return _witness_outcome(base_case(seed, index, T_range=T_range, n_range=n_range))


def _log_witness(log, w) -> None:
    _log_line(log, {"witness": dataclasses.asdict(w) if not isinstance(w, tuple) else
                    {"name": w[1], "message": w[2]}})


def rescale_task(seed: int, count: int, i: int):
    r = rescaling.random_rescalings(count, seed)[i]
    return [rescaling.check(r, path) for path in rescaling.PATHS]


def long_horizon_task(seed: int, T: int):
    # The recursion smoother's sets grow as O(T²) factors (each smoothed CZ restates the later ones);
    # at T = 100 that exhausts memory, so this case runs the filter and the trajectory smoother.
    case = triangle_case(seed, T)
    try:
        return compare.compare_case(case, estimators=("filter", "trajectory"))
    except OracleError as exc:
        return ("oracle", case.name, str(exc))


# -- tables --------------------------------------------------------------------------------------------
def _errors_cell(runs: list[compare.Outcome]) -> str:
    failed = [o for o in runs if o.error]
    if not failed:
        return "0"
    parts = []
    for est in compare.ESTIMATORS:
        mine = [o for o in failed if o.estimator == est]
        if mine:
            kinds = Counter(f"{o.status or o.error} at {o.stage}" for o in mine)
            parts.append(f"{est} {len(mine)}: " + ", ".join(f"{k} ×{v}" for k, v in kinds.most_common()))
    return f"{len(failed)} (" + "; ".join(parts) + ")"


def _count_cell(runs: list[compare.Outcome], attr: str, worst: str) -> str:
    bad = [o for o in runs if getattr(o, attr)]
    if not bad:
        return "0"
    by_est = Counter(o.estimator for o in bad)
    w = max(getattr(o, worst) for o in bad)
    return f"{len(bad)} (" + ", ".join(f"{e} {by_est[e]}" for e in compare.ESTIMATORS if by_est[e]) + \
        f"; worst {w:.1e} rel)"


def system_table(results: list[compare.CaseResult], title: str, group) -> str:
    groups = defaultdict(list)
    for r in results:
        groups[group(r)].extend(r.outcomes)
    lines = [f"### {title}", "",
             "| group | runs | runs raising (by estimator and status) | true state outside | "
             "contains rejects truth | hull off > 1e−6 (w + σ) | plain hull off > 1e−6 w | certified not enclosing | "
             "certified out > 1e−6 w | coordinates below the guaranteed width |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    order = sorted(groups, key=lambda g: (list(ALL_REGIMES).index(g) if g in ALL_REGIMES else 99, g))
    total: list[compare.Outcome] = []
    for g in order:
        runs = groups[g]
        total.extend(runs)
        lines.append(f"| {g} | {len(runs)} | {_errors_cell(runs)} | "
                     f"{_count_cell(runs, 'outside', 'worst_outside')} | {_count_cell(runs, 'rejected', 'rejected')} | "
                     f"{_count_cell(runs, 'off', 'worst_off')} | {_count_cell(runs, 'off_width', 'worst_off_width')} | "
                     f"{_count_cell(runs, 'not_enclosing', 'worst_not_enclosing')} | "
                     f"{_count_cell(runs, 'loose_width', 'worst_loose_width')} | {sum(o.thin for o in runs)} |")
    if len(order) > 1:
        lines.append(f"| **all** | {len(total)} | {_errors_cell(total)} | "
                     f"{_count_cell(total, 'outside', 'worst_outside')} | {_count_cell(total, 'rejected', 'rejected')} | "
                     f"{_count_cell(total, 'off', 'worst_off')} | {_count_cell(total, 'off_width', 'worst_off_width')} | "
                     f"{_count_cell(total, 'not_enclosing', 'worst_not_enclosing')} | "
                     f"{_count_cell(total, 'loose_width', 'worst_loose_width')} | {sum(o.thin for o in total)} |")
    return "\n".join(lines)


def rescale_table(outcomes: list[rescaling.RescaleOutcome]) -> str:
    lines = ["### Rescaled representations (1e±12), counts of sets", "",
             "| path | rescaled | sets | silent wrong finite | inf for bounded | contains rejects member | "
             "certified below exact | clear SolverError | other exception |",
             "|---|---|---|---|---|---|---|---|---|"]
    for path in rescaling.PATHS:
        for how in (*rescaling.HOWS, "all"):
            rows = [o for o in outcomes if o.path == path and (how == "all" or o.how == how)]
            if not rows:
                continue
            wrong = [o for o in rows if o.wrong]
            worst = f" (worst {max(o.worst_wrong for o in wrong):.1e} of scale)" if wrong else ""
            below = [o for o in rows if o.certified_below]
            worst_b = f" (worst {max(o.worst_certified_below for o in below):.1e})" if below else ""
            statuses = Counter(s.split(": ", 1)[1] for o in rows for s in o.solver_errors)
            se = sum(1 for o in rows if o.solver_errors)
            se_cell = f"{se}" + (" (" + ", ".join(f"{k} ×{v}" for k, v in statuses.most_common()) + ")"
                                 if se else "")
            label = f"**{how}**" if how == "all" else how
            lines.append(f"| {path} | {label} | {len(rows)} | {len(wrong)}{worst} | "
                         f"{sum(1 for o in rows if o.inf)} | {sum(1 for o in rows if o.rejected)} | "
                         f"{len(below)}{worst_b} | {se_cell} | {sum(1 for o in rows if o.other_errors)} |")
    return "\n".join(lines)


def failed_cases(results: list[compare.CaseResult], limit: int = 40) -> str:
    """The cases behind the tables' nonzero counts, one line per estimator that failed."""
    lines = []
    for r in results:
        for o in r.failed:
            what = [o.error and f"{o.error} at {o.stage}",
                    o.outside and f"{o.outside} outside (worst {o.worst_outside:.1e})",
                    o.rejected and f"{o.rejected} rejected by contains",
                    o.off and f"{o.off} off (worst {o.worst_off:.1e})",
                    o.not_enclosing and f"{o.not_enclosing} not enclosing (worst {o.worst_not_enclosing:.1e})"]
            lines.append(f"  {r.name} {o.estimator}: " + ", ".join(w for w in what if w))
    if not lines:
        return "Failing cases: none"
    more = f" (first {limit})" if len(lines) > limit else ""
    return f"Failing cases: {len(lines)}{more}\n" + "\n".join(lines[:limit])


def crashed_in_logs(paths: list[Path]) -> list[str]:
    """The tasks that crashed outside the estimators, from ``--log`` files."""
    return [json.loads(line)["message"] for path in paths for line in path.read_text().splitlines()
            if '"crashed"' in line]


def print_crashed(crashed: list[str]) -> None:
    if crashed:
        print(f"\nTasks that crashed outside the estimators (counted nowhere above): {len(crashed)}")
        for line in crashed:
            print("  " + line)


def read_log(paths: list[Path]) -> tuple[list[compare.CaseResult], list[tuple]]:
    """Case results and oracle failures from ``--log`` files (later lines win for a repeated case)."""
    cases, failed = {}, {}
    for path in paths:
        for line in path.read_text().splitlines():
            record = json.loads(line)
            if "crashed" in record or "rescaled" in record or "witness" in record:
                continue  # `crashed_in_logs`, `checks_in_logs`
            if "oracle_failed" in record:
                failed[record["oracle_failed"]] = ("oracle", record["oracle_failed"], record["message"])
                continue
            name = record["case"]
            regime = next(r for r in ALL_REGIMES if name.endswith("-" + r))
            _, kind, noise = name[: -len(regime) - 1].split("-")
            result = compare.CaseResult(name, kind, noise, regime, oracle_seconds=record["oracle_seconds"],
                                        oracle_failed=record.get("oracle_failed_message", ""))
            result.outcomes = [compare.Outcome(**o) for o in record["outcomes"]]
            cases[name] = result
            failed.pop(name, None)
    return list(cases.values()), list(failed.values())


def print_system_tables(case_results: list[compare.CaseResult], oracle_failed: list[tuple]) -> None:
    print(system_table(case_results, "By regime (runs = systems × filter/recursion/trajectory)",
                       lambda r: r.regime))
    print()
    print(system_table(case_results, "By kind and noise (all regimes)", lambda r: f"{r.kind}, {r.noise}"))
    print()
    print(failed_cases(case_results))
    print()
    unscored = [r for r in case_results if r.oracle_failed]
    if unscored:
        print(f"Oracle failures (scored for raising, truth and membership only): {len(unscored)}")
        for r in unscored[:20]:
            print(f"  {r.name}: {r.oracle_failed}")
        print()
    if oracle_failed:
        print(f"Oracle failures (cases left out of the counts): {len(oracle_failed)}")
        for _, name, msg in oracle_failed[:20]:
            print(f"  {name}: {msg}")
        print()


def checks_in_logs(paths: list[Path]) -> tuple[list[rescaling.RescaleOutcome], list]:
    """The rescaling and witness outcomes of ``--log`` files (later lines win for a repeat)."""
    rescaled, witnesses = {}, {}
    for path in paths:
        for line in path.read_text().splitlines():
            record = json.loads(line)
            if "rescaled" in record:
                o = rescaling.RescaleOutcome(**record["rescaled"])
                rescaled[(o.name, o.how, o.path)] = o
            elif "witness" in record:
                w = record["witness"]
                witnesses[w["name"]] = witness.WitnessOutcome(**w) if "checked" in w else (
                    "oracle", w["name"], w["message"])
    return list(rescaled.values()), list(witnesses.values())


def _log_line(log, record: dict) -> None:
    if log is not None:
        log.write(json.dumps(record) + "\n")
        log.flush()


def witness_table(outcomes) -> str:
    ok = [o for o in outcomes if isinstance(o, witness.WitnessOutcome)]
    bad = [o for o in ok if o.violations]
    errs = [o for o in ok if o.error]
    worst = max((o.worst for o in bad), default=0.0)
    example = max(bad, key=lambda o: o.worst).example if bad else ""
    return "\n".join([
        "### Witness check (trajectory smoother, certified support ≥ dᵀx for feasible x)", "",
        "| systems | directions checked | systems with a certified value below a witness | worst gap (rel) | "
        "raised | oracle failed |",
        "|---|---|---|---|---|---|",
        f"| {len(ok)} | {sum(o.checked for o in ok)} | {len(bad)} | {worst:.1e} {example} | {len(errs)} | "
        f"{len(outcomes) - len(ok)} |"])


def concurrency_table() -> str:
    import pickle

    lines = ["### Threads, pickling, process pools", "",
             "| check | result |", "|---|---|"]
    for name, build in concurrency.set_factories().items():
        for path in ("auto", "generic"):
            o = concurrency.threaded_support(name, build, path)
            status = "ok" if not (o.wrong or o.errors or o.hung) else \
                f"{o.wrong}/{o.queries} wrong (worst {o.worst:.1e}), {len(o.errors)} threads raised" + \
                (f" ({o.errors[0]})" if o.errors else "") + (f", {o.hung} hung" if o.hung else "")
            lines.append(f"| {name}, 4 threads, path={path} | {status} |")
        S = build()
        try:
            S.support(np.ones(S.dim), path="generic")
            S.support(np.ones(S.dim))
            pickle.loads(pickle.dumps(S))
            lines.append(f"| {name} pickles after generic + fast queries | ok |")
        except Exception as exc:  # noqa: BLE001 - reported
            lines.append(f"| {name} pickles after generic + fast queries | {type(exc).__name__}: {exc} |")
    outcomes = concurrency.montecarlo_lambda_probe(attempts=5, timeout=15.0)
    lines.append(f"| montecarlo.run with a lambda trial (5 attempts, 15 s each) | {', '.join(outcomes)} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--systems", type=int, default=250)
    ap.add_argument("--start", type=int, default=0, help="index of the first system (to split a "
                    "run over several invocations: systems start .. start + systems − 1)")
    ap.add_argument("--indices", default=None, metavar="I,J,...",
                    help="comma-separated system indices to run instead of --start/--systems (to re-run "
                         "the systems a generator change touched)")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rescaled", type=int, default=60)
    ap.add_argument("--witness", type=int, default=60, help="systems for the witness check (the first K)")
    ap.add_argument("--long-horizon", type=int, default=10, help="seeds of issue 8's triangle-CZ case")
    ap.add_argument("--horizon", type=int, default=100)
    ap.add_argument("--T-range", type=int, nargs=2, default=(10, 40), metavar=("MIN", "MAX"),
                    help="horizon range of the random systems (issue 7: 10 40)")
    ap.add_argument("--n-range", type=int, nargs=2, default=(2, 6), metavar=("MIN", "MAX"),
                    help="state-dimension range of the random systems (issue 7: 2 6)")
    ap.add_argument("--estimators", default=",".join(compare.ESTIMATORS),
                    help="comma-separated subset of " + ", ".join(compare.ESTIMATORS) + " (default: all; "
                         "the recursion smoother dominates the time at T = 40)")
    ap.add_argument("--regimes", default=",".join(REGIMES),
                    help="comma-separated subset of " + ", ".join(ALL_REGIMES) + " (default: all; one "
                         "process per regime runs a heavy system's regimes side by side)")
    ap.add_argument("--noises", default=None, metavar="N1,N2,...",
                    help="noise types cycled over the system indices, some of " + ", ".join(ALL_NOISES) +
                         " (default: box and CZ alternating every five indices, as the test corpus)")
    ap.add_argument("--no-concurrency", action="store_true")
    ap.add_argument("--log", type=Path, default=None, metavar="FILE",
                    help="append one JSON line per finished case (and oracle failure) as it finishes")
    ap.add_argument("--time-limit", type=float, default=None, metavar="SECONDS",
                    help="stop starting tasks after this long and report the tasks finished (the "
                         "title says how many systems that is)")
    ap.add_argument("--from-log", type=Path, nargs="+", default=None, metavar="FILE",
                    help="print the system tables of --log files instead of running")
    args = ap.parse_args(argv)
    if args.from_log:
        case_results, oracle_failed = read_log(args.from_log)
        systems = len({r.name.split("-")[0] for r in case_results})
        print(f"## setsmooth reliability from {', '.join(map(str, args.from_log))}: {systems} systems, "
              f"{len(case_results)} cases\n")
        print_system_tables(case_results, oracle_failed)
        rescaled, witnesses = checks_in_logs(args.from_log)
        if rescaled:
            print(rescale_table(rescaled))
            print()
        if witnesses:
            print(witness_table(witnesses))
            print()
        print_crashed(crashed_in_logs(args.from_log))
        return
    if args.indices is not None:
        try:
            indices = [int(i) for i in args.indices.split(",") if i.strip()]
        except ValueError:
            ap.error(f"--indices must be comma-separated non-negative integers, got {args.indices!r}")
        if not indices or min(indices) < 0:
            ap.error(f"--indices must be comma-separated non-negative integers, got {args.indices!r}")
    else:
        indices = list(range(args.start, args.start + args.systems))
    estimators = tuple(e.strip() for e in args.estimators.split(",") if e.strip())
    if estimators == ("none",):
        estimators = ()  # only the rescalings and the witness check
    unknown = [e for e in estimators if e not in compare.ESTIMATORS]
    if unknown or not (estimators or args.estimators.strip() == "none"):
        ap.error(f"--estimators must name some of {', '.join(compare.ESTIMATORS)} (or be 'none'), "
                 f"got {args.estimators!r}")
    regimes = tuple(r.strip() for r in args.regimes.split(",") if r.strip())
    if not regimes or any(r not in ALL_REGIMES for r in regimes):
        ap.error(f"--regimes must name some of {', '.join(ALL_REGIMES)}, got {args.regimes!r}")

    noises = None
    if args.noises is not None:
        noises = tuple(s.strip() for s in args.noises.split(",") if s.strip())
        if not noises or any(s not in ALL_NOISES for s in noises):
            ap.error(f"--noises must name some of {', '.join(ALL_NOISES)}, got {args.noises!r}")

    t0 = time.perf_counter()
    case_results, oracle_failed, witnesses, rescaled, long_runs = [], [], [], [], []
    systems_done = 0
    log = args.log.open("a") if args.log is not None else None
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = {}
        # The cheap rescaling tasks first, then the systems in index order: a run stopped by the
        # time limit covers a prefix of the systems (every kind and noise, see base_case).
        for i in range(args.rescaled):
            futures[pool.submit(rescale_task, args.seed, args.rescaled, i)] = "rescale"
        for i in indices:
            if estimators:
                futures[pool.submit(system_task, args.seed, i, i < args.witness,
                                    tuple(args.T_range), tuple(args.n_range), estimators,
                                    regimes, noises)] = "system"
            elif i < args.witness:
                futures[pool.submit(witness_task, args.seed, i, tuple(args.T_range),
                                    tuple(args.n_range))] = "witness"
        for s in range(args.long_horizon):
            futures[pool.submit(long_horizon_task, s, args.horizon)] = "long"
        stopped = False
        crashed: list[str] = []
        for fut in tqdm(as_completed(futures), total=len(futures), desc="reliability", unit="task"):
            if fut.cancelled():
                continue
            if (not stopped and args.time_limit is not None
                    and time.perf_counter() - t0 > args.time_limit):
                stopped = True
                for other in futures:
                    other.cancel()  # the ones not started; running ones finish and are counted
            kind = futures[fut]
            try:
                out = fut.result()
            except Exception as exc:  # noqa: BLE001 - one task's crash is a finding, not the run's end
                crashed.append(f"{kind} task: {type(exc).__name__}: {str(exc).splitlines()[0][:160]}")
                _log_line(log, {"crashed": kind, "message": crashed[-1]})
                continue
            if kind == "system":
                systems_done += 1
                results, w = out
                for r in results:
                    (oracle_failed if isinstance(r, tuple) else case_results).append(r)
                    _log_line(log, {"oracle_failed": r[1], "message": r[2]} if isinstance(r, tuple) else
                              {"case": r.name, "oracle_seconds": r.oracle_seconds,
                               "oracle_failed_message": r.oracle_failed,
                               "outcomes": [dataclasses.asdict(o) for o in r.outcomes]})
                if w is not None:
                    witnesses.append(w)
                    _log_witness(log, w)
            elif kind == "witness":
                witnesses.append(out)
                _log_witness(log, out)
            elif kind == "rescale":
                rescaled.extend(out)
                for o in out:
                    _log_line(log, {"rescaled": dataclasses.asdict(o)})
            else:
                (oracle_failed if isinstance(out, tuple) else long_runs).append(out)
    elapsed = time.perf_counter() - t0
    if log is not None:
        log.close()

    if estimators and systems_done < len(indices) and args.time_limit is not None:
        print(f"\nTime limit of {args.time_limit:.0f} s reached: {systems_done} of {len(indices)} "
              "systems finished; the tables count those.")
    first = f" from index {args.start}" if args.start else ""
    if args.indices is not None:
        first = f" (indices {args.indices})"
    print(f"\n## setsmooth reliability: seed {args.seed}, {systems_done} systems{first} (T = {args.T_range[0]}.."
          f"{args.T_range[1]}, n = {args.n_range[0]}..{args.n_range[1]}) × {len(regimes)} regimes × "
          f"{len(estimators)} estimators ({', '.join(estimators)}; {elapsed:.0f} s on {args.workers} workers)\n")
    print_system_tables(case_results, oracle_failed)
    if long_runs:
        print(system_table(long_runs, f"Issue 8: example (31), triangle-CZ W, T = {args.horizon}",
                           lambda r: "triangle W"))
        print()
    print(rescale_table(rescaled))
    print()
    print(witness_table(witnesses))
    print()
    oracle_t = np.median([r.oracle_seconds for r in case_results]) if case_results else float("nan")
    est_t = {e: np.median([o.seconds for r in case_results for o in r.outcomes if o.estimator == e])
             for e in estimators} if case_results else {}
    print("Median seconds per case: oracle {:.2f}; ".format(oracle_t) +
          ", ".join(f"{e} {t:.2f}" for e, t in est_t.items()))
    print_crashed(crashed)
    if not args.no_concurrency:
        print()
        print(concurrency_table())


if __name__ == "__main__":
    main()
