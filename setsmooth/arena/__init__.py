"""The arena: estimators and set representations compared on one zoo of problems, in one command.

``setsmooth arena --problems ... --estimators ... --runs N`` (or `run_arena`) runs every chosen
estimator on every chosen problem over seeded Monte Carlo runs and reports, per pair, soundness (true
states outside the estimator's hulls; containment of the exact estimator's hulls), tightness (mean
radius, hull volume over the exact one's, Hausdorff distance to the exact sets on 2-D problems) and
CPU time per step, as a JSON record, a markdown table and a figure. A new estimator enters with one call, ``register(name, fn)``. One module per job:

* `problems`: the zoo (`PROBLEMS`, `make_problem`);
* `estimators`: the registry (`register`, `ESTIMATORS`, `hull_tubes`), each estimator declaring the
  systems it applies to (`STRUCTURES`);
* `scalar`: scalar systems with increasing dynamics (`MonotoneScalarSystem`), the interval filter's class;
* `metrics`: soundness and tightness from interval hulls, and the Hausdorff gap of 2-D sets;
* `runner`: the Monte Carlo (`run_arena`);
* `report`: table, JSON and figure (`write_outputs`);
* `command`: the ``setsmooth arena`` subcommand.

Names are imported on first use, so that the command line's parser does not load the solvers.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

_EXPORTS = {
    **dict.fromkeys(["Problem", "PROBLEMS", "make_problem", "problem_names"], ".problems"),
    **dict.fromkeys(["Estimator", "ESTIMATORS", "REFERENCES", "STRUCTURES", "register", "unregister",
                     "hull_tubes"], ".estimators"),
    "MonotoneScalarSystem": ".scalar",
    **dict.fromkeys(["ArenaResult", "run_arena"], ".runner"),
    **dict.fromkeys(["markdown_table", "plot_arena", "write_outputs"], ".report"),
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'setsmooth.arena' has no attribute {name!r}")
    value = getattr(import_module(_EXPORTS[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
