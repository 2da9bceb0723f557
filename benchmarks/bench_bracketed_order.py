"""Which solver answers a bracketed support direction first (`policy.POLICIES`),
side by side in one run.

A constrained zonotope's support programs are bracketed: every answer is checked against a certified
bound and escalated when the bracket is loose (`CZProgram._verified`). Two orders of the first
solves, alternating on the same cases:

* ``interior``: the kept Clarabel instance first, the warm-started simplex method when Clarabel does
  not settle (the order before this benchmark, and still the order on programs with free factors);
* ``simplex``: as built for programs whose factors are all bounded, the warm-started simplex method
  first, Clarabel when it does not settle.

The table (`benchmarks.side_by_side.compare`): median process CPU seconds, the ratio
simplex/interior, and the largest difference between the two orders' hull endpoints (both are
checked against their certified bounds).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_bracketed_order.py [--repeats 3]
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import side_by_side  # noqa: E402
from setsmooth.solvers import policy  # noqa: E402
from setsmooth.solvers.policy import FALLBACKS, POLICIES, Attempt  # noqa: E402

#: (reliability index, regime, estimator): the recursion smoother's slowest box and CZ cases of the
#: last coverage run. (The order applies to programs whose factors are all bounded, as the recursion
#: smoother's are; trajectory sets and posterior views have free factors and keep Clarabel first,
#: `policy.POLICIES`.)
CASES = ((43, "scale1e-06", "recursion"), (45, "scale1", "recursion"), (0, "scale1", "recursion"))

def _bracketed(first: str, second: str) -> dict:
    """The policy table with the bracketed purpose (all factors bounded) asking ``first`` first."""
    return {**POLICIES, "bracketed": (Attempt(first), Attempt(second)) + FALLBACKS}


ORDERS = {"interior": {"POLICIES": _bracketed("clarabel", "simplex")},
          "simplex": {"POLICIES": _bracketed("simplex", "clarabel")}}


if __name__ == "__main__":
    side_by_side.main(__doc__, CASES, policy, ORDERS, repeats=3)
