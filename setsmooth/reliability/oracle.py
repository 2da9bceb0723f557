"""An independent trajectory-LP oracle: exact interval hulls of filtered and smoothed ranges by HiGHS.

Nothing of setsmooth's set algebra or solvers is used: the noise sets are read off the objects
(``Box.lo/hi``, ``Zonotope.G/c``, ``ConstrainedZonotope.G/c/A/b/h``) and the LP is written here and
solved with ``scipy.optimize.linprog(method="highs")``.

Formulation. Every noise set is put in factor form {Gξ + c : Aξ = b, |ξ| ≤ h} (a box is G = diag of
its half-widths). The states are eliminated, x_k = M_k ζ + m_k, with ζ the stacked factors of x_0,
v_0, w_0, v_1, w_1, … (in time order) and m_k the propagated centres and inputs, so every variable
is a factor of range O(1) whatever the regime, and the data offset never enters the LP. Each
equality row (factor-set constraints and y_j = C_j x_j + D_j v_j) is divided by its ∞-norm, bounded
factors are substituted ξ = h η with |η| ≤ 1, and every objective row is normalized; HiGHS' primal
and dual feasibility tolerances are set to 1e-10 on that unit-scaled problem. Hence

    hull of ⟦x_k | y_0:k⟧ : max/min ±e_iᵀ x_k over the rows of times 0..k (factors of times ≤ k),
    hull of ⟦x_k | y_0:T⟧ : the same over all rows,

which is the trajectory LP of the smoothing paper's Theorem 1 in factor coordinates. `polish` turns
an LP vertex into a point satisfying the equalities to rounding (a feasible witness).
"""

from __future__ import annotations

from dataclasses import dataclass

import highspy
import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth.solvers.highs import quiet_highs

#: HiGHS tolerances on the unit-scaled problem.
HIGHS_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}

#: A vertex whose unit rows are off by more than this is polished before its value is read (most
#: simplex vertices meet their rows to ~1e-15; the polish costs a dense least-squares solve).
POLISH_ABOVE = 1e-13

#: Warm starts need the unpresolved model (a presolved one restarts from scratch).
_WARM_OPTIONS = {"presolve": "off", "solver": "simplex"}


class OracleError(RuntimeError):
    """HiGHS did not settle an oracle LP (or the data are inconsistent, which a case never is)."""


@dataclass(frozen=True)
class FactorForm:
    """{Gξ + c : Aξ = b, |ξ_j| ≤ h_j}, dense."""

    G: np.ndarray
    c: np.ndarray
    A: np.ndarray
    b: np.ndarray
    h: np.ndarray

    @property
    def radius(self) -> float:
        """∞-radius of the zonotope hull, max_i Σ_j |G_ij| h_j (a magnitude; inf when unbounded)."""
        if self.G.shape[1] == 0:
            return 0.0
        with np.errstate(invalid="ignore"):
            terms = np.where(self.G == 0, 0.0, np.abs(self.G) * self.h)
        return float(terms.sum(axis=1).max())


def factor_form(S) -> FactorForm:
    """Read the factor form off a Box, Zonotope or ConstrainedZonotope (its own matrices only)."""
    if isinstance(S, ss.Box):
        mid, rad = (S.lo + S.hi) / 2, (S.hi - S.lo) / 2
        keep = rad > 0
        G = np.diag(rad)[:, keep]
        return FactorForm(G, mid, np.zeros((0, G.shape[1])), np.zeros(0), np.ones(G.shape[1]))
    if isinstance(S, ss.ConstrainedZonotope):
        G = _dense(S.G)
        return FactorForm(G, np.array(S.c, float), _dense(S.A), np.array(S.b, float), np.array(S.h, float))
    if isinstance(S, ss.Zonotope):
        G = np.array(S.G, float)
        return FactorForm(G, np.array(S.c, float), np.zeros((0, G.shape[1])), np.zeros(0),
                          np.ones(G.shape[1]))
    raise TypeError(f"the oracle reads Box, Zonotope and ConstrainedZonotope, got {type(S).__name__}")


def _dense(M) -> np.ndarray:
    return np.asarray(M.toarray() if hasattr(M, "toarray") else M, dtype=float)


