"""The same set under 1e±12 rescalings of rows, factors or coordinates answers the same, or raises.

12 rescaled random CZs (the first one the issue's example), on the fast path and the generic path:
no silently wrong finite value, no ``inf`` for a bounded direction, no member rejected by ``contains``,
no certified value below the exact one (HiGHS on the unscaled set); a `SolverError` is acceptable.
"""

from __future__ import annotations

import pytest

from setsmooth.reliability.rescaling import PATHS, check, describe, random_rescalings

RESCALED = random_rescalings(12, seed=2026)


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("r", RESCALED, ids=[r.name for r in RESCALED])
def test_rescaled_representation_answers_like_the_original_or_raises(r, path):
    outcome = check(r, path)
    assert not outcome.silent_failure, describe(outcome)


def test_rescalings_are_the_same_set_for_the_oracle():
    """The re-representations are exact: HiGHS on the rescaled matrices gives the original's values."""
    import numpy as np

    from setsmooth.reliability.oracle import cz_support, factor_form

    rng = np.random.default_rng(5)
    for r in RESCALED:
        f, g = factor_form(r.original), factor_form(r.scaled)
        for d in rng.normal(size=(4, r.original.dim)):
            exact, _ = cz_support(f, d)
            value, point = cz_support(g, d / np.diag(r.M))
            assert value == pytest.approx(exact, rel=1e-8, abs=1e-8), r.name
            assert d @ np.linalg.solve(r.M, point) == pytest.approx(exact, rel=1e-8, abs=1e-8), r.name
