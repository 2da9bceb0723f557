"""Which solver answers a bracketed support direction first (`factor_set.BRACKETED_ATTEMPTS`),
side by side in one run.

A constrained zonotope's support programs are bracketed: every answer is checked against a certified
bound and escalated when the bracket is loose (`CZProgram._verified`). Two orders of the first
solves, alternating on the same cases:

* ``interior``: the kept Clarabel instance first, the warm-started simplex method when Clarabel does
  not settle (the order before this benchmark, and still the order on programs with free factors);
* ``simplex``: as built for programs whose factors are all bounded, the warm-started simplex method
  first, Clarabel when it does not settle.

Each case computes the plain and certified interval hulls of every set of one estimator (the
recursion or trajectory smoother, or the filter's posterior views) on one
reliability case (`tests/reliability/random_systems.py`, seed 2026). It prints the median process CPU
seconds, the ratio simplex/interior, and the largest difference between the two orders' hull
endpoints relative to the hull width plus the noise scale (issue 7 demands 1e-6 against the exact
hull; both orders are checked against their certified bounds).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_bracketed_order.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import setsmooth as ss  # noqa: E402
from setsmooth.solvers import factor_set  # noqa: E402
from tests.reliability.oracle import data_scale  # noqa: E402
from tests.reliability.random_systems import base_case, in_regime, triangle_case  # noqa: E402

#: (reliability index, regime, estimator): the recursion smoother's slowest box and CZ cases of the
#: last coverage run. (The order applies to programs whose factors are all bounded, as the recursion
#: smoother's are; trajectory sets and posterior views have free factors and keep Clarabel first,
#: `factor_set.BRACKETED_ATTEMPTS_FREE`.)
CASES = ((43, "scale1e-06", "recursion"), (45, "scale1", "recursion"), (0, "scale1", "recursion"))

ORDERS = {"interior": (False, "simplex"), "simplex": ("simplex", False)}


@contextlib.contextmanager
def ordered(order: str):
    saved = factor_set.BRACKETED_ATTEMPTS
    factor_set.BRACKETED_ATTEMPTS = ORDERS[order]
    try:
        yield
    finally:
        factor_set.BRACKETED_ATTEMPTS = saved


def hulls(case, estimator: str) -> np.ndarray:
    """Rows (lo, hi) of the plain, then the certified interval hull of every set of ``estimator``
    ('recursion', 'trajectory' or 'filter') on ``case``."""
    out = []
    sets = (ss.classical_filter(case.system, case.X0, case.ys) if estimator == "filter" else
            ss.optimal_smoother(case.system, case.X0, case.ys, method=estimator))
    for S in sets:
        for certified in (False, True):
            H = S.interval_hull(certified=certified)
            out.append(np.concatenate([H.lo, H.hi]))
    return np.array(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    print(f"{'case':<44} {'interior s':>10} {'simplex s':>10} {'ratio':>7} {'max diff':>9}")
    ratios = []
    for index, regime, estimator in CASES:
        case = triangle_case(2026, T=100) if index is None else in_regime(base_case(2026, index),
                                                                          regime)
        times: dict[str, list[float]] = {order: [] for order in ORDERS}
        result = {}
        for _ in range(args.repeats):
            for order in ORDERS:
                with ordered(order):
                    start = time.process_time()
                    result[order] = hulls(case, estimator)
                    times[order].append(time.process_time() - start)
        n = case.system.n
        lo, hi = result["simplex"][:, :n], result["simplex"][:, n:]
        unit = np.concatenate([hi - lo, hi - lo], axis=1) + data_scale(case.system, case.X0)
        diff = float(np.max(np.abs(result["simplex"] - result["interior"]) / unit))
        t = {order: float(np.median(v)) for order, v in times.items()}
        ratios.append(t["simplex"] / t["interior"])
        print(f"{case.name + ' ' + estimator:<44} {t['interior']:10.2f} {t['simplex']:10.2f} "
              f"{ratios[-1]:7.3f} {diff:9.1e}")
    print(f"\nmedian ratio simplex/interior: {np.median(ratios):.3f}")


if __name__ == "__main__":
    main()
