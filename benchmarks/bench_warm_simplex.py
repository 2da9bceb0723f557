"""The warm-started simplex method's variant (`setsmooth.solvers.warm_simplex`), side by side in one
run against the one it replaced.

The recursion smoother's hulls (Algorithm 1: degenerate sets of O(T²) factors) are answered by the
warm-started simplex method first (`policy.POLICIES`). Each set's program starts a
batch from its feasible basis (the zero objective's optimum) and then solves the hull's directions,
each from the last optimum. Two configurations, alternating on the same cases:

* ``dual``: as before, the dual simplex method for the directions, and HiGHS's own scaling for the
  feasible basis;
* ``primal``: as built, the primal method from a feasible basis (only the costs change between the
  directions, so it starts in its phase two), and the feasible basis first without HiGHS's scaling
  (the presolved program is equilibrated already).

A trajectory-smoother case (free factors: Clarabel first, the simplex method only as a fallback)
shows the other estimators' share. The table (`benchmarks.side_by_side.compare`): median process
CPU seconds, the ratio primal/dual, and the largest difference between the two configurations'
hull endpoints (both are checked against their certified bounds).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_warm_simplex.py [--repeats 1]
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import side_by_side  # noqa: E402
from setsmooth.solvers import warm_simplex  # noqa: E402

#: (reliability index, regime, estimator): CZ-noise recursion cases 057 (n = 4, T = 23) and 058
#: (n = 6, T = 28, the factor sets up to 2,806 × 5,475), box cases 043 and 000 of
#: `bench_bracketed_order.py`, and case 069's trajectory smoother (free factors).
CASES = ((57, "scale1", "recursion"), (58, "scale1", "recursion"), (43, "scale1e-06", "recursion"),
         (0, "scale1", "recursion"), (69, "scale1", "trajectory"))

VARIANTS = {"dual": {"WARM_STRATEGY": warm_simplex._DUAL, "FEASIBLE_BASIS_SCALINGS": (None,)},
            "primal": {"WARM_STRATEGY": warm_simplex._PRIMAL, "FEASIBLE_BASIS_SCALINGS": (0, None)}}


if __name__ == "__main__":
    side_by_side.main(__doc__, CASES, warm_simplex, VARIANTS, repeats=1)
