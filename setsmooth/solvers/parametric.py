"""Support values of constrained zonotopes that share G and A and differ in c, b and h.

The OIT-CZ SMF's windows (stability paper (23)) all have the same generator and constraint matrices;
only the right-hand side b (the measurements), the centre c and, for detectable systems, the factor
bounds h change from step to step. `ParametricSupport` takes the support values of a fixed list of
directions for each new (c, b, h), every value certified (weak duality, `certify.certified_bound`).
"""

from __future__ import annotations

import numpy as np

from ..sets.constrained_zonotope import ConstrainedZonotope

__all__ = ["ParametricSupport"]


class ParametricSupport:
    """Certified support values h_Z(d_j) of Z(G, c, A, b, h) for fixed G, A, directions D.

    Parameters
    ----------
    G : ndarray, shape (n, ng)
    A : ndarray, shape (nc, ng)
    D : ndarray, shape (K, n)
        The directions (e.g. [I; −I] for the interval hull).
    """

    def __init__(self, G: np.ndarray, A: np.ndarray, D: np.ndarray):
        self.G, self.A, self.D = G, A, np.asarray(D, dtype=float)

    def values(self, c: np.ndarray, b: np.ndarray, h: np.ndarray) -> np.ndarray:
        """Upper bounds on h_Z(d_j), j = 1..K, for Z = Z(G, c, A, b, h) (certified)."""
        Z = ConstrainedZonotope._trusted(self.G, c, self.A, b, h)
        return Z.support_many(self.D, certified=True)
