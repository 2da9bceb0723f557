"""The simplex fallback's tolerance ladder (`setsmooth.solvers.presolve.SIMPLEX_TOLERANCES`), side
by side in one run against the single tight rung it replaced.

The recursion smoother (Algorithm 1) is the estimator whose support programs fall back to HiGHS most
(degenerate sets, copies of the posterior factors linked by the states). Each case below computes
the plain and certified interval hulls of every smoothed set twice, alternating:

* ``tight``: the former fallback, one HiGHS solve at feasibility tolerances 1e-10 with no iteration
  cap (patched in for this benchmark only);
* ``ladder``: as built, 1e-10, then 1e-9, then HiGHS's defaults, each rung capped.

It prints the median CPU seconds of each, their ratio, the HiGHS calls by outcome, and the largest
difference between the two configurations' hull endpoints relative to the hull width plus the noise
scale (the accuracy demanded by issue 7 is 1e-6).

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

import setsmooth as ss  # noqa: E402
from setsmooth.solvers import presolve  # noqa: E402
from tests.reliability.oracle import data_scale  # noqa: E402
from tests.reliability.random_systems import base_case, in_regime  # noqa: E402

#: (reliability index, horizon T, regime): case 000 at T = 20 is where the tight rung cycled.
CASES = ((0, 20, "scale1"), (8, 20, "scale1e-06"), (18, 20, "offset1e+06"))


@contextlib.contextmanager
def tight_only():
    """The former fallback: one rung at 1e-10, uncapped."""
    saved = presolve.SIMPLEX_TOLERANCES, presolve._rung_iterations
    presolve.SIMPLEX_TOLERANCES = (1e-10,)
    presolve._rung_iterations = lambda size, last: 2 ** 31 - 1
    try:
        yield
    finally:
        presolve.SIMPLEX_TOLERANCES, presolve._rung_iterations = saved


@contextlib.contextmanager
def counted(counts: collections.Counter):
    """Count the HiGHS calls of the support fallback by SciPy status."""
    import scipy.optimize

    real = scipy.optimize.linprog

    def linprog(*args, **kwargs):
        res = real(*args, **kwargs)
        counts[res.status] += 1
        return res

    scipy.optimize.linprog = linprog
    try:
        yield
    finally:
        scipy.optimize.linprog = real


def hulls(case) -> np.ndarray:
    out = []
    for S in ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion"):
        for certified in (False, True):
            H = S.interval_hull(certified=certified)
            out.append(np.concatenate([H.lo, H.hi]))
    return np.array(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    print(f"{'case':<40} {'tight s':>9} {'ladder s':>9} {'ratio':>7}  {'HiGHS calls tight':<22} "
          f"{'HiGHS calls ladder':<22} {'max diff':>9}")
    ratios = []
    for index, T, regime in CASES:
        case = in_regime(base_case(2026, index, T_range=(T, T)), regime)
        times = {"tight": [], "ladder": []}
        counts = {"tight": collections.Counter(), "ladder": collections.Counter()}
        result = {}
        for _ in range(args.repeats):
            for config in ("tight", "ladder"):
                patch = tight_only() if config == "tight" else contextlib.nullcontext()
                with patch, counted(counts[config]):
                    start = time.process_time()
                    result[config] = hulls(case)
                    times[config].append(time.process_time() - start)
        n = case.system.n
        lo, hi = result["ladder"][:, :n], result["ladder"][:, n:]
        unit = np.concatenate([hi - lo, hi - lo], axis=1) + data_scale(case.system, case.X0)
        diff = float(np.max(np.abs(result["ladder"] - result["tight"]) / unit))
        t_tight, t_ladder = np.median(times["tight"]), np.median(times["ladder"])
        ratios.append(t_ladder / t_tight)

        def calls(c):
            return ", ".join(f"{k}:{v // args.repeats}" for k, v in sorted(c.items()))

        print(f"{case.name + f' T={T}':<40} {t_tight:9.2f} {t_ladder:9.2f} {ratios[-1]:7.3f}  "
              f"{calls(counts['tight']):<22} {calls(counts['ladder']):<22} {diff:9.1e}")
    print(f"\nmedian ladder/tight time ratio: {np.median(ratios):.3f} (SciPy statuses: 0 optimal, "
          "1 iteration cap, 4 numerical difficulties)")


if __name__ == "__main__":
    main()
