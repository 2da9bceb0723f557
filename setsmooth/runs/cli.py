"""Command line: ``setsmooth figures [NAME...] [--runs N] [--out DIR] [--seed S] [--workers W | --scheduler ADDRESS] [--format pdf,svg] [--blas-threads N]``.

Regenerates the paper figures. The scripts live in the repository's ``paper_figures/`` directory,
outside the package; it is looked for in ``$SETSMOOTH_FIGURES_DIR``, then in the working directory and
its parents, then beside the package source (an editable install or a checkout).

Run sizes: each script has its own default: Figs. 3 and 5 use 300 runs, Fig. 4 the paper's 100 runs
per (q, r) pair, Fig. 6 the paper's 5000 runs. Together that is 650–720 CPU-seconds (350–380 s of
wall time measured on 2 idle cores; more on a machine shared with other jobs). ``--runs N``
sets every figure to N runs, except that Fig. 4 uses min(N, 100) runs per pair, the paper's size;
``--runs 5000`` reproduces the paper's sizes throughout (one to two hours on 2 cores). Stability
Table 1 runs the paper's 101 steps with 2 runs by default (its radii need a standard error), about
120 CPU-seconds a run, most of it the OIT-CZ's certified hulls at n = 30; it uses min(N, 100) runs,
the paper's size.

Scheduling: with two or more workers (``--workers W``, default 2) and two or more scripts, every script
runs in its own process, W of them at a time, started longest first by the costs measured in
``paper_figures/costs.json`` and each after the scripts whose outputs it reads (its ``AFTER``); all
their Monte Carlo workers share W slots, so at most W processes compute at once
(`setsmooth.runs.figure_processes`). One progress bar counts tasks: a script, or one Monte Carlo
run of it. Otherwise (one script, one worker, or ``--scheduler``) the scripts run one after the other in
this process, in the same order, each with its own bar of runs.

``--scheduler ADDRESS`` sends the runs to a Dask cluster instead of local processes (the
``setsmooth[dask]`` extra; every worker needs ``setsmooth`` installed). Results are bit-identical to a
local run: run i always uses the i-th child of the root seed.

BLAS threads: ``--blas-threads N`` (default 1) limits every BLAS library of this process and of the
worker processes it starts, before the first script runs: the Monte Carlo already keeps one process per
core, and BLAS threads on top of it only contend. The timed scripts (stability Table 1, the LSU timings)
set their own limit before their first solve and record the thread count the libraries report back.

Formats: every figure is written as PNG (the report embeds it); ``--format pdf,svg`` writes vector
copies beside it for a paper (PDF, SVG or EPS; text kept as text).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time
import traceback
from pathlib import Path

from ..arena.command import add_parser as add_arena_parser, run as run_arena  # argparse only: no solver
from .environment import BLAS_ENV, blas_limit, temporary_environment

ENV_VAR = "SETSMOOTH_FIGURES_DIR"
#: Read by ``paper_figures/_outputs.py``: the extra formats of every figure (comma-separated).
FORMATS_ENV = "SETSMOOTH_FIGURE_FORMATS"
#: The formats ``--format`` accepts besides PNG (kept equal to ``_outputs.FORMATS``).
FORMATS = ("png", "pdf", "svg", "eps")
FIGURES_DIRNAME = "paper_figures"
REPORT_MODULE = "report"


def find_figures_dir() -> Path:
    """The ``paper_figures/`` directory of the repository.

    Raises
    ------
    FileNotFoundError
        With the places searched, when none holds the figure scripts.
    """
    tried: list[Path] = []
    env = os.environ.get(ENV_VAR)
    if env:
        candidate = Path(env).expanduser().resolve()
        if (candidate / f"{REPORT_MODULE}.py").is_file():
            return candidate
        raise FileNotFoundError(f"${ENV_VAR} = {env!r} is not a paper_figures directory "
                                f"(no {REPORT_MODULE}.py in it)")
    cwd = Path.cwd().resolve()
    for base in (cwd, *cwd.parents, Path(__file__).resolve().parents[2]):
        candidate = base / FIGURES_DIRNAME
        tried.append(candidate)
        if (candidate / f"{REPORT_MODULE}.py").is_file():
            return candidate
    shown = "\n  ".join(str(p) for p in dict.fromkeys(tried))
    raise FileNotFoundError(
        f"cannot find the {FIGURES_DIRNAME}/ directory of the setsmooth repository; looked in\n  {shown}\n"
        f"Run from inside the repository, or set {ENV_VAR} to the directory holding the figure scripts.")


def discover(figures_dir: Path) -> list[str]:
    """Names of the figure scripts: every ``*.py`` except ``report.py`` and ``_private.py`` helpers."""
    return sorted(p.stem for p in figures_dir.glob("*.py")
                  if not p.name.startswith("_") and p.stem != REPORT_MODULE)


def select(available: list[str], requested: list[str]) -> list[str]:
    """Resolve requested names: exact script names, or a unique part of one (``fig3``)."""
    if not requested:
        return available
    chosen = []
    for name in requested:
        stem = name.removesuffix(".py")
        matches = [a for a in available if a == stem] or [a for a in available if stem in a]
        if len(matches) != 1:
            what = "matches no figure" if not matches else f"is ambiguous ({', '.join(matches)})"
            raise ValueError(f"{name!r} {what}; available: {', '.join(available)}")
        if matches[0] not in chosen:
            chosen.append(matches[0])
    return chosen


def parse_formats(text: str) -> list[str]:
    """The formats of ``--format`` (comma-separated), PNG first and always.

    Raises
    ------
    ValueError
        For an unknown format, naming the known ones.
    """
    asked = [f.strip().lower().lstrip(".") for f in text.split(",") if f.strip()]
    unknown = [f for f in asked if f not in FORMATS]
    if unknown:
        raise ValueError(f"unknown --format {', '.join(unknown)}; choose from {', '.join(FORMATS)}")
    return list(dict.fromkeys(["png", *asked]))


def run_figures(names: list[str], figures_dir: Path, out: Path, runs: int | None, seed: int,
                workers: int | None, progress: bool, executor=None,
                formats: list[str] | None = None, blas_threads: int | None = None) -> tuple[dict, Path]:
    """Run the named figure scripts, then write the report; return (wall times or errors, report path).

    ``executor`` (a `concurrent.futures.Executor` or a ``dask.distributed.Client``) is passed to every
    script's ``main`` and so to `setsmooth.runs.montecarlo.run`; None lets each script start its own pool.
    A Dask client's workers first receive the figure scripts (``Client.upload_file``): they unpickle
    the trials by module name, and a remote worker has only the installed ``setsmooth``.
    ``formats``: the image formats of every figure (PNG always; e.g. ``['png', 'pdf']``), passed
    to the scripts' `_outputs.write_outputs` through ``$SETSMOOTH_FIGURE_FORMATS`` for this call.
    ``blas_threads``: limit the BLAS libraries to this many threads for this call (`blas_limit`);
    None leaves them as they are.
    Without an executor, with ``workers`` (default 2) above one and several scripts, the scripts run in
    processes of their own (`setsmooth.runs.figure_processes.run_scheduled`); the wall times are then
    in the order the scripts started.
    """
    with temporary_environment({FORMATS_ENV: ",".join(formats or ["png"])}), blas_limit(blas_threads):
        return _run_figures(names, figures_dir, out, runs, seed, workers, progress, executor, blas_threads)


def _run_figures(names, figures_dir, out, runs, seed, workers, progress, executor, blas_threads):
    from .schedule import plan, read_after, read_costs

    costs, after = read_costs(figures_dir), read_after(figures_dir, names)
    n_workers = workers or min(2, os.cpu_count() or 1)
    if executor is None and n_workers > 1 and len(names) > 1:
        from .figure_processes import run_scheduled

        environment = {name: os.environ[name] for name in (FORMATS_ENV, *BLAS_ENV) if name in os.environ}
        outcome = run_scheduled(names, figures_dir, out, runs, seed, n_workers, progress, costs, after,
                                environment, blas_threads)
        return outcome, _report(figures_dir, out, names, runs)
    if str(figures_dir) not in sys.path:
        # The scripts import their sibling helpers, and pool workers unpickle trials by module name.
        sys.path.insert(0, str(figures_dir))
    if executor is not None and hasattr(executor, "upload_file"):
        _upload_scripts(executor, figures_dir)
    outcome: dict[str, float | str] = {}
    # One after the other, each after the scripts it reads (`schedule.plan`).
    for name in plan(names, costs, after):
        print(f"== {name}", flush=True)
        start = time.perf_counter()
        kwargs = {"seed": seed, "out": out, "workers": workers, "progress": progress}
        if executor is not None:
            kwargs["executor"] = executor
        if runs is not None:
            kwargs["runs"] = runs
        try:
            result = importlib.import_module(name).main(**kwargs)
        except Exception:  # one failing figure must not hide the others; reported below
            traceback.print_exc()
            outcome[name] = "failed"
            continue
        outcome[name] = time.perf_counter() - start
        for row in result.get("rows", []):
            print(f"   {row['quantity']}: paper {row['paper']} | ours {row['ours']}")
        print(f"   {outcome[name]:.1f} s", flush=True)
    return outcome, _report(figures_dir, out, names, runs)


def _report(figures_dir: Path, out: Path, names: list[str], runs: int | None) -> Path:
    from .schedule import record_costs

    record_costs(out, names, runs)
    if str(figures_dir) not in sys.path:
        sys.path.insert(0, str(figures_dir))
    return importlib.import_module(REPORT_MODULE).main(out)


def _upload_scripts(client, figures_dir: Path) -> None:
    # load=False: the workers import the scripts when a trial needs one, after all are there (loading
    # on upload would import _lsu_examples before its sibling _outputs arrived).
    for path in sorted(figures_dir.glob("*.py")):
        client.upload_file(str(path), load=False)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="setsmooth", description="setsmooth command line")
    commands = parser.add_subparsers(dest="command", required=True)
    arena = add_arena_parser(commands)
    figures = commands.add_parser(
        "figures", help="regenerate the paper figures and paper_figures/out/REPORT.md",
        description=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    figures.add_argument("names", nargs="*", metavar="NAME",
                         help="figure scripts to run (e.g. smoothing_fig3 or fig3); all by default")
    figures.add_argument("--runs", type=int, default=None,
                         help="Monte Carlo runs for every figure (Fig. 4: min(N, 100) per pair); "
                              "default: each script's own")
    figures.add_argument("--out", type=Path, default=None, help="output directory (default paper_figures/out)")
    figures.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    figures.add_argument("--workers", type=int, default=None, help="worker processes (default 2)")
    figures.add_argument("--scheduler", default=None, metavar="ADDRESS",
                         help="run the Monte Carlo on the Dask scheduler at ADDRESS (e.g. "
                              "tcp://10.0.0.5:8786; needs the setsmooth[dask] extra)")
    figures.add_argument("--blas-threads", type=int, default=1, metavar="N",
                         help="BLAS threads per process (default 1; the Monte Carlo runs one process per core)")
    figures.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    figures.add_argument("--list", action="store_true", help="list the figure scripts and exit")
    figures.add_argument("--format", default="", metavar="FMT[,FMT]",
                         help="vector copies of every figure besides the PNG: pdf, svg, eps "
                              "(comma-separated, e.g. pdf,svg)")
    args = parser.parse_args(argv)
    if args.command == "arena":
        return run_arena(args, arena)
    try:
        formats = parse_formats(args.format)
    except ValueError as exc:
        parser.error(str(exc))

    if args.runs is not None and args.runs < 1:
        parser.error("--runs must be at least 1")
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.seed < 0:
        parser.error("--seed must be non-negative")
    if args.blas_threads < 1:
        parser.error("--blas-threads must be at least 1")
    if args.scheduler is not None and args.workers is not None:
        parser.error("--workers sets the local process pool; the cluster behind --scheduler has its own "
                     "workers: give one of them")
    try:
        figures_dir = find_figures_dir()
        available = discover(figures_dir)
        names = select(available, args.names)
    except (FileNotFoundError, ValueError) as exc:
        print(f"setsmooth figures: {exc}", file=sys.stderr)
        return 2
    if args.list:
        print("\n".join(available))
        return 0
    out = (args.out or figures_dir / "out").resolve()
    start = time.perf_counter()
    from .dask_cluster import scheduler_client

    client, status = scheduler_client(args.scheduler, "setsmooth figures")
    if status:
        return status
    try:
        outcome, report = run_figures(names, figures_dir, out, args.runs, args.seed, args.workers,
                                      not args.no_progress, executor=client, formats=formats,
                                      blas_threads=args.blas_threads)
    finally:
        if client is not None:
            client.close()
    print(f"== report: {report} ({time.perf_counter() - start:.0f} s in all)")
    failed = [name for name, value in outcome.items() if value == "failed"]
    if failed:
        print(f"setsmooth figures: failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
