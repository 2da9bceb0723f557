"""Interval hulls of the exact filter's posteriors along time, at a cost per step that does not grow with k.

The posterior P_k = ⟦x_k | y_{0:k}⟧ is a projection of all trajectories 0..k, so its hull taken alone is a
program of size O(k) and the hulls of a run cost O(T²). Along time they need not: the filtering map
F_{k,i} (stability paper (7), `setsmooth.filtering_map`) is monotone in its prior and P_k = F_{k,i}(P_i),
so for any sets I_i ⊆ P_i ⊆ O_i

    h_{F_{k,i}(I_i)}(d)  ≤  h_{P_k}(d)  ≤  h_{F_{k,i}(O_i)}(d),

two programs over the window i..k alone. Here O_i is the certified interval hull of P_i, and I_i the
convex hull of the 2n maximizers found for P_i's own hull (points of P_i). The upper end is a
certified (weak-duality) support value of F_{k,i}(O_i), an upper bound on h_{P_k}(d) in floating point;
the lower end is attained by a point of F_{k,i}(I_i). When the bracket is narrower than ``GAP_TOL`` of
the hull's width along every axis, the step is settled: its certified hull is the upper ends and its
plain hull the lower ends (exact to that relative width). Otherwise the window doubles, down to i = 0
where F_{k,0}(X0) is P_k itself: the answer is then the full program's, as `SetEstimates.interval_hulls`
gives it, and so do the first steps, where that program is the cheaper one (`WINDOW_FACTOR`). So
the result never depends on the window except through its cost.

For a detectable system the priors' influence on x_k fades geometrically with k − i, and a window of a
few dozen steps closes the bracket at every k: the cost per step is flat. For a system whose data do
not forget (an undetectable unstable mode) the window grows to the full program, the cost of today.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..sets.empty import EmptySet
from .._validation import measured
from ..trajectories.sparse_cz import window_posterior

__all__ = ["GAP_TOL", "FIRST_WINDOW", "WINDOW_FACTOR", "filtered_hulls"]

#: The bracket (certified upper end minus inner lower end) accepted, relative to the hull's width
#: along the axis: an order below the 1e-6 of a width that the hulls are held to.
GAP_TOL = 1e-7

#: The window length k − i tried first; a step whose bracket does not close doubles it, and the
#: next step starts from the length that closed.
FIRST_WINDOW = 8

#: Windows are used at step k only when k ≥ WINDOW_FACTOR × the window length; earlier steps solve
#: the posterior's own program, which is cheaper there. A step's two window programs cost about as
#: much as the full program of k ≈ 50 (4 states) to 175 (2 states, example (31)) steps at a window
#: of 8: the programs' fixed costs (presolve, certificate) dominate both
#: (``benchmarks/bench_hulls_along_time.py``). The choice depends on k alone, never on time.
WINDOW_FACTOR = 12


class _Step:
    """What a settled step leaves for the windows that start at it."""

    __slots__ = ("upper", "lower", "points")

    def __init__(self, upper: np.ndarray, lower: np.ndarray, points: np.ndarray):
        # support values along [I; −I]: certified upper ends and attained lower ends of the brackets
        self.upper, self.lower, self.points = upper, lower, points

    def box(self, values: np.ndarray) -> Box:
        n = values.size // 2
        return Box(-values[n:], values[:n])

    def outer(self) -> ConstrainedZonotope:
        return self.box(self.upper).to_constrained_zonotope()

    def inner(self) -> ConstrainedZonotope:
        """conv{p_1..p_r} = {m + Σ λ_j (p_j − m) : λ ≥ 0, Σ λ_j = 1} with λ = (1 + ξ)/2: the CZ
        Z((P − m)/2, m, 1ᵀ, 2 − r), centred at the points' mean m."""
        P = self.points
        m = P.mean(axis=0)
        r = P.shape[0]
        return ConstrainedZonotope(((P - m) / 2).T, m, np.ones((1, r)), [2.0 - r])


def _solve(S: ConstrainedZonotope, D: np.ndarray):
    """(values, points, bounds or None) of the support of S along the rows of D, one set of solves."""
    return S._program.support_points_and_bounds(D)


def filtered_hulls(system, X0: ConvexSet, ys: np.ndarray, *, certified: bool | None = None,
                   progress: bool | None = None) -> list[ConvexSet]:
    """Interval hulls of the exact posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, by windows along time.

    Parameters
    ----------
    system : LinearSystem
        W and V flatten to constrained zonotopes.
    X0 : ConvexSet
        ⟦x_0⟧; flattens to a constrained zonotope.
    ys : ndarray, shape (T+1, m)
        The measurements.
    certified : bool or None
        As in `ConvexSet.interval_hull`: True and None give the certified hulls (upper ends of the
        brackets, weak-duality bounds), False the plain ones (lower ends, attained by points of the
        posterior to the solver's accuracy).
    progress : bool or None
        A tqdm bar, one tick per step; None: when standard error is a terminal.

    Returns
    -------
    list of Box or EmptySet
        One per step; empty from the first step whose posterior is empty.
    """
    from tqdm.auto import tqdm

    system, ys = measured(system, ys)
    n, T = system.n, ys.shape[0] - 1
    forms = (X0.to_constrained_zonotope(), system.W.to_constrained_zonotope(),
             system.V.to_constrained_zonotope())
    D = np.vstack([np.eye(n), -np.eye(n)])
    settled: list[_Step | None] = []
    hulls: list[ConvexSet] = []
    length = FIRST_WINDOW
    show = sys.stderr.isatty() if progress is None else bool(progress)
    for k in tqdm(range(T + 1), desc="interval hulls", unit="set", disable=not show, leave=False):
        if settled and settled[-1] is None:  # an empty posterior stays empty
            settled.append(None)
            hulls.append(EmptySet(n))
            continue
        step, length = _settle(system, forms, ys, k, D, settled, length)
        settled.append(step)
        if step is None:
            hulls.append(EmptySet(n))
        else:
            hulls.append(step.box(step.lower if certified is False else step.upper))
    return hulls


def _settle(system, forms: tuple, ys: np.ndarray, k: int, D: np.ndarray, settled: list, length: int):
    """(the settled step k or None when P_k is empty, the window length that settled it); ``forms``
    are the CZ forms of X0, W and V."""
    n, (Z0, Zw, Zv) = system.n, forms
    while k >= WINDOW_FACTOR * length:
        i = k - length
        prior = settled[i]
        upper_values, _, upper = _solve(window_posterior(system, prior.outer(), Zw, Zv, ys, i, k), D)
        if np.isneginf(upper_values).any():
            return None, length  # an outer bound of P_k is empty: P_k is
        inner_values, points, _ = _solve(window_posterior(system, prior.inner(), Zw, Zv, ys, i, k), D)
        if upper is not None and np.all(np.isfinite(inner_values)):
            width = np.maximum(inner_values[:n] + inner_values[n:], 0.0)
            scale = np.concatenate([width, width])
            if np.all(upper - inner_values <= GAP_TOL * scale):
                return _Step(upper, np.minimum(inner_values, upper), points), length
        length *= 2
    values, points, upper = _solve(window_posterior(system, Z0, Zw, Zv, ys, 0, k), D)
    if np.isneginf(values).any():
        return None, length
    return _Step(values if upper is None else upper, values, points), length
