"""The verdict table at the top of REPORT.md, computed from the checks the figure scripts record.

A script adds ``"checks": [...]`` to its JSON, each made by `value` (published numbers beside ours) or
`claim` (a published statement that our numbers either bear out or not). The report decides each
check's verdict here, with the thresholds below, so that a verdict follows the numbers of the run that
wrote the JSON:

* **reproduced** — every number within ``max(SE_FACTOR · s.e., rel_tol · |paper|)`` of the paper's
  (``rel_tol`` is REL_TOL unless the check states its own), or the claim holds;
* **qualitatively** — a number is outside that band, but the shape the paper draws from it (an
  ordering, a ratio's direction, boundedness: stated in the check) holds in ours;
* **differs** — neither;
* **missing** — an item of the papers that no JSON in the directory reproduces;
* **not numerical** — the papers' schematic figures (`SCHEMATIC`).
"""

from __future__ import annotations

import math
from typing import Any

REL_TOL = 0.10
SE_FACTOR = 2.0

REPRODUCED, QUALITATIVELY, DIFFERS, MISSING, NOT_NUMERICAL = (
    "reproduced", "qualitatively", "differs", "missing", "not numerical")

#: The numerical items of each paper and the script that reproduces each (INDEX.md of the papers).
ITEMS = {
    "rethinking": {"Fig. 1": "rethinking_fig1", "Fig. 2": "rethinking_fig2", "Fig. 3": "rethinking_fig3"},
    "smoothing": {"Fig. 3": "smoothing_fig3", "Fig. 4": "smoothing_fig4", "Fig. 5": "smoothing_fig5",
                  "Fig. 6": "smoothing_fig6"},
    "stability": {"Fig. 2": "stability_fig2", "Fig. 3": "stability_fig3", "Fig. 4": "stability_fig4",
                  "Table 1": "stability_table1"},
    "lsu": {"Tables 1–2": "lsu_tables", "Fig. 1": "lsu_fig1", "Fig. 2": "lsu_fig2", "Fig. 3": "lsu_fig3"},
}
#: The papers' figures that draw no numbers (schematics of the method).
SCHEMATIC = {"smoothing": ("Fig. 1", "Fig. 2"), "stability": ("Fig. 1",)}


def value(item: str, ours, paper, se=None, *, rel_tol: float = REL_TOL, shape: str | None = None,
          shape_holds: bool | None = None, error: str | None = None) -> dict:
    """A check of published numbers: ``ours`` and ``paper`` (a number or equal-length lists), ``se`` the
    standard error of ours (None: no sampling error, e.g. the authors' own trajectory). ``shape``: what
    the paper concludes from the numbers, ``shape_holds``: whether ours bear it out. ``error`` describes
    the Monte Carlo error when ``se`` alone does not (runs, what the s.e. is over)."""
    listed = isinstance(ours, (list, tuple))
    return {"kind": "value", "item": item, "ours": list(ours) if listed else [ours],
            "paper": list(paper) if listed else [paper],
            "se": (list(se) if listed else [se]) if se is not None else None,
            "rel_tol": rel_tol, "shape": shape, "shape_holds": shape_holds, "error": error}


def claim(item: str, holds: bool, reason: str, error: str | None = None) -> dict:
    """A published statement and whether our numbers bear it out; ``reason`` says which numbers."""
    return {"kind": "claim", "item": item, "holds": bool(holds), "reason": reason, "error": error}


def verdict(check: dict) -> tuple[str, str]:
    """(verdict, one line of reason) of a check recorded by `value` or `claim`."""
    if check["kind"] == "claim":
        return (REPRODUCED if check["holds"] else DIFFERS), check["reason"]
    ours, paper = check["ours"], check["paper"]
    se = check.get("se") or [None] * len(ours)
    off = []
    for o, p, s in zip(ours, paper, se):
        band = max(SE_FACTOR * _number(s), check["rel_tol"] * abs(p))
        if not (_finite(o) and abs(o - p) <= band):
            off.append((o, p))
    shown = ", ".join(f"{_g(o)} vs {_g(p)}" for o, p in zip(ours, paper))
    if not off:
        return REPRODUCED, f"ours vs paper: {shown}; all within max({SE_FACTOR:g} s.e., " \
                           f"{check['rel_tol']:.0%})"
    worst = max(abs(o - p) / abs(p) if p else math.inf for o, p in off)
    why = f"ours vs paper: {shown}; {len(off)} of {len(ours)} outside the band (up to {worst:.0%} off)"
    if check.get("shape_holds"):
        return QUALITATIVELY, f"{why}; {check['shape']} holds"
    if check.get("shape") is not None and check.get("shape_holds") is False:
        return DIFFERS, f"{why}; {check['shape']} does not hold"
    return DIFFERS, why


def error_text(check: dict) -> str:
    """The Monte Carlo error behind a check, as a table cell."""
    if check.get("error"):
        return check["error"]
    se = check.get("se")
    if not se or all(s is None for s in se):
        return "none (deterministic)"
    return "s.e. " + ", ".join(_g(s) for s in se)


def table(by_paper: dict[str, dict[str, dict]]) -> list[str]:
    """Markdown lines of the verdict table for the figure JSONs ``by_paper[paper][name]``."""
    lines = ["| paper | item | verdict | reason | Monte Carlo error |", "| --- | --- | --- | --- | --- |"]
    for paper in dict.fromkeys([*ITEMS, *by_paper]):
        figures = by_paper.get(paper, {})
        for item in SCHEMATIC.get(paper, ()):
            lines.append(f"| {paper} | {item} | {NOT_NUMERICAL} | a schematic of the method, no numbers | — |")
        named = dict(ITEMS.get(paper, {}))
        named.update({name: name for name in figures if name not in named.values()})
        for label, name in named.items():
            data = figures.get(name)
            if data is None:
                lines.append(f"| {paper} | {label} | {MISSING} | no `{name}.json` in this directory | — |")
                continue
            checks = data.get("checks")
            if not checks:
                lines.append(f"| {paper} | {label} (`{name}`) | not assessed | the script records no "
                             f"checks; see its rows below | — |")
                continue
            for check in checks:
                decided, reason = verdict(check)
                lines.append(f"| {paper} | {label}: {_cell(check['item'])} | **{decided}** | {_cell(reason)} | "
                             f"{_cell(error_text(check))} |")
    return lines


def legend() -> str:
    return (f"Thresholds: *reproduced* when every number is within max({SE_FACTOR:g} × standard error, "
            f"{REL_TOL:.0%} of the paper's value) (a check may state another tolerance) or a claim holds; "
            "*qualitatively* when a number is outside that band but the shape the paper draws from it (named "
            "in the reason) holds; *differs* otherwise; *missing* when no script output is in this directory. "
            "Computed by `_verdicts.py` from the checks in each JSON.")


def _number(x: Any) -> float:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return 0.0
    return x if math.isfinite(x) else 0.0


def _finite(x: Any) -> bool:
    try:
        return math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def _g(x: Any) -> str:
    try:
        return f"{float(x):.3g}"
    except (TypeError, ValueError):
        return str(x)


def _cell(value: Any) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")
