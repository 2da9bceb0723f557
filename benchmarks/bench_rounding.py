"""What the set algebra's rounding charges cost (`setsmooth.sets.rounding`), side by side in one run.

Two workloads on reliability case 000 at offset 1e6 (n = 6, T = 29), each timed with the charges as
built and with them switched off (the charge functions patched to charge nothing, for this benchmark
only): the recursion's filter and smoother sets (Algorithm 1, algebra only, no LP) and the trajectory
smoother with its certified hulls (the row slacks of the trajectory set, charged by Dot2). Medians of
CPU seconds; the ratio is charged / uncharged.

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_rounding.py [--repeats 5]
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
from setsmooth.sets import rounding  # noqa: E402
from setsmooth.reliability.random_systems import base_case, in_regime  # noqa: E402


@contextlib.contextmanager
def charges_off():
    """Patch the charge functions to charge nothing (the algebra's arithmetic is unchanged)."""
    saved = {name: getattr(rounding, name) for name in ("linear_image", "sum_with_error",
                                                         "residual_bound")}
    rounding.linear_image = lambda *args, **kwargs: (None, None)
    rounding.sum_with_error = lambda a, b: (np.asarray(a) + np.asarray(b), np.zeros(np.shape(a)))
    rounding.residual_bound = lambda pairs: np.zeros(np.shape(pairs[-1][1]))
    try:
        yield
    finally:
        for name, fn in saved.items():
            setattr(rounding, name, fn)


def recursion_sets(case):
    post = ss.classical_filter(case.system, case.X0, case.ys, form="recursion", detect_empty=False)
    ss.optimal_smoother(case.system, case.X0, case.ys, method="recursion", posteriors=post)


def trajectory_hulls(case):
    for S in ss.optimal_smoother(case.system, case.X0, case.ys, method="trajectory"):
        S.interval_hull(certified=True)


def median_cpu(fn, case, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.process_time()
        fn(case)
        times.append(time.process_time() - start)
    return float(np.median(times))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    case = in_regime(base_case(2026, 0), "offset1e+06")
    print("| workload | charged (s) | uncharged (s) | ratio |\n|---|---|---|---|")
    for name, fn in (("recursion filter + smoother sets", recursion_sets),
                     ("trajectory smoother + certified hulls", trajectory_hulls)):
        fn(case)  # warm-up (imports, caches)
        charged = median_cpu(fn, case, args.repeats)
        with charges_off():
            uncharged = median_cpu(fn, case, args.repeats)
        print(f"| {name} | {charged:.3f} | {uncharged:.3f} | {charged / uncharged:.2f} |")


if __name__ == "__main__":
    main()