def data_scale(system, X0) -> float:
    """σ: the largest ∞-radius of X0, W, V (the data's noise magnitude, independent of any offset)."""
    return max(factor_form(S).radius for S in (X0, system.W, system.V))


class TrajectoryOracle:
    """Exact hulls of ⟦x_k | y_0:k⟧ and ⟦x_k | y_0:T⟧ for a LinearSystem with Box/Zonotope/CZ sets.

    Parameters
    ----------
    system : setsmooth.LinearSystem
    X0 : Box, Zonotope or ConstrainedZonotope
    ys : ndarray, shape (T+1, m)
    """

    def __init__(self, system, X0, ys):
        ys = np.atleast_2d(np.asarray(ys, dtype=float))
        self.n, self.T = system.n, ys.shape[0] - 1
        f0, fw, fv = factor_form(X0), factor_form(system.W), factor_form(system.V)
        # Column layout: ξ0, then per time j: ξv_j, then ξw_j (j < T).
        sizes = [f0.G.shape[1]]
        for j in range(self.T + 1):
            sizes.append(fv.G.shape[1])
            if j < self.T:
                sizes.append(fw.G.shape[1])
        starts = np.concatenate([[0], np.cumsum(sizes)])
        N = int(starts[-1])
        self.N = N
        h = np.zeros(N)
        rows, rhs, row_time = [], [], []

        def add_rows(M, f, t):
            for r, fr in zip(M, f):
                rows.append(r)
                rhs.append(fr)
                row_time.append(t)

        def embed(block, start):
            out = np.zeros((block.shape[0], N))
            out[:, start:start + block.shape[1]] = block
            return out

        h[starts[0]:starts[1]] = f0.h
        add_rows(embed(f0.A, starts[0]), f0.b, 0)
        M = embed(f0.G, starts[0])  # x_0 = M ζ + m
        m = f0.c.copy()
        # The rounding level of every measurement row (`data_tolerance`): (j + 2)(n + N) ε times the
        # magnitudes it is computed from, |y| + |C||m| + |C||M|h (an estimate of the accuracy of the
        # data, not a bound: a rigorous bound by |A|^j grows like ρ(|A|)^j on stable systems).
        level = [0.0] * f0.A.shape[0]
        self._M, self._m, self._ncols = [], [], []
        col = 1
        for j in range(self.T + 1):
            if j > 0:
                Ak, Bk = system.A_at(j - 1), system.E_at(j - 1)
                sw = starts[col]
                col += 1
                h[sw:sw + fw.G.shape[1]] = fw.h
                add_rows(embed(fw.A, sw), fw.b, j)
                M = Ak @ M + embed(Bk @ fw.G, sw)
                m = Ak @ m + Bk @ fw.c + system.input_term(j - 1)
            sv = starts[col]
            col += 1
            h[sv:sv + fv.G.shape[1]] = fv.h
            add_rows(embed(fv.A, sv), fv.b, j)
            Cj, Dj = system.C_at(j), system.F_at(j)
            level.extend([0.0] * fv.A.shape[0] + [0.0] * (fw.A.shape[0] if j > 0 else 0))
            add_rows(Cj @ M + embed(Dj @ fv.G, sv), ys[j] - Cj @ m - Dj @ fv.c, j)
            hfin = np.where(np.isfinite(h), h, 0.0)
            level.extend((j + 2) * (self.n + N) * np.finfo(float).eps * (
                np.abs(ys[j]) + np.abs(Cj) @ np.abs(m) + np.abs(Dj) @ np.abs(fv.c)
                + np.abs(Cj) @ (np.abs(M) @ hfin) + np.abs(Dj) @ (np.abs(fv.G) @ np.where(np.isfinite(fv.h), fv.h, 0.0))))
            self._M.append(M.copy())
            self._m.append(m.copy())
            self._ncols.append(int(starts[col]))
        E = np.array(rows).reshape(len(rows), N)
        f = np.array(rhs, dtype=float)
        self._row_time = np.array(row_time, dtype=int)
        # Bounded factors ξ = h η, |η| ≤ 1; h = 0 fixes η = 0; h = ∞ leaves it free and unscaled.
        finite = np.isfinite(h)
        self._colscale = np.where(finite & (h > 0), h, 1.0)
        self._bounds = np.column_stack([np.where(finite, np.where(h > 0, -1.0, 0.0), -np.inf),
                                        np.where(finite, np.where(h > 0, 1.0, 0.0), np.inf)])
        E = E * self._colscale
        norms = np.abs(E).max(axis=1) if E.size else np.zeros(0)
        zero = norms == 0
        if np.any(np.abs(f[zero]) > 0):
            raise OracleError("a measurement row with no factor has a nonzero residual")
        self._E = E[~zero] / norms[~zero, None]
        self._f = f[~zero] / norms[~zero]
        #: The rounding level of the unit-scaled rows: the largest error with which floating point
        #: states the data (propagated centres, measurement residuals). Where the data pin the
        #: state (more independent measurements than unknowns, or a state 1e11 σ from the origin)
        #: the exact feasible set is as thin as this, and HiGHS at 1e-10 can call it infeasible.
        self.data_tolerance = float(np.max(np.asarray(level)[~zero] / norms[~zero], initial=0.0))
        self._row_time = self._row_time[~zero]
        self._warm: _WarmLP | None = None

    # -- LPs -------------------------------------------------------------------------------------------
    def _lp(self, upto: int) -> "_WarmLP":
        """The one HiGHS model, with the measurement rows of times > ``upto`` made free (inactive)."""
        if self._warm is None:
            self._warm = _WarmLP(self._E, self._f, self._bounds, self.data_tolerance)
        self._warm.activate(self._row_time <= upto)
        return self._warm

    def support(self, k: int, d, upto: int | None = None, point: bool = False):
        """max dᵀx_k over trajectories consistent with y_0..y_upto (upto ≥ k; default T).

        Returns the value; with ``point=True`` the triple (value, x_k, residual): a polished
        maximizing x_k and the ∞-norm residual of its (unit-row) equalities.
        """
        upto = self.T if upto is None else upto
        if not 0 <= k <= upto <= self.T:
            raise ValueError(f"need 0 <= k <= upto <= T, got k={k}, upto={upto}, T={self.T}")
        d = np.asarray(d, dtype=float)
        obj = (d @ self._M[k]) * self._colscale
        base = float(d @ self._m[k])
        scale = np.abs(obj).max(initial=0.0)
        lp = self._lp(upto)
        eta = lp.maximize(obj / scale if scale else obj, f"k={k}, upto={upto}")
        if eta is None:
            return (np.inf, None, np.nan) if point else np.inf
        # The LP vertex satisfies the rows only to HiGHS's 1e-10; on a thin set (a posterior pinned by
        # ill-conditioned measurements, reliability case 069: a point) that moved the value by 2.4e-9.
        # The polished vertex is a member of the set to rounding, so its value is the one reported
        # whenever the polish brings the rows closer (an LP optimum moved onto the rows).
        rows = self._row_time <= upto
        E, f = self._E[rows], self._f[rows]
        if residual(E, f, eta) > POLISH_ABOVE:
            polished = polish(E, f, self._bounds, eta)
            if residual(E, f, polished) < residual(E, f, eta):
                eta = polished
        value = base + float(obj @ eta)
        if not point:
            return value
        x = self._M[k] @ (eta * self._colscale) + self._m[k]
        return value, x, residual(E, f, eta)

    def support_linprog(self, k: int, d, upto: int | None = None) -> float:
        """The same value by a cold `scipy.optimize.linprog(method='highs')` (a cross-check)."""
        upto = self.T if upto is None else upto
        rows = self._row_time <= upto
        ncol = self._ncols[upto]
        d = np.asarray(d, dtype=float)
        obj = (d @ self._M[k])[:ncol] * self._colscale[:ncol]
        E = self._E[rows][:, :ncol]
        res = linprog(-obj, A_eq=E if E.size else None, b_eq=self._f[rows] if E.size else None,
                      bounds=self._bounds[:ncol], method="highs", options=HIGHS_OPTIONS)
        if res.status == 3:
            return np.inf
        if res.status != 0:
            raise OracleError(f"linprog status {res.status} ({res.message}) for k={k}, upto={upto}")
        return float(d @ self._m[k]) + float(obj @ res.x)

    def hull(self, k: int, upto: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi) of the interval hull of x_k given y_0..y_upto (default T: smoothed)."""
        eye = np.eye(self.n)
        hi = np.array([self.support(k, e, upto) for e in eye])
        lo = np.array([-self.support(k, -e, upto) for e in eye])
        return lo, hi

    def filtered_hulls(self) -> tuple[np.ndarray, np.ndarray]:
        """Hulls of ⟦x_k | y_0:k⟧, arrays (T+1, n) of lower and upper bounds."""
        pairs = [self.hull(k, k) for k in range(self.T + 1)]
        return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])

    def smoothed_hulls(self) -> tuple[np.ndarray, np.ndarray]:
        """Hulls of ⟦x_k | y_0:T⟧, arrays (T+1, n)."""
        pairs = [self.hull(k) for k in range(self.T + 1)]
        return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


class _WarmLP:
    """One HiGHS model {Eη = f (active rows), bounds}, re-solved from the last basis per objective.

    Cold ``linprog`` calls took ~10 ms each (200+ simplex iterations) on a 135 × 273 trajectory LP and
    an oracle needs 2n(T+1) of them per hull sequence; from the previous optimal basis a new objective
    or one more block of rows takes a handful of iterations. Same solver, same tolerances.
    """

    def __init__(self, E: np.ndarray, f: np.ndarray, bounds: np.ndarray, data_tolerance: float = 0.0):
        self.E, self.bounds = E, bounds
        self.data_tolerance = data_tolerance
        self.h = self._model(E, f, bounds, {**HIGHS_OPTIONS, **_WARM_OPTIONS})
        self.f = f
        self.active = np.ones(E.shape[0], dtype=bool)
        self.n = E.shape[1]

    @staticmethod
    def _model(E: np.ndarray, f: np.ndarray, bounds: np.ndarray, options: dict):
        h = quiet_highs()  # (only the construction: HiGHS's banner kept off the terminal)
        for key, value in options.items():
            h.setOptionValue(key, value)
        inf = highspy.kHighsInf
        lp = highspy.HighsLp()
        lp.num_col_, lp.num_row_ = E.shape[1], E.shape[0]
        lp.col_cost_ = np.zeros(E.shape[1])
        lp.col_lower_ = np.where(np.isfinite(bounds[:, 0]), bounds[:, 0], -inf)
        lp.col_upper_ = np.where(np.isfinite(bounds[:, 1]), bounds[:, 1], inf)
        lp.row_lower_ = f.copy()
        lp.row_upper_ = f.copy()
        A = sp.csc_matrix(E)
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = A.indptr
        lp.a_matrix_.index_ = A.indices
        lp.a_matrix_.value_ = A.data
        lp.sense_ = highspy.ObjSense.kMaximize
        h.passModel(lp)
        return h

    def activate(self, active: np.ndarray) -> None:
        change = np.flatnonzero(active != self.active)
        if change.size:
            inf = highspy.kHighsInf
            lower = np.where(active[change], self.f[change], -inf)
            upper = np.where(active[change], self.f[change], inf)
            self.h.changeRowsBounds(change.size, change.astype(np.int32), lower, upper)
            self.active = active.copy()

    def maximize(self, c: np.ndarray, context: str) -> np.ndarray | None:
        """An optimal η, or None when unbounded; raises OracleError otherwise."""
        self.h.changeColsCost(self.n, np.arange(self.n, dtype=np.int32), c)
        for attempt in range(2):
            self.h.run()
            status = self.h.getModelStatus()
            if status == highspy.HighsModelStatus.kOptimal:
                return np.array(self.h.getSolution().col_value)
            if status == highspy.HighsModelStatus.kUnbounded:
                return None
            # A warm start can stall ('Unknown'); the second attempt starts from scratch.
            self.h.clearSolver()
        # Last: a separate cold model of the active rows with HiGHS's presolve on (the warm model has
        # it off; on some singular-A trajectory LPs that model stalled or misread infeasibility).
        cold = self._model(self.E[self.active], self.f[self.active], self.bounds, HIGHS_OPTIONS)
        cold.changeColsCost(self.n, np.arange(self.n, dtype=np.int32), c)
        cold.run()
        status = cold.getModelStatus()
        tolerance = HIGHS_OPTIONS["primal_feasibility_tolerance"]
        if status == highspy.HighsModelStatus.kInfeasible and self.data_tolerance > tolerance:
            # Infeasible at 1e-10, on data that floating point states only to data_tolerance (the
            # simulated truth is feasible): the exact set is thinner than the data's rounding. The
            # oracle then answers at the data's own accuracy (reliability cases 072: states 3e11
            # at k = 6, a hull 7 wide; 074 at offset 1e6: three measurements pin x exactly).
            cold = self._model(self.E[self.active], self.f[self.active], self.bounds,
                               {**HIGHS_OPTIONS, "primal_feasibility_tolerance": self.data_tolerance})
            cold.changeColsCost(self.n, np.arange(self.n, dtype=np.int32), c)
            cold.run()
            status = cold.getModelStatus()
        if status == highspy.HighsModelStatus.kOptimal:
            return np.array(cold.getSolution().col_value)
        if status == highspy.HighsModelStatus.kUnbounded:
            return None
        raise OracleError(f"HiGHS status {cold.modelStatusToString(status)} ({context})")


def polish(E: np.ndarray, f: np.ndarray, bounds: np.ndarray, eta: np.ndarray) -> np.ndarray:
    """Move an LP point onto Eη = f to rounding, keeping it inside the bounds.

    The variables strictly inside their bounds absorb the residual by a minimum-norm least-squares
    step (twice, for refinement); if that pushes one out, it is clipped and the step repeated on the
    rest. The result is a feasible witness whose residual is reported by `residual`.
    """
    eta = np.clip(eta, bounds[:, 0], bounds[:, 1])
    if E.size == 0:
        return eta
    for _ in range(4):
        r = f - E @ eta
        if np.abs(r).max() <= 1e-15:
            break
        at_bound = (eta <= bounds[:, 0] + 1e-12) | (eta >= bounds[:, 1] - 1e-12)
        free = ~at_bound
        if not free.any():
            break
        step = np.linalg.lstsq(E[:, free], r, rcond=None)[0]
        eta_new = eta.copy()
        eta_new[free] += step
        eta = np.clip(eta_new, bounds[:, 0], bounds[:, 1])
    return eta


def residual(E: np.ndarray, f: np.ndarray, eta: np.ndarray) -> float:
    """∞-norm of Eη − f (rows are unit-∞-norm, so this is relative to the data)."""
    return float(np.abs(E @ eta - f).max(initial=0.0))


def cz_support(f: FactorForm, d) -> tuple[float, np.ndarray | None]:
    """max dᵀx over {Gξ + c : Aξ = b, |ξ| ≤ h} by linprog on the unit-scaled LP, and a polished argmax.

    Rows are divided by their ∞-norm and bounded factors substituted ξ = hη, as in the trajectory
    oracle, so the answer does not depend on how the set is scaled. ``-inf`` for an empty set,
    ``inf`` (and no point) along an unbounded direction.
    """
    d = np.asarray(d, dtype=float)
    finite = np.isfinite(f.h)
    colscale = np.where(finite & (f.h > 0), f.h, 1.0)
    bounds = np.column_stack([np.where(finite, np.where(f.h > 0, -1.0, 0.0), -np.inf),
                              np.where(finite, np.where(f.h > 0, 1.0, 0.0), np.inf)])
    E = f.A * colscale
    norms = np.abs(E).max(axis=1) if E.size else np.zeros(0)
    keep = norms > 0
    if np.any(np.abs(f.b[~keep]) > 0):
        return -np.inf, None
    E, rhs = E[keep] / norms[keep, None], f.b[keep] / norms[keep]
    obj = (d @ f.G) * colscale
    scale = np.abs(obj).max(initial=0.0) or 1.0
    res = linprog(-obj / scale, A_eq=E if E.size else None, b_eq=rhs if E.size else None,
                  bounds=bounds, method="highs", options=HIGHS_OPTIONS)
    if res.status == 2:
        return -np.inf, None
    if res.status == 3:
        return np.inf, None
    if res.status != 0:
        raise OracleError(f"linprog status {res.status} ({res.message})")
    eta = polish(E, rhs, bounds, res.x) if E.size else res.x
    point = f.G @ (eta * colscale) + f.c
    return float(d @ f.c + obj @ res.x), point
