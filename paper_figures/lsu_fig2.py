"""LSU paper Fig. 2: MAE of the state estimates against K, ours beside the paper's Table 2 values.

The experiment is shared with `lsu_tables` (`_lsu_examples.experiment`, cached). Ours: mean ± standard
error over runs; dashed: the paper's numbers (Table 2, which Fig. 2 plots).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import _lsu_examples as ex
from _outputs import Stopwatch, cli, finish, row

NAME = "lsu_fig2"
PAPER = ex.PAPER
DEFAULT_RUNS = 3
METRIC = "mae"


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, **experiment) -> dict:
    clock = Stopwatch()
    exp = ex.experiment(runs, seed, out, workers, progress, executor, **experiment)
    K = exp["settings"]["K"]
    mean, se = ex.mean_se(exp["metrics"][..., ex.METRICS.index(METRIC)] * 1e3)
    idx = [ex.ESTIMATORS.index(e) for e in ex.PAPER_ESTIMATORS]
    rows = []
    for i, k in enumerate(K):
        pub = ex.PUBLISHED_MAE.get(k)
        rows.append(row(f"MAE·10³ at K = {k:g}, best → worst", ex.ordering(np.array(pub, dtype=float))
                        if pub and None not in pub else "all < 1e-3",
                        ex.ordering(mean[i, idx]) + f" (centroid {mean[i, ex.ESTIMATORS.index('LSUCZ-c')]:.3g}"
                        f" vs LSUCZ-1 {mean[i, 0]:.3g}; LSUP kept shape "
                        f"{mean[i, ex.ESTIMATORS.index('LSUP-kept')]:.3g} vs paper LSUP "
                        f"{pub[3] if pub and pub[3] is not None else '< 1e-3'})"))
    title = f"Fig. 2: MAE of the state estimates ({exp['settings']['runs']} runs)"
    fig = ex.curve_figure(exp, METRIC, ex.PUBLISHED_MAE, "MAE·10³", title)
    data = {"figure": "LSU paper Fig. 2", "rows": rows, "settings": ex.common_settings(exp),
            "published": {"runs": ex.PAPER_RUNS, "values": ex.PUBLISHED_MAE},
            "K": K, "estimators": ex.ESTIMATORS, "mean": mean, "se": se}
    return finish(out, NAME, PAPER, fig, data, clock)


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
