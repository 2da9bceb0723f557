"""The two window programs that bracket a posterior's support along time (`hulls_along_time`).

For a settled step i with certified hull O_i ⊇ P_i and maximizers conv{p_1..p_r} = I_i ⊆ P_i, the
posterior P_k = F_{k,i}(P_i) (stability paper (7)) lies between F_{k,i}(I_i) and F_{k,i}(O_i). Its
support along each direction is bracketed by a certified upper bound on the outer window and the
values of the inner window's maximizers (points of F_{k,i}(I_i) ⊆ P_k).

Both windows are trajectory CZs over the states i..k, the states free factors about a nominal
trajectory (`trajectories.sparse_cz`: a `WindowLayout` of the matrices, `window_data` of b, the
centre, the bounds and the rounding slack): every row couples one step to the next, so
the rounding charges of a row are those of one step whatever the window's length. Written with the
outer prior O_i = {c + ξ : |ξ| ≤ r} (generators I, bounds r) and the inner prior
I_i = Z(P̃, m, 1ᵀ, 2 − r) (P̃ = (P − m)/2), the windows of one length have the same matrices from one
step to the next whenever the system's matrices are the same (a time-invariant system, a known input
allowed): only b, the centre, the factor bounds, the rows' rounding slack and, in the inner window,
the block −P̃ change. So each length keeps its layout and its two engines, re-solved
warm along time (the solver policy's 'along time' purpose): certified support values of the outer
window from a `ParametricSupport` session, support points of the inner one from a
`ParametricPoints` session. When A, C, E or F vary with k every window gets its own layout and
engines: the same programs from a cold start.

The states are kept rather than eliminated as in the OIT-CZ windows (`filters._window.Window`,
stability paper (23)): the eliminated form's matrices are powers A^j, and their rounding bounds grow
like |A|^j (relative 1e-8 at 8 steps, 0.1 at 16 and 1e13 at 32 on a 4-state drss system), which no
bracket survives.
"""

from __future__ import annotations

import numpy as np

from ..sets.constrained_zonotope import ConstrainedZonotope
from ..solvers.clarabel_lp import SolverError
from ..solvers.parametric import ParametricPoints, ParametricSupport
from ..trajectories.sparse_cz import WindowLayout, window_data

__all__ = ["EMPTY", "Windows"]

#: A bracket whose outer bound is empty: P_k is empty.
EMPTY = object()


class Windows:
    """The brackets of one run's windows, with each length's layout and engines kept while the
    matrices repeat.

    Parameters
    ----------
    system : LinearSystem
    forms : tuple
        The CZ forms of X0, W and V.
    D : ndarray, shape (2n, n)
        The directions [I; −I].
    """

    def __init__(self, system, forms: tuple, D: np.ndarray):
        self.system, self.D, self.n = system, D, system.n
        _, self.Zw, self.Zv = forms
        # The windows' matrices repeat from one window of a length to the next unless A, C, E or F
        # vary with k (a known input moves b only).
        self.repeat = not set(system.time_varying) & {"A", "C", "E", "F"}
        self._outer: dict[int, tuple] = {}  # length -> (layout, session)
        self._inner: dict[int, tuple] = {}  # length -> (layout, block, session)

    def bracket(self, prior, ys: np.ndarray, i: int, k: int):
        """(certified upper values or None, inner values, inner maximizers), or `EMPTY`. ``prior``:
        the settled step i, whose ``outer()`` is O_i = {c + ξ : |ξ| ≤ r} and ``inner()`` is
        Z(P̃, m, 1ᵀ, 2 − r) (`hulls_along_time._Step`)."""
        n = self.n
        box = prior.outer()
        layout, session = self._outer_engine(box, i, k)
        c, b, h, slack, slack_free = window_data(self.system, box, self.Zw, self.Zv, ys, i, k, layout)
        try:
            upper = session.values(c[-n:], b, h, slack=slack, slack_free=slack_free)
        except SolverError:  # no certified bound: the bracket stays open (the step's own program)
            upper = None
        if upper is not None and np.isneginf(upper).any():
            return EMPTY
        inner = prior.inner()
        layout, block, session = self._inner_engine(inner, i, k)
        c, b, h, _, _ = window_data(self.system, inner, self.Zw, self.Zv, ys, i, k, layout, charged=False)
        lower, points = session.points(c[-n:], b, h, -inner.G.ravel())
        return upper, lower, points

    def _outer_engine(self, box: ConstrainedZonotope, i: int, k: int) -> tuple:
        kept = self._outer.get(k - i) if self.repeat else None
        if kept is None:
            layout = WindowLayout(self.system, box, self.Zw, self.Zv, i, k)
            kept = self._outer[k - i] = (layout, ParametricSupport(
                _selection(layout, self.n), layout.A, self.D, _free(layout, box)).session())
        return kept

    def _inner_engine(self, inner: ConstrainedZonotope, i: int, k: int) -> tuple:
        """The layout, the block of −P̃ (the n rows x_i − P̃ξ_λ = 0, the prior's r columns after the
        states; row by row) and the session; the layout built with placeholders 1 in the block."""
        kept = self._inner.get(k - i) if self.repeat else None
        if kept is None:
            n, r = self.n, inner.ng
            placeholder = ConstrainedZonotope._trusted(-np.ones((n, r)), inner.c, inner.A, inner.b, inner.h)
            layout = WindowLayout(self.system, placeholder, self.Zw, self.Zv, i, k)
            first = (k - i + 1) * n
            block = (layout.prior_row + np.repeat(np.arange(n), r), first + np.tile(np.arange(r), n))
            kept = self._inner[k - i] = (layout, block, ParametricPoints(
                _selection(layout, n), layout.A.toarray(), self.D, _free(layout, inner), block).session())
        return kept


def _selection(layout, n: int) -> np.ndarray:
    """G of the window's posterior: x_k, the last n states."""
    G = np.zeros((n, layout.A.shape[1]))
    first = layout.G.shape[0] - n
    G[:, first:first + n] = np.eye(n)
    return G


def _free(layout, prior: ConstrainedZonotope) -> np.ndarray:
    """The states are the free factors (and the prior's own, if any)."""
    free = np.zeros(layout.A.shape[1], dtype=bool)
    states = layout.G.shape[0]
    free[:states] = True
    free[states:states + prior.ng] = np.isinf(prior.h)
    return free
