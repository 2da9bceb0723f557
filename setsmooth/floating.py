"""The error constants of binary64 arithmetic, the one definition of them in setsmooth: shared by the
set algebra's rounding charges (`setsmooth.sets.rounding`), the certified support values
(`setsmooth.solvers.certify`), the polygons' geometry, order reduction's rounding bounds and the sound
discretization of continuous-time noise (`setsmooth.models.discretization`).

Higham, *Accuracy and Stability of Numerical Algorithms* (2nd ed., §2.2, §3.1): a computed sum of n
products is off by at most γ_n times the sum of their magnitudes, plus n·η for products that
underflow.
"""

from __future__ import annotations

import numpy as np

__all__ = ["U", "ETA", "gamma"]

#: The unit roundoff u = 2⁻⁵³.
U = float(np.finfo(float).eps) / 2

#: η = 2⁻¹⁰⁷⁴, the smallest subnormal: the absolute error of a product that underflows.
ETA = float(np.nextafter(0.0, 1.0))


def gamma(n: int | np.ndarray) -> float | np.ndarray:
    """γ_n = n·u / (1 − n·u): the relative error bound of a floating-point sum of n terms (a float
    for a Python int, the same binary64 operations as for an array)."""
    nu = n * U if isinstance(n, int) else np.asarray(n, dtype=float) * U
    return nu / (1.0 - nu)
