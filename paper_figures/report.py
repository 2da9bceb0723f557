"""Write ``REPORT.md``: every published value or claim of the reproduced figures beside ours.

Reads the ``<name>.json`` files the figure scripts wrote to the output directory (their ``rows``,
``settings``, ``notes`` and ``wall_time_s``), so it can be rerun on its own:
``python paper_figures/report.py [--out DIR]``.
"""

from __future__ import annotations

import argparse
import json
import platform
from datetime import datetime, timezone
from pathlib import Path

import _smoothing_examples as ex

DEFAULT_OUT = Path(__file__).resolve().parent / "out"

PREAMBLE = """\
Reproduction of the numerical section (IV-C) of the smoothing paper with `setsmooth`. Each section lists
the published value or qualitative claim beside ours; the plotted numbers are in `<name>.json`.

Conventions shared by all figures:
- Noises are uniform on their ranges (paper footnote 3). The paper does not state the initial range
  ⟦x_0⟧; we use {X0_LINEAR} for the linear example (31) and {X0_NONLINEAR} for the nonlinear
  example (33)–(34), and draw x_0 uniformly from it.
- Smoothed ranges of (31) are those of Algorithm 1 (eq. (24)), computed as projections of the
  trajectory set (`optimal_smoother(method="trajectory")`: the same sets, O(T) instead of O(T²));
  posterior ranges come from `classical_filter` (the optimal SMF). Diameters are ∞-norm diameters of
  certified interval hulls.
- MSE_k = mean over runs of ‖x̂_k − x_k‖₂²; Fig. 4 averages it over k ∈ [0, 50] too.
- Runs are seeded with `numpy.random.SeedSequence(seed).spawn(runs)`; identical for any worker count.
""".format(X0_LINEAR=ex.describe_box(*ex.X0_LINEAR), X0_NONLINEAR=ex.describe_box(*ex.X0_NONLINEAR))


def _cell(value) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")


def section(name: str, data: dict) -> str:
    settings = data.get("settings", {})
    runs = settings.get("runs", settings.get("runs_per_pair"))
    published = data.get("published", {})
    paper_runs = published.get("runs", published.get("runs_per_pair"))
    unit = "runs per (q, r) pair" if "runs_per_pair" in settings else "runs"
    lines = [f"## {data.get('figure', name)} — `{name}`", "",
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
    figures = {}
    for path in sorted(out.glob("*.json")):
        data = json.loads(path.read_text())
        if isinstance(data, dict) and "rows" in data:
            figures[path.stem] = data
    total = sum(float(d.get("wall_time_s", 0)) for d in figures.values())
    header = ["# Paper figures: published vs reproduced", "",
              f"Generated {datetime.now(timezone.utc):%Y-%m-%d %H:%M UTC} on {platform.node() or 'unknown'} "
              f"(Python {platform.python_version()}); total figure wall time {total:.0f} s.", "", PREAMBLE]
    if not figures:
        header.append("No figure results found in this directory.\n")
    body = [section(name, data) for name, data in figures.items()]
    report = out / "REPORT.md"
    out.mkdir(parents=True, exist_ok=True)
    report.write_text("\n".join(header + body))
    return report


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="directory holding the figure JSON files")
    print(main(parser.parse_args().out))
