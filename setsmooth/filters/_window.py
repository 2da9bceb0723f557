"""The OIT-CZ window F_{k,k−δ̄}(Z) with a constant constraint matrix (stability paper (22)–(23)).

Line 8 of Algorithm 3 starts the exact filter δ̄ steps back from a prior of the form

    Z = Z(M, c_p, [], [], h_p)        (M constant; c_p, h_p change from step to step)

(ℝⁿ for observable systems: M = I, h_p = ∞; P⁻¹(P_o·IH × B_α) otherwise, with the interval hull's
half-widths and α as factor bounds). With the states eliminated as in (23) the window is one extended CZ

    factors  ξ_p (prior, h_p), ξ_w,0..δ̄−1 (W), ξ_v,0..δ̄ (V)
    G = [A^δ̄ M, A^{δ̄−1} B G_w, …, B G_w, 0],        c = x̄_δ̄,
    rows     A_w ξ_w,l = b_w,   A_v ξ_v,j = b_v,
             C A^j M ξ_p + Σ_{l<j} C A^{j−1−l} B G_w ξ_w,l + D G_v ξ_v,j = y_{i+j} − D c_v − C x̄_j,

about the nominal trajectory x̄_0 = c_p, x̄_{j+1} = A x̄_j + B c_w + u_{i+j}. G and A depend on the
system and δ̄ only, so they are built once: a step computes the nominal trajectory and b (O(δ̄ n²)
flops) and wraps the five arrays, nothing else. Every window shares G and A, which is what lets the
interval hulls share one engine of warm-started simplex models (`setsmooth.solvers.parametric`).

Rounding. G, A, the nominal trajectory and b are computed in floating point, so the stored window is
not exactly F_{k,k−δ̄}(Z). `Window.charged_data` returns, with (c, b, h), the rounding charges of
`setsmooth.sets.rounding` that make the stored window an enclosure of the exact one: the matrices'
errors (bounded once per window structure through the chain of powers A^j = A·A^{j−1}) times the
factor bounds, and per step the nominal trajectory's drift (each step's residual bounded in extended
precision, propagated through |A|) and the rounding of b. The prior (M, c_p, h_p) is taken as
given: it is exact by definition.
"""

from __future__ import annotations

import numpy as np

from ..sets import rounding
from ..sets.constrained_zonotope import ConstrainedZonotope

__all__ = ["Window"]


