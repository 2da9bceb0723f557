"""The support-function, certificate and membership programs of one constrained zonotope.

`CZProgram` holds Z(G, c, A, b, h) over its shared `FactorConstraints` and maximizes (Gᵀd)ᵀξ over the
factor set for each direction d (one LP per direction on the factor set's kept, presolved instance):

    h_Z(d) = dᵀc + max{(Gᵀd)ᵀξ : Aξ = b, |ξ| ≤ h}.

``certified=True`` returns instead the weak-duality bound of `certify.certified_bound`, an upper bound
on h_Z(d) in floating point whatever the solver did (free factors: multipliers corrected by least
squares, residual charged against a rigorous bound on the free factors, else `SolverError`).

Every answer, certified or not, is checked a posteriori (`CZProgram._verified`): the bound U and the
solver's value L of the same solve bracket h_Z(d), so U − L bounds the error of both; a bracket wider
than ``SUPPORT_GAP_TOL`` of the set's width along d is solved again by the simplex method. Interior-
point answers that stop early (a loose dual on badly scaled free factors) are caught this way rather
than returned as silently wrong numbers; and since this check decides, a rough first answer goes
straight to the simplex method (``bracketed``), without the refined interior-point re-solve.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .certify import Operators, certified_bound, correct_multipliers, normal_solver
from .clarabel_lp import _ALMOST_SOLVED, SolverError, solve_lp
from .factor_set import FactorConstraints
from .instances import cached_instance
from .warm_simplex import new_batch

__all__ = ["CZProgram", "SupportSolution"]


@dataclass(frozen=True)
class SupportSolution:
    """A support point of a CZ with its factors and multipliers.

    Attributes
    ----------
    value : float
        h_Z(d) (``-inf`` when Z is empty, ``inf`` when unbounded in d).
    point : ndarray, shape (n,)
        A maximizer x = Gξ + c (NaN when the value is infinite).
    factors : ndarray, shape (ng,)
        Its factor vector ξ (NaN when the value is infinite).
    multipliers : ndarray, shape (nc,)
        Multipliers λ of Aξ = b (for the original rows; NaN when the value is infinite).
    """

    value: float
    point: np.ndarray
    factors: np.ndarray
    multipliers: np.ndarray


class CZProgram:
    """The support-function LP of one constrained zonotope Z(G, c, A, b, h).

    Parameters
    ----------
    G : ndarray or sparse matrix, shape (n, ng)
    c : ndarray, shape (n,)
    factors : FactorConstraints
        The shared factor set of the CZ. Arguments are trusted (validated by the caller).
    """

    def __init__(self, G, c: np.ndarray, factors: FactorConstraints,
                 pad: np.ndarray | None = None, pad_free: np.ndarray | None = None):
        self.G = sp.csc_matrix(G) if sp.issparse(G) else G
        self.c = c
        self.factors = factors
        # The set's rounding pads (`setsmooth.sets.rounding`), charged by certificates.
        self.pad, self.pad_free = pad, pad_free
        self.A, self.b, self.h = factors.A, factors.b, factors.h
        self.ng, self.nc, self.finite = factors.ng, factors.nc, factors.finite
        self._ops: Operators | None = None  # prepared on the first certificate
        #: Seconds spent in the LPs (Clarabel and the presolved program's recovery) of the last
        #: `support` call.
        self.last_solve_time = 0.0

    # -- queries -----------------------------------------------------------------------------------
    def support(self, D: np.ndarray,
                certified: bool | None = False) -> tuple[np.ndarray, np.ndarray]:
        """Support values and support points for every row of ``D``.

        ``certified``: True returns floating-point upper bounds (or raises); None returns them where
        a sound bound exists and the solver's values elsewhere; False the solver's values.

        Returns
        -------
        values : ndarray, shape (k,)
            ``h_Z(d)``; ``-inf`` when Z is empty, ``+inf`` along unbounded directions. With
            ``certified``, an upper bound on it that holds in floating point.
        points : ndarray, shape (k, n)
            A maximizer per direction (NaN where the value is infinite).

        Raises
        ------
        SolverError
            When no fallback settles a program, or (``certified``) no sound finite bound exists.
        """
        solved = self._solve(D, certified is True, True)
        (values, points, _, _), bounds = self._verified(D, solved, certified is True)
        if certified is False or bounds is None:
            return values, points
        return bounds, points

    def support_and_bounds(self, D: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """The solver's support values (as ``support(D)``) and, from the same solves, their
        certified bounds (as ``support(D, certified=None)`` where a sound bound exists), or None
        for the bounds when there is none."""
        (values, _, _, _), bounds = self._verified(D, self._solve(D, False, True), False)
        return values, bounds

    def _verified(self, D: np.ndarray, solved: tuple, must_certify: bool):
        """The a-posteriori check of every value of ``solved`` = (values, points, factors,
        multipliers) from `_solve`: returns the checked quadruple and the certified bounds (or None).

        The certified bound U (weak duality, any λ) and the solver's value L (of a point feasible to
        the solver's tolerance) bracket the exact support, so U − L bounds the error of both. Where
        it exceeds ``SUPPORT_GAP_TOL`` of the set's width along d (`_gap_tolerance`), the direction
        is solved again by the simplex method (`FactorConstraints.maximize` with ``escalate``),
        and the better answer kept: the smaller U (both are bounds) and the solution of the tighter
        bracket. A value is never returned above its bound. Without a sound bound (free factors
        neither determined nor cancelled exactly) the solver's values are returned unchecked.
        """
        values, points, xis, lams = solved
        try:
            bounds, stored, own = self._certify(D, values, lams)
        except SolverError as err:
            if must_certify or err.status != "UncertifiableReducedCost":
                raise
            return solved, None
        finite = np.isfinite(values) & np.isfinite(bounds)
        # The rounding charges (`setsmooth.sets.rounding`) are part of every bound; the bracket
        # checks the solver on the stored program (``stored``: its bounds), so it leaves them out.
        with np.errstate(invalid="ignore"):
            loose = finite & ~(np.abs(stored - values) <= self._gap_tolerance(D, values, stored, own))
        rows = np.flatnonzero(loose)
        if rows.size:
            values, points, xis, lams, bounds = (a.copy() for a in (values, points, xis, lams,
                                                                    bounds))
            try:
                v2, p2, x2, l2 = self._solve(D[rows], must_certify, True, escalate=True)
            except SolverError:
                # Escalation only tries to tighten a bracket that already holds a sound bound: its
                # failure keeps the first answer (capped by its bound below) instead of raising.
                v2 = np.full(rows.size, np.nan)
                p2 = x2 = l2 = None
            ok = np.isfinite(v2)
            b2 = None
            if ok.any():
                try:
                    b2, s2, _ = self._certify(D[rows][ok], v2[ok], l2[ok])
                except SolverError as err:
                    if err.status != "UncertifiableReducedCost":
                        raise
            if b2 is not None:
                r = rows[ok]
                # The brackets on the stored program (an inverted one too) decide which answer is
                # kept; the bound is the smaller of the two either way.
                better = (s2 - v2[ok]) < np.abs(stored[r] - values[r])
                take = r[better]
                values[take], points[take] = v2[ok][better], p2[ok][better]
                xis[take], lams[take] = x2[ok][better], l2[ok][better]
                bounds[r] = np.minimum(bounds[r], b2)
        values = np.where(finite, np.minimum(values, bounds), values)
        return (values, points, xis, lams), bounds

    @staticmethod
    def _gap_tolerance(D: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                       rounding: np.ndarray | None = None) -> np.ndarray:
        """``SUPPORT_GAP_TOL`` times the width of the set along each row d of ``D`` (lower bound
        L(d) + L(−d) when −d is a row too; else the magnitude |L| + |U|), plus the rounding floor:
        four times the certificate's own rounding allowance (``rounding``, from `certified_bound`)
        and ``SUPPORT_GAP_FLOOR``·(|L| + |U|) for the rounding of L itself.

        The floor used to be 2⁻⁴⁰·(|L| + |U|) whatever the certificate's actual rounding: at states
        1.9e6 that let an interior-point answer 3e-6 from the optimum pass (2.1e-6 of the hull's
        width; reliability case 168 at offset 1e6) where the certificate's rounding was 2.8e-9."""
        magnitude = np.abs(lower) + np.abs(upper)
        scale = magnitude.copy()
        rows = {(row + 0.0).tobytes(): i for i, row in enumerate(D)}  # + 0.0: −0.0 reads as 0.0
        for i, row in enumerate(D):
            j = rows.get((-row + 0.0).tobytes())
            if j is not None:
                scale[i] = max(lower[i] + lower[j], 0.0)
        floor = tol.SUPPORT_GAP_FLOOR * magnitude
        if rounding is not None:
            floor = floor + 4.0 * rounding
        return tol.SUPPORT_GAP_TOL * scale + floor

    def solutions(self, D: np.ndarray) -> list[SupportSolution]:
        """`SupportSolution` (value, point, factors, multipliers) for every row of ``D``, each
        value checked against its certified bound like `support`'s."""
        (values, points, xis, lams), _ = self._verified(D, self._solve(D, False, True), False)
        return [SupportSolution(float(v), p, x, m) for v, p, x, m in zip(values, points, xis, lams)]

    def _solve(self, D: np.ndarray, certified: bool = False, tight: bool = False,
               escalate: bool = False):
        k, n = D.shape
        values = np.full(k, np.inf)
        points = np.full((k, n), np.nan)
        xis = np.full((k, self.ng), np.nan)
        lams = np.full((k, self.nc), np.nan)
        self.last_solve_time = 0.0
        if self.factors._empty:
            return np.full(k, -np.inf), points, xis, lams
        GtD = np.asarray((self.G.T @ D.T).T)  # (k, ng): objective of each direction
        magnitude = [None] * k
        if self.factors.free.size:  # rounding level of GtD: noise below it is an exact zero
            absG = abs(self.G) if sp.issparse(self.G) else np.abs(self.G)
            magnitude = np.asarray((absG.T @ np.abs(D).T).T) * (1 + self.G.shape[0])
        context = "computing a support function of a constrained zonotope"
        # `_verified` brackets every answer by a certified bound where one exists and escalates the
        # loose ones: a rough answer goes straight to the simplex method then.
        bracketed = not escalate and (self.factors.free.size == 0
                                      or self.factors.free_bound() is not None)
        start = time.perf_counter()
        if not escalate:
            # The simplex method's answers depend on this call alone (`warm_simplex`); the
            # escalation of its loose brackets (`_verified`) belongs to the same call and batch.
            new_batch()
        try:
            for i in range(k):
                res = self.factors.maximize(GtD[i], context, magnitude=magnitude[i],
                                            unverified=certified, tight=tight,
                                            escalate=escalate, bracketed=bracketed)
                if res.status == "infeasible":
                    return np.full(k, -np.inf), points, xis, lams
                if res.status == "unbounded":
                    continue
                xis[i], lams[i] = res.xi, res.lam
        finally:
            self.last_solve_time = time.perf_counter() - start
        solved = ~np.isnan(xis[:, 0]) if self.ng else np.ones(k, dtype=bool)
        xi = xis[solved]
        points[solved] = np.asarray((self.G @ xi.T).T) + self.c
        values[solved] = D[solved] @ self.c + np.einsum("ij,ij->i", GtD[solved], xi)
        return values, points, xis, lams

    def _certify(self, D: np.ndarray, values: np.ndarray, lams: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Replace the finite values by their floating-point weak-duality bounds; also returns the
        bounds of the stored set alone, without the rounding charges (`setsmooth.sets.rounding`),
        and the part of those that covers the certificate's own rounding."""
        rows = np.flatnonzero(np.isfinite(values))
        if rows.size == 0:
            return values, values, np.zeros(values.shape)
        lam = lams[rows]
        free = self.factors.free
        bound = 0.0
        if free.size:
            AF, AFt, _ = self.factors.certificate_operators()
            GF = self.__dict__.get("_G_free")
            if GF is None:
                GF = self.__dict__["_G_free"] = (sp.csr_matrix(self.G[:, free].T)
                                                 if sp.issparse(self.G) else self.G[:, free])
            gF = np.asarray((GF @ D[rows].T).T) if sp.issparse(self.G) else D[rows] @ GF
            solve_normal = cached_instance(self.factors, "normal equations of the free factors",
                                           lambda: normal_solver(AF))
            corrected = correct_multipliers(AF, gF, lam, solve_normal, AFt)
            bound = self.factors.free_bound()
            if bound is None:
                # Only exact cancellation certifies then; the solver's λ may have it (small
                # integer data) where the least-squares correction perturbs it by rounding.
                try:
                    return self._bound(D, values, rows, lam, None)
                except SolverError:
                    pass
            lam = corrected
        return self._bound(D, values, rows, lam, bound)

    def _bound(self, D, values, rows, lam, bound):
        if self._ops is None:
            self._ops = Operators(self.G, self.A, self.factors.certificate_operators()[2])
        out, stored, own = values.copy(), values.copy(), np.zeros(values.shape)
        out[rows], stored[rows], own[rows] = certified_bound(D[rows], self.G, self.c, self.A, self.b, self.h,
                                                   lam, bound, self._ops, pad=self.pad,
                                                   slack=self.factors.slack, pad_free=self.pad_free,
                                                   slack_free=self.factors.slack_free,
                                                   with_charge=True)
        return out, stored, own

    def _free_units(self, pre) -> np.ndarray:
        """Column units of the presolved program's factors for the membership program: 1 on bounded
        factors (|η_B| ≤ 1), and β / s_j on free ones, β ≥ ‖ξ_F‖∞ the factor set's rigorous bound
        (`FactorConstraints.free_bound`, when known or cheap), so every factor of the program is
        O(1) in the set's own metric.

        The presolve gives a free factor the units of its tightest row. On a thin set (a state
        pinned to 1e-6 by a measurement of noise 1e-6, the others only by a prior box of size 5)
        that put the free factors at |η_F| ~ 1e7, and Clarabel returned 'optimal' with distance 0.93
        (in the set's units) for a member; in units of β it returns the margin itself.
        """
        units = np.ones(pre.A.shape[1])
        if pre.bounded.all():
            return units
        beta = self.factors._cheap_free_bound()
        if beta is not None and np.isfinite(beta) and beta > 0:
            free = ~pre.bounded
            units[free] = beta / pre.col_scale[free]
        return units

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether some ξ with Aξ = b, |ξ| ≤ h has ‖Gξ + c − p‖∞ ≤ margin.

        Decided by the distance program min{t : |Gξ + c − p| ≤ t, t ≥ margin, Aξ = b, |ξ| ≤ h},
        which is feasible whenever Z is and bounded below, rather than by the feasibility of
        ``t = margin``: an interior-point method certifies infeasibility less reliably
        (AlmostPrimalInfeasible) than it solves. The explicit row t ≥ margin matters: without it a
        member (distance 0) leaves no slack and Clarabel often stops at AlmostSolved. The optimum is
        compared with ``margin`` up to the solver's accuracy on the program's data (the point, the
        centre and the set's extent).
        """
        context = "deciding membership in a constrained zonotope"
        pre = self.factors.presolved
        if pre.empty:
            return False
        M, rhs, _ = self.factors._program(pre)  # the presolved factor set: rows Âη = b̂, |η_B| ≤ 1
        m, nvar = pre.A.shape[0], pre.A.shape[1]
        units = self._free_units(pre)
        M = sp.csc_matrix(M @ sp.diags(units))
        G = self.G[:, pre.cols]
        scale = pre.col_scale * units
        G = sp.csc_matrix(G @ sp.diags(scale)) if sp.issparse(G) else G * scale
        # The program's η is the deviation from the presolve's nominal point (`Presolved.shift`).
        centre = self.c if pre.shift is None else self.c + np.asarray(
            self.G[:, pre.cols] @ (pre.shift * pre.col_scale)).reshape(-1)
        n = G.shape[0]
        ones = sp.csc_matrix(np.ones((n, 1)))
        t_row = sp.csc_matrix(([-1.0], ([0], [nvar])), shape=(1, nvar + 1))
        # Equalities first (Âη = b̂), then the bound rows, ±(Gη + c − p) ≤ t and −t ≤ −margin.
        rows = sp.vstack([sp.hstack([M, sp.csc_matrix((M.shape[0], 1))]),
                          sp.hstack([G, -ones]), sp.hstack([-G, -ones]), t_row], format="csc")
        r = np.concatenate([rhs, p - centre, centre - p, [-margin]])
        q = np.zeros(nvar + 1)
        q[-1] = 1.0
        # With iterative refinement: without it, 2 in 1,500 members of random CZs with free factors
        # came out as non-members or AlmostSolved (t* a few 1e-9 above the margin).
        try:
            sol = solve_lp(q, rows, r, m, rows.shape[0] - m, context, refine=True, kind="membership")
            status, t = sol.status, float(sol.x[-1])
        except SolverError:
            status, t = "stalled", np.nan
        if status not in ("optimal", "infeasible"):
            # The simplex method settles what the interior-point method could not.
            from scipy.optimize import linprog

            bounds = [(None, None)] * (nvar + 1)
            res = linprog(q, A_ub=rows[m:], b_ub=r[m:], A_eq=rows[:m] if m else None,
                          b_eq=r[:m] if m else None, bounds=bounds, method="highs")
            # SciPy reports HiGHS's refusal of the data (entries beyond 1e15: "Model error") with
            # the infeasible status too; only a verdict of infeasibility means empty.
            if res.status == 2 and "infeasible" in res.message.lower():
                status = "infeasible"
            elif res.status == 0:
                status, t = "optimal", float(res.x[-1])
            else:
                raise SolverError(_ALMOST_SOLVED if status == "inaccurate" else "NumericalError",
                                  context, kind="membership")
        if status == "infeasible":
            return False
        # The optimum is accurate to the solver's tolerance relative to the data of its rows, which
        # include the set's extent |G|·1 (η in the unit box): a blown-up set (generators ~1e15, as a
        # reduced filter with few outputs can produce) cannot resolve distances below that, and
        # calling a member a non-member there would be a silent wrong answer.
        extent = abs(G).sum(axis=1).max() if sp.issparse(G) else np.abs(G).sum(axis=1).max(initial=0.0)
        scale = max(np.abs(p).max(initial=0.0), np.abs(self.c).max(initial=0.0), float(extent))
        return bool(t <= margin + tol.scaled(tol.SOLVER_TOL, scale))
