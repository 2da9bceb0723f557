"""The order in which ``setsmooth figures`` starts its scripts: the longest first, after what they read.

Longest processing time first (Graham's LPT rule): started in decreasing order of their measured cost,
the scripts of a call share the workers with the long ones running from the start instead of ending
last. The costs are the CPU seconds of each script at its default size, measured and checked in as
``paper_figures/costs.json``; a script missing there goes after the measured ones (alphabetically).

A script that reads another's outputs names it in ``AFTER`` (a tuple of script names at module level,
read from its source without importing it): smoothing Fig. 5 reads Fig. 3's runs and Fig. 4's tuning,
the LSU figures share one cached experiment. Such a script starts only when those it follows (directly,
or through scripts not selected in this call) have finished, and a script's priority is its cost plus
the longest chain of costs waiting behind it. So what a script reads from another never depends on
which finished first, only on this order, and the outputs are those of running the scripts one after
the other in this order.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path

COSTS_FILE = "costs.json"


def read_costs(figures_dir: Path) -> dict[str, float]:
    """CPU seconds per script at its default size (``costs.json`` of ``figures_dir``); {} without one."""
    path = Path(figures_dir) / COSTS_FILE
    if not path.is_file():
        return {}
    return {name: float(value) for name, value in json.loads(path.read_text())["cpu_seconds"].items()}


def record_costs(out: Path, names: list[str], runs: int | None) -> Path:
    """Write ``<out>/costs.json``: the CPU seconds each script recorded in its JSON (``cpu_time_s``) in
    this call, in the format of `read_costs` (copy it over ``paper_figures/costs.json`` after a run at
    the default size, ``runs`` None, to refresh the order)."""
    measured = {}
    for name in names:
        path = Path(out) / f"{name}.json"
        if path.is_file():
            cpu = json.loads(path.read_text()).get("cpu_time_s")
            if isinstance(cpu, (int, float)):
                measured[name] = round(float(cpu), 1)
    target = Path(out) / COSTS_FILE
    target.write_text(json.dumps({"note": "CPU seconds of each script (its process and its Monte Carlo "
                                          "workers) in the last setsmooth figures call, recorded by it",
                                  "runs": runs if runs is not None else "default",
                                  "cpu_seconds": measured}, indent=1) + "\n")
    return target


def read_after(figures_dir: Path, names: list[str]) -> dict[str, tuple[str, ...]]:
    """Each script's ``AFTER`` tuple (the scripts whose outputs it reads), from its source."""
    return {name: _after(Path(figures_dir) / f"{name}.py") for name in names}


def _after(path: Path) -> tuple[str, ...]:
    for node in ast.parse(path.read_text(), str(path)).body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "AFTER"
                                                for t in node.targets):
            value = ast.literal_eval(node.value)
            if not (isinstance(value, tuple) and all(isinstance(v, str) for v in value)):
                raise ValueError(f"{path.name}: AFTER must be a tuple of script names, got {value!r}")
            return value
    return ()


def prerequisites(names: list[str], after: dict[str, tuple[str, ...]]) -> dict[str, set[str]]:
    """For each selected script, the selected scripts it must wait for: those it follows directly or
    through a chain of scripts (selected or not).

    Raises
    ------
    ValueError
        When a script follows itself through its chain (the declarations form a cycle).
    """
    chosen = set(names)
    out: dict[str, set[str]] = {}
    for name in names:
        seen: set[str] = set()
        stack = list(after.get(name, ()))
        while stack:
            other = stack.pop()
            if other == name:
                raise ValueError(f"the AFTER declarations form a cycle through {name}")
            if other in seen:
                continue
            seen.add(other)
            stack.extend(after.get(other, ()))
        out[name] = seen & chosen
    return out


def priorities(names: list[str], costs: dict[str, float], waits: dict[str, set[str]]) -> dict[str, float]:
    """A script's cost plus the costliest chain of scripts that wait for it (its "bottom level")."""
    followers = {name: [other for other in names if name in waits[other]] for name in names}
    level: dict[str, float] = {}

    def bottom(name: str) -> float:
        if name not in level:
            level[name] = costs.get(name, 0.0) + max((bottom(f) for f in followers[name]), default=0.0)
        return level[name]

    return {name: bottom(name) for name in names}


def plan(names: list[str], costs: dict[str, float], after: dict[str, tuple[str, ...]] | None = None
         ) -> list[str]:
    """The start order: among the scripts whose prerequisites come earlier, the highest priority
    first (measured scripts by `priorities`, unmeasured ones after them, alphabetically; ties by name).

    A script is started only when its prerequisites have finished (`prerequisites`), so with several
    workers the runner also waits; this order is the one it starts them in when none is waiting.

    Examples
    --------
    >>> plan(["a", "b", "c"], {"a": 1.0, "b": 30.0, "c": 5.0})
    ['b', 'c', 'a']
    >>> plan(["a", "b", "c"], {"a": 1.0, "b": 30.0, "c": 5.0}, after={"b": ("a",)})
    ['a', 'b', 'c']
    >>> plan(["new", "b"], {"b": 30.0})
    ['b', 'new']
    """
    waits = prerequisites(names, after or {})
    level = priorities(names, costs, waits)
    order: list[str] = []
    while len(order) < len(names):
        ready = [n for n in names if n not in order and waits[n] <= set(order)]
        order.append(min(ready, key=lambda n: rank(n, costs, level)))
    return order


def rank(name: str, costs: dict[str, float], level: dict[str, float]) -> tuple:
    """Sort key: measured before unmeasured, then the higher priority, then the name."""
    return (name not in costs, -level[name], name)