class Window:
    """The window structure of one (system, δ̄, M): G and A once, b and c per step.

    Parameters
    ----------
    system : LinearSystem
        Time-invariant matrices (checked by the caller); an input term u is allowed.
    delta_bar : int
        Window length δ̄ ≥ 1 (k − i).
    M : ndarray, shape (n, r)
        The prior's generator matrix.
    """

    def __init__(self, system, delta_bar: int, M: np.ndarray):
        self.system = system
        self.delta_bar = d = int(delta_bar)
        A, B, C, D = (np.asarray(f(0), dtype=float) for f in (system.A_at, system.E_at, system.C_at, system.F_at))
        # A noise set converted with rounding charges (a box whose midpoint is not representable)
        # has them written as generators, so the window's noise blocks are exact copies.
        Wz, Vz = (S.to_constrained_zonotope() for S in (system.W, system.V))
        Wz, Vz = (Z.materialized() if Z._charged else Z for Z in (Wz, Vz))
        Gw, Gv = _dense(Wz.G), _dense(Vz.G)
        Aw, Av = _dense(Wz.A), _dense(Vz.A)
        n, m = system.n, system.m
        r, pw, qv = M.shape[1], Gw.shape[1], Gv.shape[1]
        ncw, ncv = Aw.shape[0], Av.shape[0]
        self.n, self.r = n, r
        self.ng = r + d * pw + (d + 1) * qv
        nrows = d * ncw + (d + 1) * ncv + (d + 1) * m
        col_w, col_v = r, r + d * pw

        # The matrices with elementwise bounds on their rounding (None: exact), `_chain`.
        powers, dpowers = [np.eye(n)], [None]
        for _ in range(d):
            powers.append(A @ powers[-1])
            dpowers.append(_chain(A, None, powers[-2], dpowers[-1], powers[-1]))
        CP = [C @ P for P in powers]
        dCP = [_chain(C, None, P, dP, CPj) for P, dP, CPj in zip(powers, dpowers, CP)]
        BG = B @ Gw
        dBG = _chain(B, None, Gw, None, BG)
        G = np.zeros((n, self.ng))
        dG = np.zeros((n, self.ng))
        G[:, :r] = powers[d] @ M
        dG[:, :r] = _dense_or_zero(_chain(powers[d], dpowers[d], M, None, G[:, :r]), (n, r))
        for l in range(d):
            cols = slice(col_w + l * pw, col_w + (l + 1) * pw)
            G[:, cols] = powers[d - 1 - l] @ BG
            dG[:, cols] = _dense_or_zero(_chain(powers[d - 1 - l], dpowers[d - 1 - l], BG, dBG, G[:, cols]),
                                         (n, pw))
        Amat = np.zeros((nrows, self.ng))
        dA = np.zeros((nrows, self.ng))
        row = 0
        for l in range(d):
            Amat[row:row + ncw, col_w + l * pw: col_w + (l + 1) * pw] = Aw
            row += ncw
        for j in range(d + 1):
            Amat[row:row + ncv, col_v + j * qv: col_v + (j + 1) * qv] = Av
            row += ncv
        self.meas_row = row
        DGv = D @ Gv
        dDGv = _dense_or_zero(_chain(D, None, Gv, None, DGv), (m, qv))
        for j in range(d + 1):
            rows = slice(row, row + m)
            Amat[rows, :r] = CP[j] @ M
            dA[rows, :r] = _dense_or_zero(_chain(CP[j], dCP[j], M, None, Amat[rows, :r]), (m, r))
            for l in range(j):
                cols = slice(col_w + l * pw, col_w + (l + 1) * pw)
                Amat[rows, cols] = CP[j - 1 - l] @ BG
                dA[rows, cols] = _dense_or_zero(
                    _chain(CP[j - 1 - l], dCP[j - 1 - l], BG, dBG, Amat[rows, cols]), (m, pw))
            Amat[rows, col_v + j * qv: col_v + (j + 1) * qv] = DGv
            dA[rows, col_v + j * qv: col_v + (j + 1) * qv] = dDGv
            row += m
        # For a prior that is the whole space (M = I, all factors free) any centre c_p describes the
        # same window; `centred_prior` picks the least-squares one through the measurement rows'
        # prior block (the observability matrix [C; CA; …; CA^δ̄]), so that the free factors, and
        # the bound β on them that every certificate multiplies, stay of the noise's scale instead
        # of the states' (4e-3 of the width looser at states 1e6 with c_p = 0).
        prior_rows = Amat[self.meas_row:, :r]
        self._prior_pinv = np.linalg.pinv(prior_rows) if r == n else None
        self._dG = dG if dG.any() else None
        self._dA = dA if dA.any() else None
        self._absA, self._absC = np.abs(A), np.abs(C)
        self._B, self._D, self._cw, self._cv = B, D, Wz.c, Vz.c
        for arr in (G, Amat):
            arr.flags.writeable = False
        self.G, self.A = G, Amat
        self._G0, self._A0 = np.zeros((n, 0)), np.zeros((0, 0))  # cheap stand-ins for the copy
        self._sysA, self._C = A, C
        self._Bcw = B @ Wz.c
        self._Dcv = D @ Vz.c
        self._b_fixed = np.concatenate([np.tile(Wz.b, d), np.tile(Vz.b, d + 1)])
        self._h_noise = np.concatenate([np.tile(Wz.h, d), np.tile(Vz.h, d + 1)])

    def data(self, ys: np.ndarray, k: int, c_p: np.ndarray, h_p: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(c, b, h) of the window ending at time k (prior at i = k − δ̄ with centre c_p, bounds h_p),
        without the rounding charges (`charged_data`)."""
        nominal, _, b = self._nominal(ys, k, c_p)
        return nominal[-1], b, np.concatenate([h_p, self._h_noise])

    def _nominal(self, ys: np.ndarray, k: int, c_p: np.ndarray) -> tuple[list, list, np.ndarray]:
        """The nominal states x̄_0..x̄_δ̄ from c_p, the inputs u_i..u_{k−1}, and b."""
        d, m, n = self.delta_bar, self.system.m, self.n
        i = k - d
        b = np.empty(self.A.shape[0])
        b[:self.meas_row] = self._b_fixed
        nominal = [np.asarray(c_p, dtype=float)]
        inputs = []
        has_input = self.system.has_input
        for j in range(d + 1):
            x = nominal[-1]
            b[self.meas_row + j * m: self.meas_row + (j + 1) * m] = ys[i + j] - self._Dcv - self._C @ x
            if j < d:
                u = self.system.input_term(i + j) if has_input else np.zeros(n)
                x = self._sysA @ x + self._Bcw
                if has_input:
                    x = x + u
                nominal.append(x)
                inputs.append(u)
        return nominal, inputs, b

    def charged_data(self, ys: np.ndarray, k: int, c_p: np.ndarray, h_p: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
        """(c, b, h, charges): `data` and the rounding charges (``pad``, ``slack``, ``pad_free``,
        ``slack_free``; None where zero) under which the stored window encloses the exact one.

        With x̄_j the computed nominal states and x*_j the exact ones (x*_0 = x̄_0 = c_p),
        δ_j = x*_j − x̄_j obeys δ_{j+1} = A δ_j + r_j, r_j = A x̄_j + B c_w + u − x̄_{j+1} the residual of
        the computed step: |δ_j| ≤ Δ_j, Δ_{j+1} = |A|Δ_j + bound(r_j). So the centre is padded by Δ_δ̄
        and measurement row j's slack is |C|Δ_j plus the rounding of its b; the matrices' errors add
        |ΔG| h and |ΔA| h (per unit of ‖ξ_F‖∞ on free factors).
        """
        d, m, n = self.delta_bar, self.system.m, self.n
        i = k - d
        nominal, inputs, b = self._nominal(ys, k, c_p)
        h = np.concatenate([h_p, self._h_noise])
        meas = slice(self.meas_row, self.meas_row + (d + 1) * m)
        # Every step's residual and every measurement row's rounding, in two extended-precision
        # products (one column per step).
        X = np.array(nominal).T               # (n, d + 1)
        B_meas = b[meas].reshape(d + 1, m).T  # (m, d + 1)
        b_error = rounding.extended_residual_bound(
            [(np.ones(m), np.asarray(ys[i:k + 1], dtype=float).T),
             (-self._D, np.repeat(self._cv[:, None], d + 1, axis=1)),
             (-self._C, X), (-np.ones(m), B_meas)])
        if d:
            step_error = rounding.extended_residual_bound(
                [(self._sysA, X[:, :d]), (self._B, np.repeat(self._cw[:, None], d, axis=1)),
                 (np.ones(n), np.array(inputs).T), (-np.ones(n), X[:, 1:])])
        drift = np.zeros(n)
        meas_slack = np.empty((d + 1, m))
        for j in range(d + 1):
            meas_slack[j] = rounding.rounded_up(b_error[:, j] + self._absC @ drift, n + 1)
            if j < d:
                drift = rounding.rounded_up(self._absA @ drift + step_error[:, j], n + 1)
        slack = np.zeros(self.A.shape[0])
        slack[meas] = meas_slack.reshape(-1)
        pad, pad_free, slack_free = drift, None, None
        if self._dG is not None:
            bounded, free = rounding._weighted_rows(self._dG, h)
            pad = rounding.add(pad, bounded)
            pad_free = free if free.any() else None
        if self._dA is not None:
            bounded, free = rounding._weighted_rows(self._dA, h)
            slack = rounding.add(slack, bounded)
            slack_free = free if free.any() else None
        charges = {"pad": pad if pad.any() else None, "slack": slack if slack.any() else None,
                   "pad_free": pad_free, "slack_free": slack_free}
        return nominal[-1], b, h, charges

    def centred_prior(self, ys: np.ndarray, k: int) -> np.ndarray:
        """A centre c_p for a prior that is the whole space (M = I, h_p = ∞): the least-squares fit of
        the window's measurements (any c_p gives the same set; this one keeps the free factors small).
        """
        if self._prior_pinv is None:
            raise ValueError("centred_prior needs a window built with M = I (a prior of all of R^n)")
        zero = np.zeros(self.n)
        b = self._nominal(ys, k, zero)[2]
        c_p = self._prior_pinv @ b[self.meas_row:]
        return c_p if np.all(np.isfinite(c_p)) else zero

    def estimate(self, ys: np.ndarray, k: int, c_p: np.ndarray, h_p: np.ndarray) -> ConstrainedZonotope:
        """F_{k,k−δ̄}(Z(M, c_p, [], [], h_p)) as an extended CZ sharing this window's G and A, with
        the rounding charges that make it an enclosure of the exact window (`charged_data`)."""
        c, b, h, charges = self.charged_data(ys, k, c_p, h_p)
        return self.estimate_from(c, b, h, **charges)

    def free(self, count: int) -> np.ndarray:
        """The free-factor pattern when the prior's first ``count`` factors are free (h = ∞)."""
        out = np.zeros(self.ng, dtype=bool)
        out[:count] = True
        return out

    def estimate_from(self, c: np.ndarray, b: np.ndarray, h: np.ndarray,
                      pad: np.ndarray | None = None, slack: np.ndarray | None = None,
                      pad_free: np.ndarray | None = None, slack_free: np.ndarray | None = None
                      ) -> ConstrainedZonotope:
        """The window CZ with this window's G and A, the given (c, b, h) and rounding charges.

        G and A are not copied: every window shares this object's private read-only arrays (the CZ
        constructor's defensive copy is for arrays a caller might still write to).
        """
        Z = ConstrainedZonotope._trusted(self._G0, c, self._A0, b, h, pad=pad, slack=slack,
                                         pad_free=pad_free, slack_free=slack_free)
        Z.G, Z.A = self.G, self.A
        return Z


def _chain(X, dX, Y, dY, stored: np.ndarray) -> np.ndarray | None:
    """The error bound of ``stored`` = fl(X·Y) (`rounding.chained_product_error`), None when zero."""
    err = rounding.chained_product_error(_dense(X), dX, _dense(Y), dY, product=stored)
    return err if err.any() else None


def _dense_or_zero(E: np.ndarray | None, shape: tuple[int, int]) -> np.ndarray:
    return np.zeros(shape) if E is None else E


def _dense(M) -> np.ndarray:
    return M.toarray() if hasattr(M, "toarray") else np.asarray(M, dtype=float)
