"""The two window programs of one bracket of `hulls_along_time`, kept for a time-invariant system.

For a window of length L the outer program is F_{k,k−L}(O) with O a box, and the inner one
F_{k,k−L}(I) with I a zonotope inside the convex hull of points of P_{k−L}. With the states eliminated
(stability paper (23), `_window.Window`) both have a constraint matrix that depends on the system and L
only, apart from the inner prior's generators:

* outer: O = Z(I, mid, [], [], radius) — `Window` with M = I, so the matrices are fixed and only
  (c, b, h) move; one `ParametricSupport` instance certifies it at every step;
* inner: I = Z(M, m, [], [], 1) with M = (P − m)ᵀ/(2r), m the mean of the r points P of P_{k−L}. Every
  point m + Mξ, |ξ| ≤ 1, is Σ_j w_j p_j with w_j = (1 + (ξ_j − ξ̄)/2)/r ≥ 0 and Σ_j w_j = 1, so I ⊆ conv P
  ⊆ P_{k−L}. Its blocks are the outer window's prior columns times M: A^L M and C A^j M. One Clarabel
  instance per L keeps a dense pattern for them, and a step updates their values and b.

Nothing is assembled or presolved per step. The inner program's values are plain (attained by points
of I's window to the solver's tolerance; a direction the kept instance does not settle is solved by the
window's own program, `solvers.policy`); the outer's are certified.
"""

from __future__ import annotations

import clarabel
import numpy as np
import scipy.sparse as sp

from ..sets.constrained_zonotope import ConstrainedZonotope
from ..solvers import clarabel_lp
from ..solvers.instances import cached_instance
from ..solvers.parametric import ParametricSupport
from ._window import Window

__all__ = ["BracketWindows"]


class BracketWindows:
    """The outer and inner programs of windows of length L for one system and directions D.

    Parameters
    ----------
    system : LinearSystem
        Time-invariant (the caller checks).
    length : int
        L = k − i ≥ 1.
    D : ndarray, shape (K, n)
        The directions (rows).
    points : int
        r, the number of points that span the inner prior.
    """

    def __init__(self, system, length: int, D: np.ndarray, points: int):
        n = system.n
        self.window = Window(system, length, np.eye(n))
        self.D, self.r = D, int(points)
        G, A = self.window.G, self.window.A
        self.outer = ParametricSupport(G, A, D, np.zeros(G.shape[1], dtype=bool))
        # The inner program: the prior's n columns become r, [A^L; C A^j] M; the rest is shared.
        self._prior_G, self._prior_A = G[:, :n], A[:, :n]
        self._rest_G, self._rest_A = G[:, n:], A[:, n:]
        self.ng_inner = self.r + G.shape[1] - n
        self._pattern = np.hstack([np.ones((A.shape[0], self.r), dtype=bool), self._rest_A != 0])

    def upper(self, ys: np.ndarray, k: int, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Certified upper bounds on h(d_j) over F_{k,k−L}(box [lo, hi]) (−inf: empty)."""
        mid = (lo + hi) / 2
        # the radius rounded up, so that the stored box {mid + ξ : |ξ| ≤ radius} holds [lo, hi]
        radius = np.nextafter(np.maximum(np.abs(hi - mid), np.abs(mid - lo)), np.inf)
        c, b, h, charges = self.window.charged_data(ys, k, mid, radius)
        return self.outer.values(c, b, h, **charges)

    def lower(self, ys: np.ndarray, k: int, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The solver's values and maximizers over F_{k,k−L}(I), I the zonotope of the points P
        (shape (r, n)) described in the module docstring; NaN where a solve did not settle."""
        m = P.mean(axis=0)
        M = (P - m).T / (2 * self.r)
        G = np.hstack([self._prior_G @ M, self._rest_G])
        A = np.hstack([self._prior_A @ M, self._rest_A])
        c, b, h = self.window.data(ys, k, m, np.ones(self.r))
        K, n = self.D.shape
        q = -(self.D @ G)
        solver = cached_instance(self, "inner", lambda: self._solver(A, b, h))
        solver.update(A=self._stacked_values(A), b=np.concatenate([b, h, h]))
        values, points = np.full(K, np.nan), np.full((K, n), np.nan)
        for j in range(K):
            solver.update(q=q[j])
            sol = solver.solve()
            if str(sol.status).split(".")[-1] == "Solved":
                points[j] = G @ np.asarray(sol.x) + c
                values[j] = self.D[j] @ points[j]
        unsettled = np.flatnonzero(np.isnan(values))
        if unsettled.size:
            # Degenerate windows (a state the data pin to a sliver) can stop the kept interior-point
            # instance short; the set's own program settles them (`solvers.policy`).
            Z = ConstrainedZonotope._trusted(G, c, A, b, h)
            values[unsettled], points[unsettled], _ = Z._program.support_points_and_bounds(
                self.D[unsettled])
        return values, points

    def _stacked_values(self, A: np.ndarray) -> np.ndarray:
        """The CSC values of [A; I; −I] on the fixed pattern (columns in order, rows ascending)."""
        ng = A.shape[1]
        blocks = []
        for col in range(ng):
            blocks.append(A[self._pattern[:, col], col])
            blocks.append(np.array([1.0, -1.0]))
        return np.concatenate(blocks)

    def _solver(self, A: np.ndarray, b: np.ndarray, h: np.ndarray) -> clarabel.DefaultSolver:
        nc, ng = A.shape
        rows, cols = np.nonzero(self._pattern)
        order = np.lexsort((rows, cols))
        rows, cols = rows[order], cols[order]
        all_rows = np.concatenate([rows, nc + np.arange(ng), nc + ng + np.arange(ng)])
        all_cols = np.concatenate([cols, np.arange(ng), np.arange(ng)])
        M = sp.csc_matrix((np.ones(all_rows.size), (all_rows, all_cols)), shape=(nc + 2 * ng, ng))
        M.sort_indices()
        M.data = self._stacked_values(A)
        cones = ([clarabel.ZeroConeT(nc)] if nc else []) + [clarabel.NonnegativeConeT(2 * ng)]
        settings = clarabel_lp.settings()
        settings.presolve_enable = False  # fixed rows, so that the data can be updated
        return clarabel.DefaultSolver(sp.csc_matrix((ng, ng)), np.zeros(ng), M,
                                      np.concatenate([b, h, h]), cones, settings)
