"""The rethinking paper's two examples (Section IV), in one importable place for figures, tests and docs.

**(27)–(28), Section IV-A**: x_{k+1} = sin(x_k) + x_k + w_k, y_k = v_k x_k, ⟦x_0⟧ = [0, 1], ⟦w_k⟧ = [0, 1],
⟦v_k⟧ = [1, 2], with v_k related to w_{k−1}.

*Reading of the conditional range.* The text states ⟦v_k | w_{k−1}⟧ = [0, 2 − w_{k−1}] and Algorithm 2
line 10 tests y_k/x_k ∈ [0, 1 − 2w_{k−1}]. Neither is consistent with ⟦v_k⟧ = [1, 2] and with Algorithm 1's
update x ∈ [y/2, y] (which is {x : y = v x, v ∈ [1, 2]}): by the law of total range (9) the conditional
ranges over w ∈ [0, 1] must lie in [1, 2] and cover it, but [0, 2 − w] reaches 0, and [0, 1 − 2w] is
empty for w > 1/2 and never reaches 2. We read **⟦v_k | w_{k−1}⟧ = [1, 2 − w_{k−1}]**: inside [1, 2] for
every w, and its union over w ∈ [0, 1] is [1, 2]. With it the classical range contains the true state in
every run (with [0, 2 − w] it does not: v_k < 1 puts x_k = y_k/v_k above y_k, outside [y/2, y]), and the
averaged length ratio of Fig. 2 settles near the paper's 84 % (see `paper_figures/rethinking_fig2.py`).

**(30)–(31), Section IV-B**: x_{k+1} = [[1, 1], [0, 1]] x_k + [0.5, 1]ᵀ w, y_k = [1, 0] x_k + v_k, with one
identical process noise w, ⟦x_0⟧ = [−10, 10]², ⟦w⟧ = [−1, 1], ⟦v_k⟧ = [−1, 1]. (32) prints D = 0 but (31)
adds v_k, so we take D = 1 (with D = 0 the posteriors would be segments of zero area, and Fig. 3's area
ratios 27.1 % and 1.04 % would be undefined).
"""

from __future__ import annotations

import numpy as np

from ..models.related_noise import JointRange, ScalarRelatedNoiseSystem
from ..sets.box import Box
from ..models.systems import LinearSystem

__all__ = ["RETHINKING_27_X0", "RETHINKING_27_W", "RETHINKING_27_V", "eta_27", "v_given_w_27",
           "rethinking_example_27", "optimal_ranges_27",
           "RETHINKING_30_X0", "RETHINKING_30_W", "RETHINKING_30_V",
           "rethinking_example_30", "rethinking_example_30_x0", "rethinking_example_30_joint_range"]

#: ⟦x_0⟧, ⟦w_k⟧ and ⟦v_k⟧ of example (27)–(28) as (lo, hi).
RETHINKING_27_X0 = (0.0, 1.0)
RETHINKING_27_W = (0.0, 1.0)
RETHINKING_27_V = (1.0, 2.0)

#: ⟦x_0⟧ = [−10, 10]² (as (lo, hi)), ⟦w⟧ and ⟦v_k⟧ of example (30)–(31).
RETHINKING_30_X0 = ((-10.0, -10.0), (10.0, 10.0))
RETHINKING_30_W = (-1.0, 1.0)
RETHINKING_30_V = (-1.0, 1.0)


def eta_27(x):
    """η(x) = sin(x) + x of (27): continuous and increasing (η′ = 1 + cos x ≥ 0); works on arrays.

    Examples
    --------
    >>> float(eta_27(0.0))
    0.0
    """
    return np.sin(x) + x


def v_given_w_27(w):
    """⟦v_k | w_{k−1} = w⟧ = [1, 2 − w], our reading of the paper's conditional range (module docstring).

    Examples
    --------
    >>> v_given_w_27(np.array([0.0, 1.0]))
    (array([1., 1.]), array([2., 1.]))
    """
    w = np.asarray(w, dtype=float)
    return np.broadcast_to(1.0, w.shape), 2.0 - w     # a read-only view: no array of ones is written


def _measure_28(x, v):
    return v * x


def _measurement_interval_28(y, v_lo, v_hi):
    """{x : y = v x, v ∈ [v_lo, v_hi]} for 0 < v_lo ≤ v_hi: [y/v_hi, y/v_lo] for y ≥ 0 (mirrored for y < 0)."""
    y = np.asarray(y, dtype=float)
    a, b = y / v_hi, y / v_lo
    return np.minimum(a, b), np.maximum(a, b)


