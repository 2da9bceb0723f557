"""The papers' example systems, in one importable place for the figures, tests, benchmarks and docs.

Smoothing paper §IV-C:

* linear example (31): Φ = [[sin 1, cos 1], [−cos 1, sin 1]], Γ = [0.5, 1]ᵀ, Ξ = [[0.5, 0.5], [1, 0.3]],
  Ψ = I, ⟦w_k⟧ = [−1, 1], ⟦v_k⟧ = [−1, 1]² (Figs. 3–5), `smoothing_example_31`;
* nonlinear example (33)–(34): x_{k+1} = ∛x_k + x_k + w_k, y_k = 2x_k + v_k, ⟦w_k⟧ = [−1, 1],
  ⟦v_k⟧ = [1, 3] (Fig. 6), `smoothing_example_33` with η, η⁻¹ and the measurement interval (34).

The paper does not state ⟦x_0⟧ for either example. The figures take ⟦x_0⟧ = [−5, 5]² for (31) and
[−5, 5] for (33) (`SMOOTHING_31_X0`, `SMOOTHING_33_X0`): wider than what one measurement tells (Ξ⁻¹⟦v⟧
has widths 4.6 × 8.6 for (31); (34) pins x_k to an interval of width 1), so the first posteriors are
shaped by the data rather than by the prior.
"""

from __future__ import annotations

import numpy as np

from ..sets.box import Box
from ..models.systems import LinearSystem, NonlinearSystem

__all__ = ["smoothing_example_31", "smoothing_example_31_x0", "SMOOTHING_31_X0", "smoothing_example_33",
           "eta_33", "eta_33_inverse", "measurement_interval_34", "SMOOTHING_33_X0", "SMOOTHING_33_W",
           "SMOOTHING_33_V"]

#: ⟦x_0⟧ = [−5, 5]² of example (31) as (lo, hi): our choice, the paper does not state it.
SMOOTHING_31_X0 = ((-5.0, -5.0), (5.0, 5.0))
#: ⟦x_0⟧, ⟦w_k⟧ and ⟦v_k⟧ of example (33)–(34) as (lo, hi) pairs (⟦x_0⟧ is our choice).
SMOOTHING_33_X0 = (-5.0, 5.0)
SMOOTHING_33_W = (-1.0, 1.0)
SMOOTHING_33_V = (1.0, 3.0)


def smoothing_example_31() -> LinearSystem:
    """The linear example (31) of the smoothing paper.

    Returns
    -------
    LinearSystem
        x_{k+1} = Φ x_k + Γ w_k, y_k = Ξ x_k + v_k with ⟦w_k⟧ = [−1, 1], ⟦v_k⟧ = [−1, 1]²: the
        `LinearSystem` with A = Φ, E = Γ, C = Ξ (no known input, F = I).

    Examples
    --------
    >>> system = smoothing_example_31()
    >>> system.n, system.m, system.p
    (2, 2, 1)
    """
    s1, c1 = np.sin(1.0), np.cos(1.0)
    return LinearSystem([[s1, c1], [-c1, s1]], None, [[0.5, 0.5], [1.0, 0.3]], E=[[0.5], [1.0]],
                        W=Box([-1.0], [1.0]), V=Box([-1.0, -1.0], [1.0, 1.0]))


def smoothing_example_31_x0() -> Box:
    """⟦x_0⟧ = [−5, 5]² for example (31), the initial range the figures use (`SMOOTHING_31_X0`)."""
    return Box(*SMOOTHING_31_X0)


def eta_33(x):
    """η(x) = ∛x + x of (33): continuous, strictly increasing, onto ℝ (works on arrays).

    Examples
    --------
    >>> float(eta_33(8.0))
    10.0
    """
    return np.cbrt(x) + x


def eta_33_inverse(z: float) -> float:
    """η⁻¹(z) in closed form: t = ∛x solves t³ + t − z = 0 (Cardano, one real root, u·v = −1/3).

    Examples
    --------
    >>> round(eta_33_inverse(10.0), 12)
    8.0
    """
    z = float(z)
    s = np.sqrt(z * z / 4 + 1 / 27)
    u = np.cbrt(abs(z) / 2 + s)          # the larger Cardano term: no cancellation for either sign
    t = np.copysign(u - 1 / (3 * u), z)
    return float(t ** 3)


def measurement_interval_34(k: int, y) -> tuple[float, float]:
    """{x : y = 2x + v, v ∈ [1, 3]} = [(y − 3)/2, (y − 1)/2], the states consistent with y_k (34).

    Examples
    --------
    >>> measurement_interval_34(0, 5.0)
    (1.0, 2.0)
    """
    y = float(np.asarray(y).reshape(-1)[0])
    return (y - SMOOTHING_33_V[1]) / 2, (y - SMOOTHING_33_V[0]) / 2


def _step_33(k, x, w):
    return eta_33(x) + w


def _measure_33(k, x, v):
    return 2 * x + v


def smoothing_example_33() -> NonlinearSystem:
    """The nonlinear example (33)–(34) of the smoothing paper, for `simulate`.

    Examples
    --------
    >>> smoothing_example_33().n
    1
    """
    return NonlinearSystem(_step_33, _measure_33, Box([SMOOTHING_33_W[0]], [SMOOTHING_33_W[1]]),
                           Box([SMOOTHING_33_V[0]], [SMOOTHING_33_V[1]]), n=1)
