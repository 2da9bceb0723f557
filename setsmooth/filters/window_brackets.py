"""The two window programs that bracket a posterior's support along time (`hulls_along_time`).

For a settled step i with certified hull O_i ⊇ P_i and maximizers conv{p_1..p_r} = I_i ⊆ P_i, the
posterior P_k = F_{k,i}(P_i) (stability paper (7)) lies between F_{k,i}(I_i) and F_{k,i}(O_i). Its
support along each direction is bracketed by a certified upper bound on the outer window and the
values of the inner window's maximizers (points of F_{k,i}(I_i) ⊆ P_k). Two ways to set up the same
two programs:

* `TrajectoryWindows`, for any system: both windows as trajectory CZs over the states i..k
  (`trajectories.sparse_cz.window_posterior`), assembled and presolved anew at every step.
* `FixedWindows`, for a time-invariant system (A, C, E, F constant; a known input allowed): the
  states eliminated as in the OIT-CZ windows (`filters._window.Window`, stability paper (23)), whose
  matrices depend on (system, k − i) alone, kept per window length and re-solved warm along time
  (the solver policy's 'along time' purpose). The outer window's prior O_i = {c + ξ : |ξ| ≤ r}
  enters only b, the centre and the factor bounds: certified support values from a
  `ParametricSupport` session, with the window's rounding charges. The inner window's prior
  x_i = m + P̃ξ_λ (P̃ = (P − m)/2, 1ᵀξ_λ = 2 − r) keeps x_i as free factors, so the points enter
  the matrix only as the block −P̃ of n × r entries: support points from a `ParametricPoints`
  session, checked to satisfy the program.

Both return the same brackets up to the solvers' accuracy; `hulls_along_time` accepts a bracket only
when it is closed to ``GAP_TOL`` of the hull's diameter, so the hulls do not depend on which built it
(tests compare them).
"""

from __future__ import annotations

import numpy as np

from ..sets import rounding
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..solvers.clarabel_lp import SolverError
from ..solvers.parametric import ParametricPoints, ParametricSupport
from ..trajectories.sparse_cz import window_posterior
from ._window import Window

__all__ = ["EMPTY", "FixedWindows", "TrajectoryWindows", "solve", "windows_for"]

#: A bracket whose outer bound is empty: P_k is empty.
EMPTY = object()


def windows_for(system, forms: tuple, D: np.ndarray):
    """`FixedWindows` for a system whose A, C, E and F do not vary, else `TrajectoryWindows`.
    ``forms``: the CZ forms of X0, W and V; ``D``: the directions [I; −I]."""
    if set(system.time_varying) & {"A", "C", "E", "F"}:
        return TrajectoryWindows(system, forms, D)
    return FixedWindows(system, D)


def solve(S: ConstrainedZonotope, D: np.ndarray):
    """(values, points, bounds or None) of the support of S along the rows of D, one set of solves."""
    return S._program.support_points_and_bounds(D)


class TrajectoryWindows:
    """Both windows as trajectory CZs over the states i..k (any system)."""

    fixed = False

    def __init__(self, system, forms: tuple, D: np.ndarray):
        self.system, self.D = system, D
        _, self.Zw, self.Zv = forms

    def bracket(self, prior, ys: np.ndarray, i: int, k: int):
        """(certified upper values or None, inner values, inner maximizers), or `EMPTY`. ``prior``:
        the settled step i (its ``outer()`` and ``inner()`` sets)."""
        upper_values, _, upper = solve(window_posterior(self.system, prior.outer(), self.Zw, self.Zv,
                                                           ys, i, k), self.D)
        if np.isneginf(upper_values).any():
            return EMPTY
        lower, points, _ = solve(window_posterior(self.system, prior.inner(), self.Zw, self.Zv, ys,
                                                     i, k), self.D)
        return upper, lower, points


class FixedWindows:
    """Both windows on the state-eliminated matrices of a time-invariant system, kept per length."""

    fixed = True

    def __init__(self, system, D: np.ndarray):
        self.system, self.D, self.n = system, D, system.n
        self._parts: dict[int, tuple] = {}

    def _part(self, length: int) -> tuple:
        """The window of this length and the warm sessions of its outer and inner programs."""
        part = self._parts.get(length)
        if part is None:
            window = Window(self.system, length, np.eye(self.n))
            outer = ParametricSupport(window.G, window.A, self.D, window.free(0)).session()
            part = self._parts[length] = (window, outer, _inner_engine(window, self.D).session())
        return part

    def bracket(self, prior, ys: np.ndarray, i: int, k: int):
        """As `TrajectoryWindows.bracket`; ``prior`` gives ``upper`` (its certified support values
        along [I; −I]) and ``points`` (its maximizers)."""
        n = self.n
        window, outer, inner = self._part(k - i)
        lo, hi = -prior.upper[n:], prior.upper[:n]  # finite: P_i is bounded
        centre = (lo + hi) / 2
        # {centre + ξ : |ξ| ≤ radius} ⊇ [lo, hi] though the centre and the differences are rounded
        radius = rounding.rounded_up(np.maximum(hi - centre, centre - lo), 1)
        c, b, h, charges = window.charged_data(ys, k, centre, radius)
        try:
            upper = outer.values(c, b, h, **charges)
        except SolverError:  # no certified bound: the bracket stays open (the step's own program)
            upper = None
        if upper is not None and np.isneginf(upper).any():
            return EMPTY
        # The inner window: x_i = m + ξ_x with ξ_x = P̃ξ_λ, 1ᵀξ_λ = 2 − r, P̃ = (P − m)/2 (the prior
        # of `hulls_along_time._Step.inner`); only P̃ is in the matrix, as the block −P̃.
        P = prior.points
        m = P.mean(axis=0)
        c, b, h = window.data(ys, k, m, np.zeros(n))
        r = P.shape[0]
        b = np.concatenate([b, np.zeros(n), [2.0 - r]])
        h = np.concatenate([np.full(n, np.inf), np.ones(r), h[n:]])
        lower, points = inner.points(c, b, h, (-(P - m) / 2).T.ravel())
        return upper, lower, points


def _inner_engine(window: Window, D: np.ndarray) -> ParametricPoints:
    """The inner windows of one length: factors [ξ_x (n, free) | ξ_λ (r = 2n) | the window's noise
    factors], rows [the window's rows, ξ_x in its prior columns; ξ_x − P̃ξ_λ = 0; 1ᵀξ_λ = 2 − r];
    the block is P̃'s place (−P̃, row by row)."""
    n = window.n
    r = D.shape[0]
    nc, ng = window.A.shape
    G = np.hstack([window.G[:, :n], np.zeros((n, r)), window.G[:, n:]])
    A = np.zeros((nc + n + 1, ng + r))
    A[:nc, :n], A[:nc, n + r:] = window.A[:, :n], window.A[:, n:]
    A[nc:nc + n, :n] = np.eye(n)
    A[nc:nc + n, n:n + r] = 1.0  # placeholders for −P̃
    A[nc + n, n:n + r] = 1.0
    block = (nc + np.repeat(np.arange(n), r), n + np.tile(np.arange(r), n))
    free = np.zeros(ng + r, dtype=bool)
    free[:n] = True
    return ParametricPoints(G, A, D, free, block)
