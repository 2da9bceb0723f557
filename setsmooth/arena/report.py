"""The arena's outputs: a markdown table, a JSON record and a figure (tightness against time per problem).

Unsound entries are flagged: "UNSOUND" in the table, red crosses in the figure. A pair whose estimator
does not apply to the problem's system is a row marked "n/a" in the table and left out of the figure.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from . import metrics
from .runner import ArenaResult

__all__ = ["markdown_table", "plot_arena", "write_outputs"]

_COLUMNS = ("problem", "estimator", "runs", "truth outside", "contains exact", "mean radius",
            "volume / exact", "d_H to exact", "CPU ms/step", "verdict")


def markdown_table(result: ArenaResult) -> str:
    """The rows as a markdown table, with a line stating the tolerances of the containment test."""
    show_memory = result.config.get("memory", False)
    columns = _COLUMNS[:-1] + (("peak MiB",) if show_memory else ()) + _COLUMNS[-1:]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for row in result.rows:
        if not row.get("applicable", True):
            cells = [row["problem"], row["estimator"], "0", "n/a", "n/a", "", "", "", ""]
            cells += [""] if show_memory else []
            cells += [f"n/a: {row['not_applicable']}"]
        elif row["sound"] is None:
            cells = [row["problem"], row["estimator"], "0", "", "", "", "", "", ""]
            cells += [""] if show_memory else []
            cells += [f"error: {_short(row['error'])}"]
        else:
            cells = [row["problem"], row["estimator"], str(row["runs"]),
                     f"{row['outside']}/{row['steps']}", _containment(row), _number(row["mean_radius"]),
                     _number(row["volume_ratio"]), _number(row["hausdorff_gap"]),
                     f"{row['cpu_ms_per_step']:.2f}"]
            cells += [_number(row["peak_mib"])] if show_memory else []
            verdict = "sound" if row["sound"] else "**UNSOUND**"
            if row["errors"]:
                verdict += f" ({row['errors']} runs failed: {_short(row['error'])})"
            cells.append(verdict)
        lines.append("| " + " | ".join(cells) + " |")
    refs = ", ".join(f"{kind}: {name}" for kind, name in result.config.get("references", {}).items())
    lines.append("")
    lines.append(f"Reference (exact) per kind: {refs or 'none'}. 'contains exact': runs whose hulls "
                 f"contain the reference's at every step, up to {metrics.CONTAINMENT_RTOL:g} of its width "
                 f"+ {metrics.CONTAINMENT_ATOL:g}·max(1, |bound|) (largest shortfall in brackets, as a "
                 "fraction of the width). 'd_H to exact' (2-D problems): Hausdorff distance (2-norm) "
                 "of the sets to the reference's at k = T/2 and T, the larger, mean over runs. "
                 "CPU: estimator plus its interval hulls, per step. 'n/a': not run, the estimator "
                 "does not apply to the problem's system (its declared applies_to).")
    return "\n".join(lines)


def _containment(row: dict) -> str:
    if not row["containment_checked"]:
        return "no exact reference"
    passed = row["runs"] - row["containment_failures"]
    gap = row["containment_gap"]
    return f"{passed}/{row['runs']}" + (f" ({gap:.1e})" if gap is not None and gap > 0 else "")


def _number(value: Any) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    return f"{value:.4g}"


def _short(text: str | None, limit: int = 60) -> str:
    text = (text or "").replace("|", "/").replace("\n", " ")
    return text if len(text) <= limit else text[:limit - 1] + "…"


def plot_arena(result: ArenaResult):
    """Tightness (hull volume / exact; mean radius where no reference) against CPU time per step.

    One panel per problem, log-log; an unsound estimator is a red cross with "(unsound)" in its label.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    problems = result.config["problems"]
    cols = min(3, len(problems))
    nrows = math.ceil(len(problems) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.4 * nrows), squeeze=False)
    for ax, problem in zip(axes.flat, problems):
        rows = [r for r in result.rows if r["problem"] == problem and r["sound"] is not None]
        use_ratio = any(not math.isnan(r["volume_ratio"]) for r in rows)
        for i, r in enumerate(rows):
            y = r["volume_ratio"] if use_ratio else r["mean_radius"]
            if y is None or math.isnan(y) or y <= 0:
                continue
            unsound = not r["sound"]
            marker = "x" if unsound else ("s" if r["kind"] == "smoothed" else "o")
            ax.scatter(r["cpu_ms_per_step"], y, marker=marker, s=40,
                       color="tab:red" if unsound else "tab:blue", zorder=3)
            # alternate above and below, so that estimators at one volume (the exact ones) stay legible
            ax.annotate(r["estimator"] + (" (unsound)" if unsound else ""), (r["cpu_ms_per_step"], y),
                        textcoords="offset points", xytext=(4, 4 if i % 2 == 0 else -11), fontsize=7,
                        color="tab:red" if unsound else "black")
        if use_ratio:
            ax.axhline(1.0, color="grey", lw=0.8, ls=":", zorder=1)   # the exact estimator's volume
        for axis, set_scale in ((ax.xaxis, ax.set_xscale), (ax.yaxis, ax.set_yscale)):
            set_scale("log")
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            axis.set_minor_formatter(NullFormatter())
        ax.margins(0.2)
        ax.set_title(problem, fontsize=9)
        ax.set_xlabel("CPU ms per step (estimator + hulls)", fontsize=8)
        ax.set_ylabel("hull volume / exact" if use_ratio else "mean radius", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(problems):]:
        ax.set_visible(False)
    fig.suptitle(f"setsmooth arena: {result.config['runs']} runs, seed {result.config['seed']}   "
                 "(○ filter / exact filter, □ smoother / exact smoother, red × unsound)", fontsize=10)
    fig.tight_layout()
    return fig


def write_outputs(result: ArenaResult, out: Path | str) -> dict[str, Path]:
    """Write ``arena.json``, ``arena.md`` and ``arena.png`` to ``out`` (created); return their paths."""
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"json": out / "arena.json", "markdown": out / "arena.md", "figure": out / "arena.png"}
    record = {"config": result.config, "seconds": result.seconds, "rows": result.rows,
              "tolerances": {"truth_atol": metrics.TRUTH_ATOL, "containment_rtol": metrics.CONTAINMENT_RTOL,
                             "containment_atol": metrics.CONTAINMENT_ATOL}}
    paths["json"].write_text(json.dumps(_plain(record), indent=2) + "\n", encoding="utf-8")
    paths["markdown"].write_text(f"# setsmooth arena\n\n{markdown_table(result)}\n\n"
                                 f"![arena]({paths['figure'].name})\n", encoding="utf-8")
    fig = plot_arena(result)
    fig.savefig(paths["figure"], dpi=130)
    plt.close(fig)
    return paths


def _plain(value: Any) -> Any:
    """JSON-safe copy: NaN and infinities as strings (JSON has neither)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        return _plain(value.item())
    return value
