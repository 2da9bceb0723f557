"""Interval hulls of the exact filter's posteriors along time, at a cost per step that does not grow with k.

The posterior P_k = ⟦x_k | y_{0:k}⟧ is a projection of all trajectories 0..k, so its hull taken alone is a
program of size O(k) and the hulls of a run cost O(T²). Along time they need not: the filtering map
F_{k,i} (stability paper (7), `setsmooth.filtering_map`) is monotone in its prior and P_k = F_{k,i}(P_i),
so for any sets I_i ⊆ P_i ⊆ O_i

    h_{F_{k,i}(I_i)}(d)  ≤  h_{P_k}(d)  ≤  h_{F_{k,i}(O_i)}(d),

two programs over the window i..k alone. Here O_i is the certified interval hull of P_i, and I_i the
convex hull of the 2n maximizers found for P_i's hull (points of P_i). The upper end is a
certified (weak-duality) support value of F_{k,i}(O_i), an upper bound on h_{P_k}(d) in floating point;
the lower end is attained by a point of F_{k,i}(I_i). When every bracket is narrower than ``GAP_TOL``
of the hull's ∞-diameter, the step is settled: its certified hull is the upper ends and its
plain hull the lower ends (exact to that fraction of the diameter). Otherwise the step solves
F_{k,0}(X0), P_k itself, and the next step tries a window twice as long: the answer is then the full
program's, as a set's own `interval_hull` gives it, and so do the first steps, where that program is the cheaper one (`WINDOW_FACTOR`). So
the result never depends on the window except through its cost.

The two window programs are set up by `window_brackets`: trajectory CZs whose solver engines are
kept per window length while their matrices repeat (a time-invariant system), re-solved warm along
time.

For a detectable system the priors' influence on x_k fades geometrically with k − i, and a window of a
few steps closes the bracket at every k: the cost per step is flat. For a system whose data do not
forget (an undetectable unstable mode) the steps solve their own programs, the cost of today.
"""

from __future__ import annotations

import sys

import numpy as np

from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..sets.empty import EmptySet
from ..sets import rounding
from .._validation import measured
from ..trajectories.sparse_cz import window_posterior
from .window_brackets import EMPTY, Windows

__all__ = ["GAP_TOL", "FIRST_WINDOW", "WINDOW_FACTOR", "SHRINK_EVERY", "filtered_hulls"]

#: The bracket (certified upper end minus inner lower end) accepted, relative to the hull's widest
#: edge (its ∞-diameter): an order below the 1e-6 that the hulls are held to. Relative to the set's
#: size, not to each coordinate's width: a coordinate that the data pin to a sliver (a state read
#: by a precise sensor and driven by no noise) has a width below any solver's accuracy, and a
#: per-coordinate test would never settle it.
GAP_TOL = 1e-7

#: The window length k − i tried first; a step tries its length and twice it, keeps the one that
#: closes, and doubles the length when neither does.
FIRST_WINDOW = 8

#: Windows are used at step k only when k ≥ WINDOW_FACTOR × the window length; earlier steps solve
#: the posterior's own program, which is cheaper there. The choice depends on k alone, never on time.
WINDOW_FACTOR = 4

#: Every SHRINK_EVERY steps a step first tries half the current window length (not below
#: FIRST_WINDOW): a length is otherwise kept once it closed, and the first steps, whose posteriors
#: are still wide, need long windows that the later ones do not.
SHRINK_EVERY = 16


class _Step:
    """What a settled step leaves for the windows that start at it: the support values along
    [I; −I] (certified upper ends and attained lower ends of the brackets) and the maximizers."""

    __slots__ = ("upper", "lower", "points")

    def __init__(self, upper: np.ndarray, lower: np.ndarray, points: np.ndarray):
        self.upper, self.lower, self.points = upper, lower, points

    def box(self, values: np.ndarray) -> Box:
        n = values.size // 2
        return Box(-values[n:], values[:n])

    def outer(self) -> ConstrainedZonotope:
        """O_i = {c + ξ : |ξ| ≤ r}: the certified hull as a CZ with generators I, so that the windows
        starting at every step share their matrices (`window_brackets`); r is rounded up so that
        the box covers [lo, hi] though the centre and the differences are rounded."""
        n = self.upper.size // 2
        lo, hi = -self.upper[n:], self.upper[:n]  # finite: P_i is bounded
        centre = (lo + hi) / 2
        radius = rounding.rounded_up(np.maximum(hi - centre, centre - lo), 1)
        return ConstrainedZonotope._trusted(np.eye(n), centre, np.zeros((0, n)), np.zeros(0), radius)

    def inner(self) -> ConstrainedZonotope:
        """I_i = conv{p_1..p_r} = {m + Σ λ_j (p_j − m) : λ ≥ 0, Σ λ_j = 1} with λ = (1 + ξ)/2: the CZ
        Z((P − m)/2, m, 1ᵀ, 2 − r), centred at the points' mean m."""
        P = self.points
        m = P.mean(axis=0)
        r = P.shape[0]
        return ConstrainedZonotope._trusted(((P - m) / 2).T, m, np.ones((1, r)), np.array([2.0 - r]),
                                            np.ones(r))


