"""``setsmooth arena``: the subcommand's parser and its action (`setsmooth.runs.cli` dispatches here).

This module imports only the standard library at the top, so that ``setsmooth --help`` stays fast; the
arena itself is imported when the subcommand runs.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

# 5 runs of every light problem and estimator: about 130 CPU-seconds, about a minute on 2 free cores
# (measured 2026-11-28 with example33 and scalar_linear; docs/arena.md has the table).
DEFAULT_RUNS = 5
DEFAULT_OUT = Path("arena_out")

DESCRIPTION = """\
Compare estimators (and the set representations they use) on a zoo of problems over seeded Monte
Carlo runs. Per (problem, estimator): true states outside the estimator's interval hulls, whether its
hulls contain the exact estimator's (the exact filter for filters, the trajectory smoother for
smoothers), the mean hull radius, the hull volume over the exact one's, on 2-D problems the
Hausdorff distance of the sets to the exact ones, and CPU time per step (estimator plus hulls).
Writes DIR/arena.json, DIR/arena.md and DIR/arena.png (tightness against time, unsound entries in
red) and prints the table. The exit status is 1 when an entry is unsound.

An estimator runs only on the problems whose system it applies to (the interval filter and smoother
on scalar systems with increasing dynamics, such as the nonlinear example33; the others on linear
systems); the other pairs are marked n/a. A problem no exact estimator applies to (example33) is
judged by the truth alone ("no exact reference").

Heavy problems (random20, random30, long_horizon) and heavy estimators (recursion_smoother,
lsup) run only when named. Register your own estimator from Python with
setsmooth.arena.register(name, fn) and call setsmooth.arena.run_arena, or see
examples/arena_new_representation.py."""


def _names(values: list[str] | None) -> list[str] | None:
    """Names given as separate words or comma-separated (or both)."""
    if values is None:
        return None
    return [name for value in values for name in value.split(",") if name]


def add_parser(commands) -> argparse.ArgumentParser:
    """Add the ``arena`` subcommand to an ``add_subparsers`` object; return its parser."""
    parser = commands.add_parser("arena", help="compare estimators on a zoo of problems (soundness, "
                                               "tightness, time)",
                                 description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--problems", nargs="+", metavar="NAME",
                        help="problems (default: every one not heavy); see --list")
    parser.add_argument("--estimators", nargs="+", metavar="NAME",
                        help="estimators (default: every registered one not heavy); see --list")
    parser.add_argument("--runs", type=int, default=DEFAULT_RUNS,
                        help=f"Monte Carlo runs (default {DEFAULT_RUNS})")
    parser.add_argument("--horizon", type=int, default=None, metavar="T",
                        help="horizon T for every problem (default: each problem's own)")
    parser.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT,
                        help=f"output directory (default ./{DEFAULT_OUT})")
    parser.add_argument("--workers", type=int, default=None, help="worker processes (default 2)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="run on the Dask scheduler at ADDRESS (needs the setsmooth[dask] extra)")
    parser.add_argument("--memory", action="store_true",
                        help="also record peak memory per estimator (tracemalloc; slows every estimator)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    parser.add_argument("--list", action="store_true", help="list the problems and estimators and exit")
    return parser


def run(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    """Carry out ``setsmooth arena`` with parsed ``args``; return the exit status."""
    for flag, value, minimum in (("--runs", args.runs, 1), ("--workers", args.workers, 1),
                                 ("--horizon", args.horizon, 0), ("--seed", args.seed, 0)):
        if value is not None and value < minimum:
            parser.error(f"{flag} must be at least {minimum}, got {value}")
    if args.scheduler is not None and args.workers is not None:
        parser.error("--workers sets the local process pool; the cluster behind --scheduler has its own "
                     "workers: give one of them")
    from .estimators import ESTIMATORS, check_estimators
    from .problems import PROBLEMS, check_problems

    if args.list:
        print("problems:")
        for name, spec in PROBLEMS.items():
            print(f"  {name:<22} T = {spec.horizon:<5} {spec.summary}{' (heavy)' if spec.heavy else ''}"
                  f" [{', '.join(sorted(spec.structure))}]")
        print("estimators:")
        for name, e in ESTIMATORS.items():
            print(f"  {name:<22} {e.kind:<9} {e.summary}{' (heavy)' if e.heavy else ''}"
                  f" [applies to {', '.join(sorted(e.applies_to))}]")
        return 0
    try:
        problems = check_problems(_names(args.problems), "--problems")
        estimators = check_estimators(_names(args.estimators), "--estimators")
    except ValueError as exc:
        parser.error(str(exc))
    from .report import markdown_table, write_outputs
    from .runner import run_arena

    start = time.perf_counter()
    from ..runs.dask_cluster import scheduler_client

    client, status = scheduler_client(args.scheduler, "setsmooth arena")
    if status:
        return status
    try:
        result = run_arena(problems, estimators, args.runs, args.seed, horizon=args.horizon,
                           executor=client, workers=args.workers, progress=not args.no_progress,
                           memory=args.memory)
    finally:
        if client is not None:
            client.close()
    paths = write_outputs(result, args.out)
    print(markdown_table(result))
    print(f"\nwrote {paths['json']}, {paths['markdown']}, {paths['figure']} "
          f"({time.perf_counter() - start:.0f} s)")
    unsound = result.unsound()
    if unsound:
        print("setsmooth arena: unsound: " + ", ".join(f"{e} on {p}" for p, e in unsound), file=sys.stderr)
        return 1  # a script or CI job running the arena fails on an unsound estimator
    return 0
