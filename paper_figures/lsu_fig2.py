"""LSU paper Fig. 2: MAE of the state estimates against K, ours beside the paper's Table 2 values.

The experiment is shared with `lsu_tables` (`_lsu_examples.experiment`, cached). Ours: mean ± standard
error over runs; dashed: the paper's numbers (Table 2, which Fig. 2 plots).
"""

from __future__ import annotations

from pathlib import Path

import _lsu_examples as ex
from _outputs import cli

NAME = "lsu_fig2"
PAPER = ex.PAPER
DEFAULT_RUNS = 3
#: The first of lsu_fig1, lsu_fig2, lsu_fig3, lsu_tables to run computes the shared experiment, the others
#: read it back; `setsmooth figures` runs them in this chain, so which one computes never depends on timing.
AFTER = ("lsu_fig1",)
METRIC = "mae"


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, **experiment) -> dict:
    return ex.error_curve_main(NAME, METRIC, "MAE", ex.PUBLISHED_MAE, 2, 2, runs, seed, out, workers,
                               progress, executor, **experiment)


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
