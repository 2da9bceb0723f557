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
interval hulls reuse one solver instance (`setsmooth.solvers.parametric`).
"""

from __future__ import annotations

import numpy as np

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
        A, B, C, D = (np.asarray(f(0), dtype=float) for f in (system.A, system.B, system.C, system.D))
        Wz, Vz = system.W.to_constrained_zonotope(), system.V.to_constrained_zonotope()
        Gw, Gv = _dense(Wz.G), _dense(Vz.G)
        Aw, Av = _dense(Wz.A), _dense(Vz.A)
        n, m = system.n, system.m
        r, pw, qv = M.shape[1], Gw.shape[1], Gv.shape[1]
        ncw, ncv = Aw.shape[0], Av.shape[0]
        self.n, self.r = n, r
        self.ng = r + d * pw + (d + 1) * qv
        nrows = d * ncw + (d + 1) * ncv + (d + 1) * m
        col_w, col_v = r, r + d * pw

        powers = [np.eye(n)]
        for _ in range(d):
            powers.append(A @ powers[-1])
        BG = B @ Gw
        G = np.zeros((n, self.ng))
        G[:, :r] = powers[d] @ M
        for l in range(d):
            G[:, col_w + l * pw: col_w + (l + 1) * pw] = powers[d - 1 - l] @ BG
        Amat = np.zeros((nrows, self.ng))
        row = 0
        for l in range(d):
            Amat[row:row + ncw, col_w + l * pw: col_w + (l + 1) * pw] = Aw
            row += ncw
        for j in range(d + 1):
            Amat[row:row + ncv, col_v + j * qv: col_v + (j + 1) * qv] = Av
            row += ncv
        self.meas_row = row
        DGv = D @ Gv
        for j in range(d + 1):
            rows = slice(row, row + m)
            Amat[rows, :r] = C @ powers[j] @ M
            for l in range(j):
                Amat[rows, col_w + l * pw: col_w + (l + 1) * pw] = C @ powers[j - 1 - l] @ BG
            Amat[rows, col_v + j * qv: col_v + (j + 1) * qv] = DGv
            row += m
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
        """(c, b, h) of the window ending at time k (prior at i = k − δ̄ with centre c_p, bounds h_p)."""
        d, m = self.delta_bar, self.system.m
        i = k - d
        b = np.empty(self.A.shape[0])
        b[:self.meas_row] = self._b_fixed
        x = np.asarray(c_p, dtype=float)
        row = self.meas_row
        has_input = self.system.has_input
        for j in range(d + 1):
            b[row:row + m] = ys[i + j] - self._Dcv - self._C @ x
            row += m
            if j < d:
                x = self._sysA @ x + self._Bcw
                if has_input:
                    x = x + self.system.input_term(i + j)
        h = np.concatenate([h_p, self._h_noise])
        return x, b, h

    def estimate(self, ys: np.ndarray, k: int, c_p: np.ndarray, h_p: np.ndarray) -> ConstrainedZonotope:
        """F_{k,k−δ̄}(Z(M, c_p, [], [], h_p)) as an extended CZ sharing this window's G and A."""
        return self.estimate_from(*self.data(ys, k, c_p, h_p))

    def free(self, count: int) -> np.ndarray:
        """The free-factor pattern when the prior's first ``count`` factors are free (h = ∞)."""
        out = np.zeros(self.ng, dtype=bool)
        out[:count] = True
        return out

    def estimate_from(self, c: np.ndarray, b: np.ndarray, h: np.ndarray) -> ConstrainedZonotope:
        """The window CZ with this window's G and A and the given (c, b, h).

        G and A are not copied: every window shares this object's private read-only arrays (the CZ
        constructor's defensive copy is for arrays a caller might still write to).
        """
        Z = ConstrainedZonotope._trusted(self._G0, c, self._A0, b, h)
        Z.G, Z.A = self.G, self.A
        return Z


def _dense(M) -> np.ndarray:
    return M.toarray() if hasattr(M, "toarray") else np.asarray(M, dtype=float)
