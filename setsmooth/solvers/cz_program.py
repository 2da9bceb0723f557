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
from .clarabel_lp import SolverError
from .cz_membership import contains
from .factor_set import FactorConstraints
from .instances import cached_instance
from .presolved import CompiledProduct
from .warm_simplex import Batch

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
        partner = _partners(D)  # for both the tolerance and the thin-set guarantee below
        # The rounding charges (`setsmooth.sets.rounding`) are part of every bound; the bracket
        # checks the solver on the stored program (``stored``: its bounds), so it leaves them out.
        with np.errstate(invalid="ignore"):
            loose = finite & ~(np.abs(stored - values)
                               <= self._gap_tolerance(D, values, stored, own, partner))
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
        thin = finite & self._below_guarantee(D, values, partner)
        values = np.where(thin, bounds, values)
        return (values, points, xis, lams), bounds

    @staticmethod
    def _below_guarantee(D: np.ndarray, values: np.ndarray,
                         partner: np.ndarray | None = None) -> np.ndarray:
        """The rows d of ``D`` along which the set is thinner than the plain values' guarantee:
        −d is a row too and the width h(d) + h(−d) is below ``GUARANTEED_WIDTH_RATIO``·(|h(d)| +
        |h(−d)|). There the floor of the bracket, not 1e-7 of the width, bounds a plain value's
        error, so the certified bound is returned in its place (docs/numerical_core.md).
        ``partner``: `_partners` of D, when the caller has it."""
        if partner is None:
            partner = _partners(D)
        paired = partner >= 0
        other = values[np.where(paired, partner, 0)]
        with np.errstate(invalid="ignore"):
            width = values + other
            return paired & (width < tol.GUARANTEED_WIDTH_RATIO * (np.abs(values) + np.abs(other)))

    @staticmethod
    def _gap_tolerance(D: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                       rounding: np.ndarray | None = None,
                       partner: np.ndarray | None = None) -> np.ndarray:
        """``SUPPORT_GAP_TOL`` times the width of the set along each row d of ``D`` (lower bound
        L(d) + L(−d) when −d is a row too; else the magnitude |L| + |U|), plus the rounding floor:
        four times the certificate's own rounding allowance (``rounding``, from `certified_bound`)
        and ``SUPPORT_GAP_FLOOR``·(|L| + |U|) for the rounding of L itself. A floor tied to the
        certificate's actual rounding, not to the magnitude alone, keeps a state far from the
        origin from hiding a loose answer (docs/numerical_core.md). ``partner``: `_partners` of D,
        when the caller has it."""
        magnitude = np.abs(lower) + np.abs(upper)
        scale = magnitude.copy()
        if partner is None:
            partner = _partners(D)
        paired = partner >= 0
        scale[paired] = np.maximum(lower[paired] + lower[partner[paired]], 0.0)
        floor = tol.SUPPORT_GAP_FLOOR * magnitude
        if rounding is not None:
            floor = floor + 4.0 * rounding
        return tol.SUPPORT_GAP_TOL * scale + floor

    def support_points_and_bounds(self, D: np.ndarray
                                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """`support_and_bounds` with the maximizers: (values, points, bounds or None), one set of
        solves; every value is checked against its bound as in `support`."""
        (values, points, _, _), bounds = self._verified(D, self._solve(D, False, True), False)
        return values, points, bounds

    def solutions(self, D: np.ndarray) -> list[SupportSolution]:
        """`SupportSolution` (value, point, factors, multipliers) for every row of ``D``, each
        value checked against its certified bound like `support`'s."""
        (values, points, xis, lams), _ = self._verified(D, self._solve(D, False, True), False)
        return [SupportSolution(float(v), p, x, m) for v, p, x, m in zip(values, points, xis, lams)]

    def _solve(self, D: np.ndarray, certified: bool = False, tight: bool = False,
               escalate: bool = False):
        self.last_solve_time = 0.0
        if self.factors._empty:
            return self._collected(D, None)
        GtD, magnitude, purpose = self._objectives(D, escalate)
        batch = Batch(GtD)  # the simplex method's answers depend on this call alone (`warm_simplex`)
        xis = np.full((D.shape[0], self.ng), np.nan)
        lams = np.full((D.shape[0], self.nc), np.nan)
        start = time.perf_counter()
        try:
            for i in range(D.shape[0]):
                if not self._maximize(GtD[i], magnitude[i], certified, tight, purpose, batch, xis[i],
                                      lams[i]):
                    return self._collected(D, None)
        finally:
            self.last_solve_time = time.perf_counter() - start
        return self._collected(D, GtD, xis, lams)

    def _objectives(self, D: np.ndarray, escalate: bool = False) -> tuple[np.ndarray, list, str]:
        """The objectives Gᵀd of the rows d of ``D`` (k, ng), their rounding magnitudes (None each
        without free factors) and the policy's purpose (`policy.policy`)."""
        k = D.shape[0]
        GtD = np.asarray((self._transposed() @ D.T).T)  # (k, ng): objective of each direction
        magnitude = [None] * k
        if self.factors.free.size:  # rounding level of GtD: noise below it is an exact zero
            magnitude = np.asarray((self._transposed(True) @ np.abs(D).T).T) * (1 + self.G.shape[0])
        # `_verified` brackets every answer by a certified bound where one exists and escalates the
        # loose ones: a rough answer goes straight to the simplex method then.
        bracketed = self.factors.free.size == 0 or self.factors.free_bound() is not None
        return GtD, magnitude, "escalated" if escalate else "bracketed" if bracketed else "plain"

    def _transposed(self, absolute: bool = False):
        """Gᵀ (|G|ᵀ) for products bit for bit ``G.T @ X`` (``abs(G).T @ X``): scipy's kernels on G's
        arrays when sparse (`presolved.CompiledProduct`), a transposed view when dense."""
        if sp.issparse(self.G):
            return CompiledProduct(self.G, transpose=True, absolute=absolute)
        return (np.abs(self.G) if absolute else self.G).T

    def _maximize(self, g: np.ndarray, magnitude, certified: bool, tight: bool, purpose: str,
                  batch: object, xi: np.ndarray, lam: np.ndarray) -> bool:
        """One objective: its factors and multipliers written into ``xi`` and ``lam`` (left NaN
        when unbounded); False when the factor set is infeasible."""
        res = self.factors.maximize(g, "computing a support function of a constrained zonotope",
                                    magnitude=magnitude, unverified=certified, tight=tight,
                                    purpose=purpose, batch=batch)
        if res.status == "infeasible":
            return False
        if res.status != "unbounded":
            xi[:], lam[:] = res.xi, res.lam
        return True

    def _collected(self, D: np.ndarray, GtD: np.ndarray | None, xis: np.ndarray | None = None,
                   lams: np.ndarray | None = None):
        """(values, points, factors, multipliers) of the rows of ``D`` from their factors (NaN rows:
        unbounded, value inf); GtD None: the set is empty (values −inf)."""
        k, n = D.shape
        points = np.full((k, n), np.nan)
        if GtD is None:
            return (np.full(k, -np.inf), points, np.full((k, self.ng), np.nan),
                    np.full((k, self.nc), np.nan))
        values = np.full(k, np.inf)
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
            gF = self._free_objectives(D[rows], free)
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

    def _free_objectives(self, D: np.ndarray, free: np.ndarray) -> np.ndarray:
        """g_F = (Gᵀd)_F for the rows d of ``D``: for a sparse G the free entries of the product
        with all of Gᵀ (each the same sum as with Gᵀ's free rows alone), for a dense one D G_F."""
        if sp.issparse(self.G):
            return np.asarray((self._transposed() @ D.T).T)[:, free]
        GF = self.__dict__.get("_G_free")
        if GF is None:
            GF = self.__dict__["_G_free"] = self.G[:, free]
        return D @ GF

    def _bound(self, D, values, rows, lam, bound):
        if self._ops is None:
            self._ops = Operators(self.G, self.A, self.factors.certificate_part())
        out, stored, own = values.copy(), values.copy(), np.zeros(values.shape)
        out[rows], stored[rows], own[rows] = certified_bound(D[rows], self.G, self.c, self.A, self.b, self.h,
                                                   lam, bound, self._ops, pad=self.pad,
                                                   slack=self.factors.slack, pad_free=self.pad_free,
                                                   slack_free=self.factors.slack_free,
                                                   with_charge=True)
        return out, stored, own

    def contains(self, p: np.ndarray, margin: float) -> bool:
        """Whether some ξ with Aξ = b, |ξ| ≤ h has ‖Gξ + c − p‖∞ ≤ margin
        (`cz_membership.contains`)."""
        return contains(self, p, margin)


def _partners(D: np.ndarray) -> np.ndarray:
    """For every row d of ``D`` the index of the row −d, or −1 when there is none."""
    rows = {(row + 0.0).tobytes(): i for i, row in enumerate(D)}  # + 0.0: −0.0 reads as 0.0
    return np.array([rows.get((-row + 0.0).tobytes(), -1) for row in D], dtype=int)
