"""The exact estimators on seeded random systems of every kind and regime, against the HiGHS oracle.

A small version of ``benchmarks/reliability.py``: 10 systems (every kind, box and CZ noises), each in
one of the four regimes, T = 10..14, n = 2..4. On every case, for the filter, the recursion smoother
and the trajectory smoother: no exception on these well-posed data, no true state outside a hull, every
hull endpoint (plain and certified) within 1e-6 of the exact one relative to the hull's width plus the
noise scale, and every certified hull enclosing the exact one (see `compare`).
"""

from __future__ import annotations

import pytest

from setsmooth.reliability.compare import compare_case, describe
from setsmooth.reliability.random_systems import REGIMES, base_case, in_regime

SEED = 2026
CASES = [(i, REGIMES[i % len(REGIMES)]) for i in range(10)]


@pytest.mark.parametrize("index,regime", CASES, ids=[f"{i:02d}-{r}" for i, r in CASES])
def test_exact_estimators_agree_with_the_trajectory_lp_oracle(index, regime):
    case = in_regime(base_case(SEED, index, T_range=(10, 14), n_range=(2, 4)), regime)
    result = compare_case(case)
    assert not result.failed, "\n" + describe(result)


def test_the_filter_form_is_checked_at_the_door():
    import setsmooth as ss

    case = base_case(2026, 0, T_range=(10, 12), n_range=(2, 3))
    with pytest.raises(ValueError, match="form must be one of"):
        ss.classical_filter(case.system, case.X0, case.ys, form="fast")
