"""Certified means certified: the trajectory smoother's certified supports are never below a feasible point."""

from __future__ import annotations

import pytest

from setsmooth.reliability.random_systems import base_case
from setsmooth.reliability.witness import witness_check

SEED = 2026
#: Cases 0–39 of this seed (T = 10..14, n = 2..4) were scanned on the code of 2026-11-23; these three
#: (singular/box, stable/CZ, non-square D/CZ) are three of the four that gave certified values below a witness.
INDICES = [2, 15, 29]


@pytest.mark.parametrize("index", INDICES)
def test_certified_support_of_smoothed_set_is_at_least_every_feasible_witness(index):
    case = base_case(SEED, index, T_range=(10, 14), n_range=(2, 4))
    outcome = witness_check(case)
    assert outcome.error is None, outcome.error
    assert outcome.checked > 0
    assert outcome.violations == 0, (f"{case.name}: {outcome.violations} of {outcome.checked} certified "
                                     f"values below a feasible witness, worst {outcome.worst:.2e} rel "
                                     f"({outcome.example})")
