"""LSU paper Fig. 3: STD against K — the posterior standard deviation of the approximations, ours.

STD is not defined in the paper; we plot the standard deviation of x_t under the uniform density on
each filter's support (averaged over t = 1..600 and the components; one value for LSUCZ-1/2/centroid,
which share the support), as the paper's remark that "both LSUCZ variants" behave alike suggests.
The JSON also holds the standard deviation of the estimation error. The paper gives no numbers for
Fig. 3, only the claims checked below. The experiment is shared with `lsu_tables` (cached).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import _lsu_examples as ex
import _verdicts
from _outputs import Stopwatch, cli, finish, row

NAME = "lsu_fig3"
PAPER = ex.PAPER
DEFAULT_RUNS = 3
AFTER = ("lsu_fig2",)     # the shared experiment: see lsu_fig2.AFTER


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, **experiment) -> dict:
    clock = Stopwatch()
    exp = ex.experiment(runs, seed, out, workers, progress, executor, **experiment)
    K = np.array(exp["settings"]["K"])
    mean, se = ex.mean_se(exp["metrics"][..., ex.METRICS.index("posterior_std")] * 1e3)
    err, err_se = ex.mean_se(exp["metrics"][..., ex.METRICS.index("error_std")] * 1e3)
    cz, lsuo, lsup = (ex.ESTIMATORS.index(e) for e in ("LSUCZ-1", "LSUO", "LSUP-kept"))  # the paper's LSUP
    top = int(np.argmin(K))
    low = K >= 2.5
    spread = mean[low][:, [cz, lsuo, lsup]]
    rows = [
        row("STD at low noise (K ≥ 2.5): comparable for all filters", "yes (plot)",
            f"max/min ratio over filters {np.max(spread.max(1) / spread.min(1)):.2f}"),
        row(f"STD at the highest noise (K = {K[top]:g}): both LSUCZ variants smaller than LSUO, LSUP",
            "yes (plot)", f"LSU-CZ {mean[top, cz]:.3g}, LSUO {mean[top, lsuo]:.3g}, LSUP {mean[top, lsup]:.3g} "
                          f"(·10³)"),
    ]
    fig = ex.curve_figure(exp, "posterior_std", None, "posterior STD·10³",
                          f"Fig. 3: STD of the uniform approximations ({exp['settings']['runs']} runs)")
    smaller = all(mean[top, other] - mean[top, cz] > 2 * np.hypot(se[top, other], se[top, cz])
                  for other in (lsuo, lsup))
    checks = [_verdicts.claim(
        f"at the highest noise (K = {K[top]:g}) the LSU-CZ STD is below LSUO's and LSUP's (kept shape) by "
        "more than 2 s.e.", smaller,
        f"LSU-CZ {mean[top, cz]:.3g} ± {se[top, cz]:.2g}, LSUO {mean[top, lsuo]:.3g} ± {se[top, lsuo]:.2g}, "
        f"LSUP {mean[top, lsup]:.3g} ± {se[top, lsup]:.2g} (·10³)",
        f"s.e. over {exp['settings']['runs']} runs")]
    data = {"figure": "LSU paper Fig. 3", "rows": rows, "checks": checks, "settings": ex.common_settings(exp),
            "published": {"runs": ex.PAPER_RUNS, "values": "plot only"},
            "K": K, "estimators": ex.ESTIMATORS, "mean": mean, "se": se, "error_std_mean": err,
            "error_std_se": err_se}
    return finish(out, NAME, PAPER, fig, data, clock)


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
