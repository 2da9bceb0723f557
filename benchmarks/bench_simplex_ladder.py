"""The simplex fallback's tolerance ladder (`setsmooth.solvers.highs.SIMPLEX_TOLERANCES`), side
by side in one run against the single tight rung it replaced.

The recursion smoother (Algorithm 1) is the estimator whose support programs fall back to HiGHS most
(degenerate sets, copies of the posterior factors linked by the states). Each case below computes
the plain and certified interval hulls of every smoothed set in three configurations, alternating:

* ``tight``: the first fallback, one cold HiGHS solve (SciPy's ``linprog``) at feasibility
  tolerances 1e-10 with no iteration cap (patched in for this benchmark only);
* ``cold``: the ladder 1e-10, then 1e-9, then HiGHS's defaults, each rung capped, every objective
  from scratch (`highs.simplex_cold`);
* ``warm``: as built, the same ladder on one kept HiGHS model per program, warm-started from the last
  objective's basis (`warm_simplex.WarmSimplex`).

It prints the median CPU seconds of each, the ratios to ``tight``, the simplex fallback calls, and
the largest difference between ``warm``'s hull endpoints and the others' relative to the hull width
plus the noise scale (the accuracy demanded by issue 7 is 1e-6).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_simplex_ladder.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from setsmooth.solvers import highs, warm_simplex  # noqa: E402
from setsmooth.solvers.backends import BACKENDS  # noqa: E402
from benchmarks.side_by_side import hulls as estimator_hulls  # noqa: E402
from setsmooth.reliability.oracle import data_scale  # noqa: E402
from setsmooth.reliability.random_systems import base_case, in_regime  # noqa: E402

#: (reliability index, horizon T, regime): case 000 at T = 20 is where the tight rung cycled; 029
#: and 018 (CZ noises) are where the fallback's solves are largest.
CASES = ((0, 20, "scale1"), (29, 20, "scale1"), (18, 20, "offset1e+06"))


@contextlib.contextmanager
def configured(config: str, calls: collections.Counter):
    """Patch the support fallback to ``config`` ('tight', 'cold' or 'warm') and count its calls."""
    saved = (dict(BACKENDS), highs.SIMPLEX_TOLERANCES, warm_simplex.SIMPLEX_TOLERANCES,
             highs.rung_iterations)
    if config == "tight":
        highs.SIMPLEX_TOLERANCES = warm_simplex.SIMPLEX_TOLERANCES = (1e-10,)
        highs.rung_iterations = lambda size, last: 2 ** 31 - 1
    fallback = BACKENDS["simplex" if config == "warm" else "simplex cold"]

    def counted(pre, q, batch=None):
        calls[config] += 1
        return fallback(pre, q, batch)

    BACKENDS["simplex"] = counted
    try:
        yield
    finally:
        BACKENDS.update(saved[0])
        highs.SIMPLEX_TOLERANCES, warm_simplex.SIMPLEX_TOLERANCES, highs.rung_iterations = saved[1:]


def hulls(case) -> np.ndarray:
    """Plain and certified hull endpoints of every set of the recursion smoother on ``case``."""
    return estimator_hulls(case, "recursion")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--configs", default="tight,cold,warm",
                    help="comma-separated subset of tight, cold, warm (warm is required)")
    args = ap.parse_args()
    configs = tuple(c.strip() for c in args.configs.split(",") if c.strip())
    if "warm" not in configs or not set(configs) <= {"tight", "cold", "warm"}:
        ap.error("--configs must be a subset of tight,cold,warm including warm, "
                 f"got {args.configs!r}")
    print(f"{'case':<40} {'tight s':>8} {'cold s':>8} {'warm s':>8} {'cold/tight':>10} "
          f"{'warm/tight':>10} {'warm/cold':>9}  {'fallback calls t/c/w':<20} {'max diff':>9}")
    ratios = collections.defaultdict(list)
    for index, T, regime in CASES:
        case = in_regime(base_case(2026, index, T_range=(T, T)), regime)
        times = {c: [] for c in configs}
        calls: collections.Counter = collections.Counter()
        result = {}
        for _ in range(args.repeats):
            for config in configs:
                with configured(config, calls):
                    start = time.process_time()
                    result[config] = hulls(case)
                    times[config].append(time.process_time() - start)
        n = case.system.n
        lo, hi = result["warm"][:, :n], result["warm"][:, n:]
        unit = np.concatenate([hi - lo, hi - lo], axis=1) + data_scale(case.system, case.X0)
        diff = max(float(np.max(np.abs(result["warm"] - result[c]) / unit)) for c in configs)
        t = {c: float(np.median(times[c])) for c in configs}
        for a, b in (("cold", "tight"), ("warm", "tight"), ("warm", "cold")):
            ratios[a, b].append(t[a] / t[b] if a in t and b in t else float("nan"))
        counts = "/".join(str(calls[c] // args.repeats) if c in t else "-" for c in
                          ("tight", "cold", "warm"))
        seconds = " ".join(f"{t.get(c, float('nan')):8.2f}" for c in ("tight", "cold", "warm"))
        print(f"{case.name + f' T={T}':<40} {seconds} "
              f"{ratios['cold', 'tight'][-1]:10.3f} {ratios['warm', 'tight'][-1]:10.3f} "
              f"{ratios['warm', 'cold'][-1]:9.3f}  {counts:<20} {diff:9.1e}")
    print("\nmedian ratios: " + ", ".join(f"{a}/{b} {np.median(v):.3f}"
                                         for (a, b), v in ratios.items() if np.isfinite(v).all()))


if __name__ == "__main__":
    main()
