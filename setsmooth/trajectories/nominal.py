"""Algorithm 1's recursion about a nominal trajectory: the same sets, computed as deviations.

With x̄_0 the centre of X0 and x̄_{k+1} = A_k x̄_k + E_k c_W + B_k u_k (the noises at the centres c_W,
c_V), the deviations δ_k = x_k − x̄_k obey (y_k without its feedthrough D_k u_k, as the estimators' door
gives it)

    δ_{k+1} = A_k δ_k + E_k (w_k − c_W),          y_k − C_k x̄_k − F_k c_V = C_k δ_k + F_k (v_k − c_V),

a system with the same matrices, noise ranges W − c_W and V − c_V, no input, initial range X0 − x̄_0
and measurements ỹ_k. Its posteriors and smoothed ranges, translated by x̄_k, are the original ones.

Why. The recursion's sets share their factors' data in every later set: the smoothed set at k is a
posterior intersected with a backward image that holds its own copy of the same data, and the exact
sets coincide only if both copies carry them identically. In absolute coordinates each combination
of centres (c_R − A_k c_Z in an intersection's rows) rounds at the states' magnitude, differently in
each copy; on a thin set the difference is amplified by the inverse of its width. Reliability case
033 (rank-deficient C, states offset by 1e6, widths 1–7): the recursion smoother's plain hulls were
up to 5.3e-6 of the width narrower than the exact ones. As deviations every number the recursion
combines is of the sets' width, the states' magnitude enters once, in ỹ_k (rounded like any
formulation rounds y_k − C_k x_k), and the same hulls agree with the oracle to 3e-9. The posterior
views (`setsmooth.trajectories.posterior_views`) and the trajectory set are built about the same nominal.

The nominal states are computed in floating point, so the deviation model differs from the exact one
by their rounding (a few units in the last place of x̄_k per step, like the rounding of any step of the
recursion). Certified values do not depend on it: the recursion's sets are certified against the
original data (`setsmooth.trajectories.recursion_certificates`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..sets.algebra import translate
from ..sets.base import ConvexSet
from ..sets.empty import EmptySet

__all__ = ["NominalDeviations", "RecursionDeviations", "about_nominal"]


@dataclass(frozen=True)
class NominalDeviations:
    """The deviation form of one data set (module docstring).

    Attributes
    ----------
    system : LinearSystem
        The same matrices A_k, B_k, C_k, D_k with noise ranges W − c_W, V − c_V and no input.
    X0 : ConvexSet
        X0 − x̄_0.
    ys : ndarray, shape (T+1, m)
        ỹ_k = y_k − C_k x̄_k − D_k c_V.
    nominal : ndarray, shape (T+1, n)
        The nominal states x̄_0..x̄_T.
    """

    system: object
    X0: ConvexSet
    ys: np.ndarray
    nominal: np.ndarray

    def to_states(self, deviations: list[ConvexSet]) -> list[ConvexSet]:
        """The sets of states x_k = δ_k + x̄_k from sets of deviations δ_k, k = 0..T."""
        return [S if isinstance(S, EmptySet) else translate(S, self.nominal[k])
                for k, S in enumerate(deviations)]


def about_nominal(system, X0: ConvexSet, ys: np.ndarray) -> NominalDeviations | None:
    """The deviation form of ``system``, ``X0`` and the measurements ``ys`` (validated by the caller).

    Returns
    -------
    NominalDeviations or None
        None when X0, W or V has no constrained-zonotope form (no centre to expand about: the
        recursion then runs in the original coordinates).
    """
    flats = [S._flat_cz for S in (X0, system.W, system.V)]
    if any(F is None for F in flats):
        return None
    c_X0, c_W, c_V = (np.asarray(F.c, dtype=float) for F in flats)
    T = len(ys) - 1
    nominal = np.empty((T + 1, system.n))
    nominal[0] = c_X0
    for k in range(T):
        nominal[k + 1] = system.A_at(k) @ nominal[k] + system.E_at(k) @ c_W + system.input_term(k)
    ys_dev = np.array([ys[k] - system.C_at(k) @ nominal[k] - system.F_at(k) @ c_V for k in range(T + 1)])
    deviation_system = system._with_noises(translate(system.W, -c_W), translate(system.V, -c_V))
    return NominalDeviations(deviation_system, translate(X0, -c_X0), ys_dev, nominal)


class RecursionDeviations:
    """The deviation sets behind the recursion filter's posteriors, for the smoother to read.

    `classical_filter` (``form='recursion'``) returns the posteriors translated to states and keeps
    this on its result; `optimal_smoother` runs the backward recursion on the deviations when it is
    given that result unchanged (the same set objects, in order: pickling keeps them shared).

    Parameters
    ----------
    form : NominalDeviations
    deviations : list of ConvexSet
        The posteriors of ``form.system``, k = 0..T.
    states : list of ConvexSet
        ``form.to_states(deviations)`` as returned to the user.
    """

    def __init__(self, form: NominalDeviations, deviations: list[ConvexSet], states: list[ConvexSet]):
        self.form, self.deviations, self._states = form, list(deviations), list(states)

    def matches(self, posteriors: list[ConvexSet]) -> bool:
        """Whether ``posteriors`` are still the very sets these deviations were translated to."""
        return len(posteriors) == len(self._states) and all(
            S is R for S, R in zip(posteriors, self._states))