def rethinking_example_27() -> ScalarRelatedNoiseSystem:
    """Example (27)–(28) with ⟦v_k | w_{k−1}⟧ = [1, 2 − w_{k−1}] (our reading; see the module docstring).

    Examples
    --------
    >>> rethinking_example_27().v_range
    (1.0, 2.0)
    """
    return ScalarRelatedNoiseSystem(eta=eta_27, measurement=_measure_28,
                                    measurement_interval=_measurement_interval_28,
                                    x0_range=RETHINKING_27_X0, w_range=RETHINKING_27_W,
                                    v_range=RETHINKING_27_V, v_given_w=v_given_w_27)


def optimal_ranges_27(ys) -> tuple[np.ndarray, np.ndarray]:
    """The exact optimal ranges ⟦x_k | y_{0:k}⟧ of (27)–(28) in closed form (our reading of ⟦v_k | w_{k−1}⟧).

    From the range [a, b] at k − 1 and y_k > 0: x_k = η(x) + w with x ∈ [a, b], w ∈ [0, 1], x_k ≤ y_k
    (v_k ≥ 1) and w ≤ 2 − y_k/x_k (v_k ≤ 2 − w). As η is continuous and increasing, such x and w exist iff
    max(0, x_k − η(b)) ≤ min(1, x_k − η(a), 2 − y_k/x_k), that is

        x_k ∈ [max(η(a), y_k/2, r₁), min(η(b) + 1, y_k, r₂)],  r₁,₂ the roots of x² − (2 + η(b)) x + y_k

    (the last condition is x + y_k/x ≤ 2 + η(b)). At k = 0: [max(0, y_0/2), min(1, y_0)]. An exact
    reference for Algorithm 2's inner approximation (Fig. 2); Algorithm 2 itself applies to any
    `ScalarRelatedNoiseSystem`.

    Parameters
    ----------
    ys : array_like, shape (T+1,) or (runs, T+1)
        Positive measurements (x_k > 0 after k = 0 whenever x_0 > 0).

    Returns
    -------
    lo, hi : ndarray, shape (runs, T+1)
        NaN from the first empty range on.

    Examples
    --------
    >>> lo, hi = optimal_ranges_27([1.0, 2.0])
    >>> lo.round(6).tolist(), hi.round(6).tolist()
    ([[0.5, 1.0]], [[1.0, 2.0]])
    """
    ys = np.atleast_2d(np.asarray(ys, dtype=float))
    lo, hi = np.full(ys.shape, np.nan), np.full(ys.shape, np.nan)
    lo[:, 0], hi[:, 0] = np.maximum(0.0, ys[:, 0] / 2), np.minimum(1.0, ys[:, 0])
    for k in range(1, ys.shape[1]):
        y, eb = ys[:, k], eta_27(hi[:, k - 1])
        with np.errstate(invalid="ignore"):
            root = np.sqrt((2 + eb) ** 2 - 4 * y)          # NaN: no x with x + y/x ≤ 2 + η(b)
            lo[:, k] = np.maximum.reduce([eta_27(lo[:, k - 1]), y / 2, ((2 + eb) - root) / 2])
            hi[:, k] = np.minimum.reduce([eb + 1, y, ((2 + eb) + root) / 2])
            empty = ~(lo[:, k] <= hi[:, k])
        lo[empty, k], hi[empty, k] = np.nan, np.nan
    return lo, hi


def rethinking_example_30() -> LinearSystem:
    """Example (30)–(31) as a LinearSystem whose W, V are the marginal ranges ⟦w⟧, ⟦v_k⟧ (D = 1).

    Examples
    --------
    >>> system = rethinking_example_30()
    >>> system.n, system.m, system.p
    (2, 1, 1)
    """
    return LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]],
                        W=Box([RETHINKING_30_W[0]], [RETHINKING_30_W[1]]),
                        V=Box([RETHINKING_30_V[0]], [RETHINKING_30_V[1]]))


def rethinking_example_30_x0() -> Box:
    """⟦x_0⟧ = [−10, 10]² of example (30)."""
    return Box(*RETHINKING_30_X0)


def rethinking_example_30_joint_range(T: int) -> JointRange:
    """The joint range of (30)–(31) over k = 0..T: x_0, w, v_{0:T} unrelated, w_k = w (Section IV-B)."""
    system = rethinking_example_30()
    return JointRange.identical_process_noise(rethinking_example_30_x0(), system.W, system.V, T)
