"""Write ``REPORT.md``: a verdict table, then every published value or claim of the figures beside ours, by paper.

Reads the ``<name>.json`` files the figure scripts wrote to the output directory (their ``paper``,
``rows``, ``checks``, ``settings``, ``notes`` and ``wall_time_s``; the protocol is in ``_outputs.py``;
the verdicts and their thresholds in ``_verdicts.py``), so it can
be rerun on its own: ``python paper_figures/report.py [--out DIR]``. Each paper's title and
conventions come from its ``_<paper>_examples.py`` (``PAPER_TITLE``, ``REPORT_PREAMBLE``).
"""

from __future__ import annotations

import argparse
import importlib
import json
import platform
from datetime import datetime, timezone
from pathlib import Path

import _verdicts
from _outputs import DEFAULT_OUT

#: Heading of the figures whose JSON names no paper (written before the protocol had the key).
UNKNOWN_PAPER = "other"


def _cell(value) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")


def paper_header(paper: str) -> list[str]:
    """``# title`` and the paper's conventions, from ``_<paper>_examples.py`` when it exists."""
    try:
        module = importlib.import_module(f"_{paper}_examples")
    except ImportError:
        return [f"## {paper} paper", ""]
    return [f"## {getattr(module, 'PAPER_TITLE', paper)}", "", getattr(module, "REPORT_PREAMBLE", "")]


def section(name: str, data: dict) -> str:
    settings = data.get("settings", {})
    runs = settings.get("runs", settings.get("runs_per_pair"))
    published = data.get("published", {})
    paper_runs = published.get("runs", published.get("runs_per_pair"))
    unit = "runs per (q, r) pair" if "runs_per_pair" in settings else "runs"
    lines = [f"### {data.get('figure', name)} — `{name}`", "",
             f"![{name}]({name}.png)", "",
             f"Size: {runs} {unit} (paper: {paper_runs}); seed {settings.get('seed')}; "
             f"wall time {data.get('wall_time_s', '?')} s (CPU {data.get('cpu_time_s', '?')} s).", "",
             "| quantity | paper | ours |", "| --- | --- | --- |"]
    lines += [f"| {_cell(r['quantity'])} | {_cell(r['paper'])} | {_cell(r['ours'])} |" for r in data["rows"]]
    details = {k: v for k, v in settings.items() if k not in ("runs", "runs_per_pair", "seed")}
    if details:
        lines += ["", "Settings:"]
        lines += [f"- {k}: {v if isinstance(v, str) else json.dumps(v, ensure_ascii=False)}"
                  for k, v in details.items()]
    if data.get("notes"):
        lines += ["", "Notes:"] + [f"- {note}" for note in data["notes"]]
    return "\n".join(lines) + "\n"


def main(out: Path | None = None) -> Path:
    """Write ``out/REPORT.md`` from the figure JSON files in ``out`` and return its path."""
    out = Path(out) if out is not None else DEFAULT_OUT
    by_paper: dict[str, dict[str, dict]] = {}
    for path in sorted(out.glob("*.json")):
        data = json.loads(path.read_text())
        if isinstance(data, dict) and "rows" in data:
            by_paper.setdefault(data.get("paper", UNKNOWN_PAPER), {})[path.stem] = data
    figures_all = [d for figures in by_paper.values() for d in figures.values()]
    wall = sum(float(d.get("wall_time_s", 0)) for d in figures_all)
    cpu = sum(float(d.get("cpu_time_s", 0)) for d in figures_all)
    lines = ["# Paper figures: published vs reproduced", "",
             f"Generated {datetime.now(timezone.utc):%Y-%m-%d %H:%M UTC} on {platform.node() or 'unknown'} "
             f"(Python {platform.python_version()}) with `setsmooth`; the figures' own times sum to "
             f"{cpu:.0f} CPU-s and {wall:.0f} wall-s (figures run side by side, so the run itself took "
             "less wall time than that sum).",
             ""]
    if by_paper:
        lines += ["Papers: " + ", ".join(f"{paper} ({len(figs)} figures)" for paper, figs in by_paper.items()),
                  "", "## Verdicts", "", _verdicts.legend(), "", *_verdicts.table(by_paper), ""]
    else:
        lines.append("No figure results found in this directory.\n")
    for paper, figures in by_paper.items():
        lines += paper_header(paper)
        lines += [section(name, data) for name, data in figures.items()]
    report = out / "REPORT.md"
    out.mkdir(parents=True, exist_ok=True)
    report.write_text("\n".join(lines))
    return report


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="directory holding the figure JSON files")
    print(main(parser.parse_args().out))
