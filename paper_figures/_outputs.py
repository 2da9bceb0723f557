"""The figure-script protocol, written once for every paper.

A figure script ``<paper>_<figure>.py`` in this directory defines

* ``NAME`` (its file stem: the outputs are ``<NAME>.png`` and ``<NAME>.json``), ``PAPER`` (the short
  name of its paper in ``/papers/INDEX.md``: ``smoothing``, ``stability``, ...) and ``DEFAULT_RUNS``;
* ``main(runs, seed, out, workers, progress, executor) -> dict``, which runs the Monte Carlo
  (`setsmooth.runs.montecarlo.run`), builds the figure and returns `finish(...)`;
* ``if __name__ == "__main__": cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])``.

The JSON written by `finish` holds the plotted numbers plus the keys the report reads: ``paper``,
``figure``, ``rows`` (made by `row`: a published value or claim beside ours), ``settings``,
``published``, ``notes``, ``wall_time_s`` and ``cpu_time_s``, and optionally ``checks`` (made by
``_verdicts.value`` / ``_verdicts.claim``: the numbers behind the report's verdict table). Every figure is written as ``<NAME>.png``
(the report embeds it) and also in the vector formats named by ``$SETSMOOTH_FIGURE_FORMATS``
(comma-separated, from ``setsmooth figures --format pdf,svg`` or a script's own ``--format``): PDF and
SVG for papers. ``setsmooth figures`` (`setsmooth.runs.cli`)
runs the scripts and then ``report.py``, which groups the rows by paper; each paper's conventions
(``REPORT_PREAMBLE``, ``PAPER_TITLE``) live in its ``_<paper>_examples.py``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from setsmooth.runs.cli import FORMATS_ENV, parse_formats

DEFAULT_OUT = Path(__file__).resolve().parent / "out"


def figure_formats() -> tuple[str, ...]:
    """The formats to write: PNG plus those of ``$SETSMOOTH_FIGURE_FORMATS`` (`setsmooth.runs.cli`)."""
    return tuple(parse_formats(os.environ.get(FORMATS_ENV, "")))


class Stopwatch:
    """Wall time, and CPU time of this process plus its finished worker processes (Unix)."""

    def __init__(self):
        self.start = time.perf_counter()
        self.cpu_start = _cpu_time()

    @property
    def seconds(self) -> float:
        return round(time.perf_counter() - self.start, 2)

    @property
    def cpu_seconds(self) -> float | None:
        now = _cpu_time()
        return None if now is None else round(now - self.cpu_start, 2)


def _cpu_time() -> float | None:
    try:
        import resource
    except ImportError:   # Windows
        return None
    usage = [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    return sum(u.ru_utime + u.ru_stime for u in usage)


def row(quantity: str, paper: Any, ours: Any) -> dict:
    """One line of the report: a published value or claim beside ours."""
    return {"quantity": quantity, "paper": paper, "ours": ours}


def finish(out: Path | None, name: str, paper: str, fig, data: dict, clock: Stopwatch) -> dict:
    """Stamp ``data`` with its paper and timings, write ``<name>.png`` and ``<name>.json``, return it."""
    data = {"paper": paper, **data, "wall_time_s": clock.seconds, "cpu_time_s": clock.cpu_seconds}
    return write_outputs(out, name, fig, data)


def write_outputs(out: Path | None, name: str, fig, data: dict) -> dict:
    """Write ``<name>.png`` (plus the vector formats of `figure_formats`) and ``<name>.json`` to
    ``out`` (default ``paper_figures/out``); return ``data``."""
    out = Path(out) if out is not None else DEFAULT_OUT
    out.mkdir(parents=True, exist_ok=True)
    for fmt in figure_formats():
        # Vector formats keep text as text (fonttype 42 in PDF/EPS), so a paper's fonts can be edited.
        with _vector_fonts():
            fig.savefig(out / f"{name}.{fmt}", dpi=150, bbox_inches="tight", format=fmt)
    import matplotlib.pyplot as plt

    plt.close(fig)
    (out / f"{name}.json").write_text(json.dumps(jsonable(data), indent=1))
    return data


def _vector_fonts():
    import matplotlib

    return matplotlib.rc_context({"pdf.fonttype": 42, "ps.fonttype": 42, "svg.fonttype": "none"})


def jsonable(obj: Any) -> Any:
    """``obj`` with NumPy arrays and scalars as JSON types; non-finite floats as strings ('inf', 'nan')."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        return value if np.isfinite(value) else str(value)
    return obj


def cli(main: Callable[..., dict], default_runs: int, description: str, **options: dict) -> None:
    """``--runs --seed --out --workers`` for a figure script run on its own; prints its report rows.

    ``options``: the script's own keyword arguments of ``main``, each as the keyword arguments of
    `argparse.ArgumentParser.add_argument` (``offset={"choices": (...), "default": ...}`` makes ``--offset``).
    """
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--runs", type=int, default=default_runs,
                        help=f"Monte Carlo runs (default {default_runs})")
    parser.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output directory")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: 2)")
    parser.add_argument("--format", default="", help="extra formats besides PNG, e.g. pdf,svg")
    for name, spec in options.items():
        parser.add_argument(f"--{name.replace('_', '-')}", dest=name, **spec)
    args = parser.parse_args()
    try:
        os.environ[FORMATS_ENV] = ",".join(parse_formats(args.format))
    except ValueError as exc:
        parser.error(str(exc))
    result = main(runs=args.runs, seed=args.seed, out=args.out, workers=args.workers,
                  **{name: getattr(args, name) for name in options})
    for r in result["rows"]:
        print(f"{r['quantity']}: paper {r['paper']} | ours {r['ours']}")
