"""Nearly empty sets: emptiness is decided without a solver error and agrees with the hull's verdict.

Two slabs x ≤ 0 and x ≥ g (H-polytopes), and the CZ {ξ ∈ [−1, 1]² : ξ₁ = 1 + g}: empty exactly when
g > 0. For |g| ≥ 1e-6 (far above any solver tolerance on unit data) the verdict must be the exact one;
for every gap, ``is_empty()`` and ``interval_hull()`` must answer (no `SolverError`) and agree.
"""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss

GAPS = [3e-9, 1e-8, 3e-7, 3e-5, 1e-3, -3e-9, -1e-8, -3e-7, -3e-5, -1e-3]


def _slabs(g: float) -> ss.ConvexSet:
    square = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    left = ss.HPolytope(square, [0.0, 1.0, 1.0, 1.0])        # x ∈ [−1, 0]
    right = ss.HPolytope(square, [1.0 + g, -g, 1.0, 1.0])    # x ∈ [g, 1 + g]
    return left & right


def _cz(g: float) -> ss.ConstrainedZonotope:
    return ss.ConstrainedZonotope(np.eye(2), np.zeros(2), [[1.0, 0.0]], [1.0 + g])


@pytest.mark.parametrize("g", GAPS)
@pytest.mark.parametrize("build", [_slabs, _cz], ids=["hpolytope_intersection", "constrained_zonotope"])
def test_emptiness_of_a_nearly_empty_set_is_decided_and_agrees_with_its_hull(build, g):
    S = build(g)
    empty = S.is_empty()
    hull = S.interval_hull()
    assert hull.is_empty() == empty, f"is_empty() = {empty} but interval_hull() = {hull}"
    if abs(g) >= 1e-6:
        assert empty == (g > 0)
    if not empty:
        certified = S.interval_hull(certified=True) if isinstance(S, ss.ConstrainedZonotope) else hull
        assert not certified.is_empty()