def _solve(S: ConstrainedZonotope, D: np.ndarray):
    """(values, points, bounds or None) of the support of S along the rows of D, one set of solves."""
    return S._program.support_points_and_bounds(D)


def filtered_hulls(system, X0: ConvexSet, ys: np.ndarray, *, certified: bool | None = None,
                   progress: bool | None = None) -> list[ConvexSet]:
    """Interval hulls of the exact posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, by windows along time.

    Parameters
    ----------
    system : LinearSystem
        W and V flatten to constrained zonotopes (time-varying matrices are read at their k).
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
    run = _Run(system, X0, ys, np.vstack([np.eye(n), -np.eye(n)]))
    hulls: list[ConvexSet] = []
    show = sys.stderr.isatty() if progress is None else bool(progress)
    for k in tqdm(range(T + 1), desc="interval hulls", unit="set", disable=not show, leave=False):
        step = run.settle(k)
        hulls.append(EmptySet(n) if step is None else
                     step.box(step.lower if certified is False else step.upper))
    return hulls


class _Run:
    """The settled steps of one data set and the window length the next step starts from."""

    def __init__(self, system, X0: ConvexSet, ys: np.ndarray, D: np.ndarray):
        self.system, self.ys, self.D = system, ys, D
        self.forms = tuple(S.to_constrained_zonotope() for S in (X0, system.W, system.V))
        self.windows = Windows(system, self.forms, D)
        self.settled: list[_Step | None] = []
        self.length = FIRST_WINDOW

    def settle(self, k: int) -> _Step | None:
        """Step k settled (None when P_k is empty, and at every step after an empty one)."""
        if self.settled and self.settled[-1] is None:
            step = None
        else:
            step = self._bracketed(k)
            step = self._own(k) if step is None else None if step is EMPTY else step
        self.settled.append(step)
        return step

    def _bracketed(self, k: int):
        """The step from the window of the current length, or of twice that length, whose bracket
        closes; EMPTY when an outer bound is empty; None when neither closes or no window is
        cheaper than P_k's own program (k < WINDOW_FACTOR × length). A length that closed is
        kept for the next step, so the length settles at what the data need, and every
        ``SHRINK_EVERY`` steps half of it is tried first; when neither closes the next step starts
        at the longer one, so data whose brackets never close pay for O(log T) windows in a run,
        not two per step."""
        lengths = (self.length, 2 * self.length)
        if k % SHRINK_EVERY == 0 and self.length >= 2 * FIRST_WINDOW:
            lengths = (self.length // 2,) + lengths
        for L in lengths:
            if k < WINDOW_FACTOR * L:
                return None
            step = self._window(k, L)
            if step is not None:
                self.length = L
                return step
        self.length *= 2
        return None

    def _window(self, k: int, L: int):
        """Step k from the bracket of the window k − L..k (`window_brackets`), EMPTY, or None when
        it does not close."""
        n = self.system.n
        bracket = self.windows.bracket(self.settled[k - L], self.ys, k - L, k)
        if bracket is EMPTY:
            return EMPTY  # an outer bound of P_k is empty: P_k is
        upper, lower, points = bracket
        if upper is not None and np.all(np.isfinite(lower)):
            diameter = max(float(np.max(lower[:n] + lower[n:])), 0.0)
            if np.all(upper - lower <= GAP_TOL * diameter):
                return _Step(upper, np.minimum(lower, upper), points)
        return None

    def _own(self, k: int) -> _Step | None:
        """Step k from P_k's own program (the trajectories 0..k)."""
        Z0, Zw, Zv = self.forms
        values, points, upper = _solve(window_posterior(self.system, Z0, Zw, Zv, self.ys, 0, k), self.D)
        if np.isneginf(values).any():
            return None
        return _Step(values if upper is None else upper, values, points)


