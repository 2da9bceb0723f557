"""ℝⁿ as the extended constrained zonotope Z(I, 0, h = ∞)."""

from __future__ import annotations

import numpy as np

from .._validation import check_dim
from .constrained_zonotope import ConstrainedZonotope


class Reals(ConstrainedZonotope):
    """The whole space ℝⁿ: every factor free (h = ∞), no constraint.

    It is a `ConstrainedZonotope`, so ``Reals(n).intersect_preimage(M, Y)`` is the exact preimage
    {x : Mx ∈ Y} of a CZ under any (possibly singular) M.

    Parameters
    ----------
    n : int
        Dimension.
    """

    def __init__(self, n: int):
        n = check_dim(n, "n")
        self._init(np.eye(n), np.zeros(n), np.zeros((0, n)), np.zeros(0), np.full(n, np.inf), None)

    def __repr__(self) -> str:
        return f"Reals({self.dim})"

    def constraints(self, x):
        return []

    def _contains(self, p: np.ndarray, margin: float) -> bool:
        return True
