"""LSU paper Fig. 1: RMSE of the state estimates against K, ours beside the paper's Table 1 values.

The experiment is shared with `lsu_tables` (`_lsu_examples.experiment`, cached). Ours: mean ± standard
error over runs; dashed: the paper's numbers (Table 1, which Fig. 1 plots).
"""

from __future__ import annotations

from pathlib import Path

import _lsu_examples as ex
from _outputs import cli

NAME = "lsu_fig1"
PAPER = ex.PAPER
DEFAULT_RUNS = 3
METRIC = "rmse"


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, **experiment) -> dict:
    return ex.error_curve_main(NAME, METRIC, "RMSE", ex.PUBLISHED_RMSE, 1, 1, runs, seed, out, workers,
                               progress, executor, **experiment)


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
