"""The fast path's factor set {ξ : Aξ = b, |ξ| ≤ h}: presolved, solved, emptiness and recession.

The fast path for constrained zonotopes Z(G, c, A, b, h) substitutes ``x = Gξ + c`` out, so every query
is a linear program over the factor set. `FactorConstraints` owns that set: it presolves it once
(`presolve`: fixed factors and zero rows dropped, bounds scaled out, rows and free factors
equilibrated, dependent rows dropped for small programs) and maximizes objectives over it, one LP per
objective on a Clarabel instance that only has its objective replaced. The instance lives in the
per-thread, bounded cache of `instances.cached_instance`, never on the object, so a factor set can be
queried from several threads and pickled.

Status policy (`maximize`): 'Solved' is taken; any other status is settled by a verified fallback
before anything is raised: a fresh solve with iterative refinement, then, if the presolve had not looked
for dependent rows, the fully presolved program (when it dropped some), and last HiGHS's simplex
method on it (warm-started across objectives, `presolve.simplex`). A reduced-accuracy answer
('AlmostSolved', and every simplex answer) is used only after an independent check in the presolved
units: the primal point's residual and bound overshoot and its gap to the always-valid weak-duality
bound, within ``SOLVER_CHECK_TOL`` of the scale; one with a gap above ``ACCURATE_GAP_TOL`` is kept
while the later fallbacks look for a tighter one (a caller that brackets the answer itself,
``bracketed``, skips the refined re-solve). Infeasible statuses are settled by the emptiness verdict
below; unbounded ones, and solutions whose multipliers do not cancel the objective on free factors,
by a recession program.

Emptiness (`is_empty`): a feasibility solve on the kept instance whose point satisfies the rows to
``EMPTINESS_TOL`` proves non-emptiness (the common case, at the cost of one re-solve); anything else
is decided by an elastic phase-one program, min{t : |Âη − b̂| ≤ t, |η_B| ≤ 1}, which is feasible and
bounded whatever the data, so an interior-point method settles it even on flat or nearly empty sets;
the set is empty iff t* > ``EMPTINESS_TOL`` in the equilibrated units (every presolved row has unit
∞-norm and every bounded factor unit bound). A support LP that reports infeasibility on a set this
program calls non-empty is solved on the set relaxed by t* (``|Âη − b̂| ≤ t* + EMPTINESS_TOL``), an
outer value, so the two verdicts never contradict each other. Such a set's rows are inconsistent by
rounding: where the warm simplex method has also run out of time on them, the later bracketed and
escalated directions of the same support call (`CZProgram`'s batch) go to the relaxed program
directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import clarabel
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from . import clarabel_lp
from .clarabel_lp import SolverError, _csc, _index_type, _zero_cost, solve_lp
from .instances import cached_instance
from .interior_point import interior_point
from .presolve import (Presolved, presolve, project_free, simplex, simplex_box_equalities,
                       simplex_cold, simplex_inequalities, simplex_timed_out)
from .warm_simplex import current_batch

__all__ = ["FactorConstraints", "Maximized", "STACK_MAX_VARIABLES", "DENSE_PRESOLVE_MAX"]


#: The recession programs that decide unbounded directions stack their objectives into one LP while
#: it has at most this many variables, and go one objective at a time beyond.
STACK_MAX_VARIABLES = 3000

_INFEASIBLE = ("PrimalInfeasible", "AlmostPrimalInfeasible")
_UNBOUNDED = ("DualInfeasible", "AlmostDualInfeasible")

#: Objective entries below NOISE_FACTOR·eps·(|G|ᵀ|d|)_j are the rounding noise of an exact zero
#: (a direction orthogonal to the free factors' lineality, computed in floating point).
NOISE_FACTOR = 64

#: A part of a joined factor set (`FactorConstraints.joined`) with at most this many free factors has
#: its dense free-factor bound computed when the parts are joined.
CHEAP_FREE_BOUND_MAX = 60

#: The solves of a direction the caller brackets (`FactorConstraints.maximize`, ``bracketed``) on a
#: program whose factors are all bounded, in order: 'simplex' the warm-started simplex method, False
#: the kept interior-point instance. ``benchmarks/bench_bracketed_order.py`` measures this order
#: against the reverse one.
BRACKETED_ATTEMPTS: tuple = ("simplex", False)

#: The solves of a bracketed direction on a program whose factors are all bounded once the
#: warm-started simplex method has run out of time on it (`presolve.rung_seconds`) in the current
#: batch of queries (one support call, `warm_simplex.new_batch`): HiGHS's interior-point method
#: without crossover first ('cold interior'), then as `BRACKETED_ATTEMPTS`. On the recursion
#: smoother's flat sets (non-square D with fewer noise components than outputs, reliability case
#: 029) the rows are inconsistent by rounding (phase-one residual 4e-10 at k = 0, 5,371 rows,
#: 7,672 factors): the warm primal simplex method took 5-12 ms an iteration and ran into its
#: 76 s limit on several directions of one hull (505 s of solves; 271 s with this order), where
#: the interior-point method reports the rows infeasible in 0.4 s and the phase-one verdict sends
#: the direction to the relaxed program (`_relaxed`).
AFTER_TIME_OUT_ATTEMPTS: tuple = ("cold interior", "simplex", False)

#: The same on a program with free factors (the states of trajectory sets and posterior views):
#: the interior-point method first. The simplex method's multipliers leave up to its dual
#: feasibility tolerance on the free factors, which a certificate multiplies by the free factors'
#: bound: with the simplex method first, the certified filter hulls of reliability case 069 (CZ
#: noises, non-square D) were up to 6e-5 of the width wider than the exact ones in every regime.
BRACKETED_ATTEMPTS_FREE: tuple = (False, "simplex")

#: Linearly dependent rows are looked for up front (dense rank-revealing QR) when nc·ng is at most
#: this; larger (sparse, trajectory-sized) programs look for them only after a failed solve.
DENSE_PRESOLVE_MAX = 5_000


@dataclass(frozen=True)
class Maximized:
    """One objective maximized over the factor set.

    Attributes
    ----------
    status : str
        'optimal' (Solved, or a reduced-accuracy answer that passed the independent check),
        'infeasible' (the factor set is empty), 'unbounded', 'relaxed' (the factor set is non-empty
        by the phase-one verdict but its support LP is infeasible: solved on the set relaxed by the
        phase-one residual, an outer value) or 'unverified' (only on request: no attempt settled the
        program; ``lam`` is still good for a weak-duality certificate).
    xi : ndarray, shape (ng,)
        The maximizer (original factors), NaN unless solved.
    lam : ndarray, shape (nc,)
        Multipliers of Aξ = b for the original rows (zero on dropped rows), NaN unless solved.
    """

    status: str
    xi: np.ndarray
    lam: np.ndarray


class FactorConstraints:
    """The factor set {ξ : Aξ = b, -h ≤ ξ ≤ h} of a constrained zonotope, presolved for Clarabel.

    It depends on (A, b, h) only, so every linear map, translation and projection of a CZ shares one
    instance, and with it the presolve, the emptiness verdict and the Clarabel instance (kept per
    thread by `instances.cached_instance`).
    """

    #: The batch of queries (`warm_simplex.current_batch`, one `CZProgram` support call with its
    #: escalation) in which a support LP on the exact rows was reported infeasible after the warm
    #: simplex method had run out of time on them, and the relaxed program answered (`_relaxed`):
    #: the stored rows are inconsistent by rounding and costly to solve, and the batch's later
    #: bracketed and escalated directions go to the relaxed program directly. (A class default, so
    #: that factor sets pickled before it existed still load.)
    _relaxed_batch: int | None = None

    def __init__(self, A, b: np.ndarray, h: np.ndarray, slack: np.ndarray | None = None,
                 slack_free: np.ndarray | None = None):
        self.A = _csc(A)  # canonical (sorted, unique row indices): the presolve scales its arrays
        self.b = np.asarray(b, dtype=float)
        self.h = np.asarray(h, dtype=float)
        #: Rounding slack of the rows (`setsmooth.sets.rounding`): the certificates hold for the
        #: relaxed set {ξ : |Aξ − b| ≤ slack, |ξ| ≤ h}; None when the rows are exact.
        self.slack = None if slack is None or not np.any(slack) else np.asarray(slack, dtype=float)
        #: The rows' slack per unit of ‖ξ_F‖∞ (rounded free columns): |Aξ − b| ≤ slack +
        #: slack_free·‖ξ_F‖∞ on the relaxed set. None when no free column was rounded.
        self.slack_free = (None if slack_free is None or not np.any(slack_free)
                           else np.asarray(slack_free, dtype=float))
        self.ng = self.A.shape[1]
        self.nc = self.A.shape[0]
        self.finite = np.flatnonzero(np.isfinite(self.h))
        self.free = np.flatnonzero(~np.isfinite(self.h))
        self._empty: bool | None = None
        self._phase_one: float | None = None
        self._pre: Presolved | None = None
        self._pre_full: Presolved | None = None
        self._free_bound: tuple[float | None] | None = None

    def __getstate__(self) -> dict:
        # A batch id means nothing in another process (each counts its own from 1): a copy sent to
        # a process pool must not take the relaxed shortcut of a batch it was never in.
        return {k: v for k, v in self.__dict__.items() if k != "_relaxed_batch"}

    @property
    def _nan(self) -> tuple[np.ndarray, np.ndarray]:
        """(ξ, λ) filled with NaN: the factors and multipliers of an infinite value (read-only)."""
        nan = self.__dict__.get("_nan_cache")
        if nan is None:
            nan = (np.full(self.ng, np.nan), np.full(self.nc, np.nan))
            for a in nan:
                a.flags.writeable = False
            self.__dict__["_nan_cache"] = nan
        return nan

    # -- presolve ----------------------------------------------------------------------------------
    @property
    def presolved(self) -> Presolved:
        """The presolved program (dependent rows dropped only for small programs)."""
        if self._pre is None:
            small = self.nc * self.ng <= DENSE_PRESOLVE_MAX
            self._pre = presolve(self.A, self.b, self.h, dependent=small)
            if small:
                self._pre_full = self._pre
        return self._pre

    @property
    def fully_presolved(self) -> Presolved:
        """The presolved program with dependent rows dropped whatever its size (fallback)."""
        if self._pre_full is None:
            self._pre_full = presolve(self.A, self.b, self.h, dependent=True)
        return self._pre_full

    @classmethod
    def joined(cls, A, b: np.ndarray, h: np.ndarray, parts: list["FactorConstraints | None"],
               slack: np.ndarray | None = None, slack_free: np.ndarray | None = None
               ) -> "FactorConstraints | None":
        """The factor set of a CZ whose factors are those of ``parts`` side by side, with more rows.

        Minkowski sums, Cartesian products and generalized intersections of CZs concatenate their
        operands' factors and add rows: every factor vector of the result restricts, on each part's
        columns, to a factor vector of that part. So the parts' free-factor bounds β_i ≥ ‖ξ_F,i‖∞
        bound the result's: β = max_i β_i, with no eigenvalue problem on the (larger) result. That
        keeps certified supports available where the result has more free factors than the dense
        bound accepts (the recursion smoother on the filter's trajectory views). A part's bound is
        used only when already known or cheap (no free factors, a structured factor set, or a small
        one); otherwise the result's own bound is computed when first needed, as before. With
        ``slack`` (the rows' rounding charge, the parts' own slacks among them) each part's bound,
        computed for its relaxed set, holds on the restriction of the relaxed result.

        Returns None (the CZ builds its factor set lazily) when no part has free factors.
        """
        if not any(p is not None and p.free.size for p in parts):
            return None
        joined = cls(A, b, h, slack, slack_free)
        betas = [p._cheap_free_bound() for p in parts]
        if all(beta is not None for beta in betas):
            joined._free_bound = (max(betas, default=0.0),)
        return joined

    def _cheap_free_bound(self) -> float | None:
        """`free_bound` when it is known or cheap to compute (see `joined`), else None."""
        if self.free.size == 0:
            return 0.0
        if self._free_bound is not None or type(self).free_bound is not FactorConstraints.free_bound \
                or self.free.size <= CHEAP_FREE_BOUND_MAX:
            return self.free_bound()
        return None

    def _fully_presolved_if_new(self, first: Presolved) -> Presolved | None:
        """`fully_presolved` when it differs from ``first`` (dependent rows dropped, or found
        empty), else None: an interior-point solve of it would repeat one of ``first``."""
        pre = self.fully_presolved
        return None if pre.rows.size == first.rows.size and not pre.empty else pre

    def free_bound(self) -> float | None:
        """β ≥ ‖ξ_F‖∞ on the free factors (`certify.free_factor_bound`; cached), or None."""
        if self._free_bound is None:
            from .certify import free_factor_bound

            self._free_bound = (free_factor_bound(self.A, self.b, self.h, slack=self.slack,
                                                  slack_free=self.slack_free),)
        return self._free_bound[0]

    def certificate_operators(self) -> tuple[sp.csc_matrix, sp.csr_matrix, tuple]:
        """(A_F, A_Fᵀ, `certify.Operators.factor_part`): the factor set's part of a certificate,
        prepared once and shared by every CZ over this factor set (the projections of one
        trajectory set each certify against the same A)."""
        ops = self.__dict__.get("_certificate_ops")
        if ops is None:
            from .certify import Operators

            AF = sp.csc_matrix(self.A[:, self.free])
            ops = self.__dict__["_certificate_ops"] = (AF, sp.csr_matrix(AF.T),
                                                       Operators.factor_part(self.A))
        return ops

    # -- solving -----------------------------------------------------------------------------------
    def _program(self, pre: Presolved) -> tuple[sp.csc_matrix, np.ndarray, list]:
        """Rows [Â; I_B; −I_B], right-hand sides [b̂; 1; 1] and cones of the presolved program."""
        m, p = pre.A.shape
        bcols = np.flatnonzero(pre.bounded)
        nb = bcols.size
        # Assembled from index arrays, column by column (Â[:, j], then +1 in row m + i and −1 in row
        # m + nb + i when j is the i-th bounded factor): scipy's vstack costs more than a small solve.
        A = pre.A
        a_count = np.diff(A.indptr)
        col_nnz = a_count + 2 * pre.bounded
        indptr = np.zeros(p + 1, dtype=np.int64)
        np.cumsum(col_nnz, out=indptr[1:])
        a_dest = np.arange(A.nnz) + np.repeat(indptr[:-1] - A.indptr[:-1], a_count)
        upper = indptr[1:][bcols] - 2
        rows = np.empty(int(indptr[-1]), dtype=np.int64)
        data = np.empty(int(indptr[-1]))
        rows[a_dest], data[a_dest] = A.indices, A.data
        rows[upper], data[upper] = m + np.arange(nb), 1.0
        rows[upper + 1], data[upper + 1] = m + nb + np.arange(nb), -1.0
        itype = _index_type(max(int(indptr[-1]), m + 2 * nb))
        M = sp.csc_matrix((data, rows.astype(itype), indptr.astype(itype)), shape=(m + 2 * nb, p))
        rhs = np.concatenate([pre.b, np.ones(2 * nb)])
        cones = ([clarabel.ZeroConeT(m)] if m else []) + ([clarabel.NonnegativeConeT(2 * nb)]
                                                          if nb else [])
        return M, rhs, cones

    def _instance(self, pre: Presolved):
        """This thread's Clarabel instance of the presolved program (objective replaced per solve)."""
        def build():
            M, rhs, cones = self._program(pre)
            p = pre.A.shape[1]
            return clarabel.DefaultSolver(_zero_cost(p), np.zeros(p), M, rhs, cones,
                                          clarabel_lp.settings())
        return cached_instance(self, ("maximize", id(pre)), build)

    def _solve_on(self, pre: Presolved, q: np.ndarray, refine: bool | str):
        """Minimize qᵀη over the presolved program: (status name, η, ẑ of the rows).

        ``refine``: False on the kept instance, True on a fresh one with iterative refinement,
        'simplex' by HiGHS's simplex (`presolve.simplex`, warm-started; 'cold simplex':
        `presolve.simplex_cold`), the last resort on LPs where the interior-point method stops at
        reduced accuracy, and 'cold interior' HiGHS's interior-point method without crossover
        (`interior_point.interior_point`) after every other; their optima are reported as
        'AlmostSolved' so that they go through the same independent check as any answer not
        certified by Clarabel.
        """
        if refine == "simplex":
            return simplex(pre, q)
        if refine == "cold simplex":
            return simplex_cold(pre, q)
        if refine == "cold interior":
            return interior_point(pre, q)
        if refine:  # a fresh instance: the fallback must not inherit the kept one's state
            M, rhs, cones = self._program(pre)
            solver = clarabel.DefaultSolver(_zero_cost(q.size), q, M, rhs, cones,
                                            clarabel_lp.settings(refine=True))
        else:
            solver = self._instance(pre)
            solver.update(q=q)
        sol = solver.solve()
        name = str(sol.status).split(".")[-1]
        return name, np.asarray(sol.x), np.asarray(sol.z)

    def maximize(self, g: np.ndarray, context: str, kind: str = "support", *,
                 magnitude: np.ndarray | None = None, unverified: bool = False,
                 tight: bool = False, escalate: bool = False,
                 bracketed: bool = False) -> Maximized:
        """Maximize gᵀξ over the factor set (status policy in the module docstring).

        Parameters
        ----------
        g : ndarray, shape (ng,)
            The objective on the original factors.
        context, kind : str
            For a `SolverError`.
        magnitude : ndarray, shape (ng,), optional
            |G|ᵀ|d| when g = Gᵀd was computed in floating point: entries of g below its rounding
            level (γ_{n+1} times this, with a margin) are rounding noise of an exact zero and are
            taken as zero, and boundedness is judged relative to this magnitude, not to g's own.
        unverified : bool
            Return the last attempt's point and multipliers with status 'unverified' instead of
            raising when no attempt is settled (for weak-duality certificates, valid for any λ).
        tight : bool
            The multipliers will certify a bound: with free factors, a solution whose multipliers
            leave more than ``CERTIFICATE_LEAK_TOL`` of the objective on them is solved again with
            iterative refinement (the least-squares correction of a loose λ loosens the bound).
        escalate : bool
            Skip the kept instance and start with a cold solve by HiGHS's simplex method, then a
            fresh instance with iterative refinement: for a program whose first answer failed the
            caller's a-posteriori check (`CZProgram`: certified bound against primal value).
        bracketed : bool
            The caller brackets the answer by a rigorous bound and escalates it when the bracket is
            loose (`CZProgram._verified`): on a program whose factors are all bounded the
            warm-started simplex method answers first, and the kept interior-point instance
            (without its refined re-solve) only if the simplex method does not settle; with free
            factors the reverse (`BRACKETED_ATTEMPTS`, `BRACKETED_ATTEMPTS_FREE`); once the simplex
            method has run out of time in this support call, the interior-point method without
            crossover first (`AFTER_TIME_OUT_ATTEMPTS`), and the simplex method is not run again on
            a copy of the same rows; once a direction's exact rows were then reported infeasible
            and the relaxed program answered it (rows inconsistent by rounding), the call's later
            bracketed and escalated directions go there directly (`_relaxed_batch`; reliability
            case 029, k = 0: one hull's solves 505 s before, 107 s with both). On degenerate
            programs (the recursion smoother's sets: copies of the posterior factors linked by
            the states) the interior-point method stalls at 'AlmostSolved' with duals off by
            ~1e-6 on half the directions and the refined solve stalls at the same point.
            (Returning the rough answer for the bracket to judge is not enough: the bracket's
            rounding floor, 2⁻⁴⁰ of the values' magnitude, lets a loose dual through at offset
            1e6, certified hulls 1.3e-6 off.)

        Raises
        ------
        SolverError
            When neither the kept instance nor the fallbacks settle the program.
        """
        nan_xi, nan_lam = self._nan
        if magnitude is not None:
            g = np.where(np.abs(g) <= NOISE_FACTOR * np.finfo(float).eps * magnitude, 0.0, g)
        else:
            magnitude = np.abs(g)
        first = self.presolved
        if (bracketed or escalate) and not first.has_free \
                and self._relaxed_batch == current_batch():
            # An earlier direction of this batch found the exact rows infeasible, after the warm
            # simplex method ran out of time on them, on a set the phase-one program calls
            # non-empty: the rows are inconsistent by rounding (reliability case 029), and that
            # direction's answer was the relaxed program's.
            return self._relaxed_direction(first, g)
        if escalate:
            # The simplex method first: a vertex and exact-to-rounding multipliers, where the
            # interior-point method stopped with a loose dual (badly scaled free factors).
            # A cold solve (HiGHS's presolve and scaling from scratch), not the warm model that
            # may have given the first answer: warm-started from another objective's basis, its
            # optima are verified but can be ~1e-9 of the objective's scale from the cold ones,
            # which at states 3500 σ from the origin is 4e-5 of a hull's width (reliability case
            # 150, k = 6).
            attempts = [(first, "cold simplex"), (first, True)]
        elif bracketed:
            # All factors bounded: the warm-started simplex method first, the interior-point
            # method if it does not settle (free factors: the reverse, `BRACKETED_ATTEMPTS_FREE`).
            # On the recursion smoother's degenerate sets Clarabel stopped at 'AlmostSolved'
            # on most directions and the simplex method re-solved them anyway: simplex first took
            # the plain hulls of reliability cases 043 (scale 1e-6), 045 and 000 from 58, 70 and
            # 8.4 s to 13, 39 and 5.4 s (``benchmarks/bench_bracketed_order.py``). HiGHS's presolve
            # drops dependent rows, so it runs on the kept program; the fully presolved one is built
            # only if both fail (its dense rank-revealing QR was 72 % of the recursion smoother's
            # time on reliability case 029, CZ noises, 1000 × 1500 factor sets).
            order = (BRACKETED_ATTEMPTS_FREE if first.has_free
                     else AFTER_TIME_OUT_ATTEMPTS if simplex_timed_out(first) else BRACKETED_ATTEMPTS)
            attempts = [(first, refine) for refine in order]
        else:
            attempts = [(first, False), (first, True)]
        if not first.dependent_checked:
            attempts.append((None, True))  # the fully presolved program, built only if needed
        if not escalate and not (bracketed and first.dependent_checked):
            attempts.append((None, "simplex"))  # (when dependent rows were checked: `first` again)
        # Last, HiGHS's interior-point method: on reliability case 184 (k = 8) the simplex method
        # met a singular basis on every rung and Clarabel a 'NumericalError', where it settled;
        # without crossover, since at noise 1e3 (k = 25) the crossover's bases failed too.
        if attempts[0][1] != "cold interior":  # (not already first: `AFTER_TIME_OUT_ATTEMPTS`)
            attempts.append((first, "cold interior"))
        simplex_on_first = any(planned is first and refine == "simplex"
                               for planned, refine in attempts)
        last = "Unknown"
        best: tuple[float, Maximized] | None = None  # the tightest verified reduced-accuracy answer
        rough: Maximized | None = None  # the last unverified one (for certificates only)
        bounded = None  # the recession program's verdict on g, computed at most once
        pre = first  # the last program actually solved (the relaxed last resort reuses it)
        for planned, refine in attempts:
            if planned is None:
                # An attempt skipped as a repeat must not leave `pre` empty-handed (reliability
                # case 018: the relaxed last resort was handed None after a skipped attempt).
                # The simplex method is not run on a copy of `first`'s rows after it ran on `first`
                # for this direction and ran out of time there in this batch (reliability case 029,
                # k = 0: a second 81 s time-out on the first direction).
                repeat = refine == "simplex" and simplex_on_first and simplex_timed_out(first)
                planned = (self._fully_presolved_if_new(first) if refine is True or repeat
                           else self.fully_presolved)
                if planned is None:
                    continue
            pre = planned
            if pre.empty:
                self._empty = True
                return Maximized("infeasible", nan_xi, nan_lam)
            m, p = pre.A.shape
            q, sigma, lam0 = self._scaled_objective(pre, g)
            if p == 0 or m + np.count_nonzero(pre.bounded) == 0:
                if np.any(q[~pre.bounded]):
                    return Maximized("unbounded", nan_xi, nan_lam)
                eta = -np.sign(q)  # every factor bounded (or cost-free): the box's vertex
                return Maximized("optimal", pre.factors(eta[None], self.ng)[0], np.zeros(self.nc))
            if bounded:
                q, lam0 = project_free(pre, q)
            name, eta, z = self._solve_on(pre, q, refine)
            z = z[:m]
            if name in _INFEASIBLE:
                if self.is_empty():
                    return Maximized("infeasible", nan_xi, nan_lam)
                return self._relaxed(pre, q, sigma, lam0, infeasible=True)
            leak = pre.free_residual(q, z)
            if name == "Solved" and refine is False and leak > (
                    tol.CERTIFICATE_LEAK_TOL if tight else tol.REDUCED_COST_TOL):
                # Multipliers that leave part of the objective on the free factors: refined first
                # (cheaper than the recession program, and a certificate needs them tight).
                again = self._solve_on(pre, q, True)
                again_leak = pre.free_residual(q, again[2][:m])
                if again[0] == "Solved" and again_leak < leak:
                    name, eta, z, leak = again[0], again[1], again[2][:m], again_leak
            if pre.has_free and not bounded and (
                    name in _UNBOUNDED or (name in ("Solved", "AlmostSolved")
                                                 and leak > tol.REDUCED_COST_TOL)):
                # Unbounded, or the solver's 'optimum' of an unbounded direction (seen with huge
                # primal points), or an objective that cancels on the free factors only up to
                # rounding: the recession program decides.
                if name in _UNBOUNDED and self.is_empty():
                    return Maximized("infeasible", nan_xi, nan_lam)
                bounded = not self.unbounded_objectives(g[None, :], context, magnitude[None, :])[0]
                if not bounded:
                    return Maximized("unbounded", nan_xi, nan_lam)
                # Bounded to tolerance: solve the objective with its free-factor part projected out.
                q, lam0 = project_free(pre, q)
                name, eta, z = self._solve_on(pre, q, refine)
                z = z[:m]
                if name in _INFEASIBLE:
                    if self.is_empty():
                        return Maximized("infeasible", nan_xi, nan_lam)
                    return self._relaxed(pre, q, sigma, lam0, infeasible=True)
                leak = pre.free_residual(q, z)
            gap = None
            if leak <= tol.REDUCED_COST_TOL and name in ("Solved", "AlmostSolved"):
                gap = 0.0 if name == "Solved" else pre.checked_gap(q, eta, z)
            if gap is not None:
                answer = Maximized("optimal", pre.factors(eta[None], self.ng)[0],
                                   pre.multipliers((z + lam0)[None], np.array([sigma]), self.nc)[0])
                if gap <= tol.ACCURATE_GAP_TOL:
                    return answer
                # Verified but loose: kept, while the fallbacks try for a tighter answer.
                if best is None or gap < best[0]:
                    best = (gap, answer)
            last = name
            if np.all(np.isfinite(z)) and np.all(np.isfinite(eta)) and name not in _UNBOUNDED:
                rough = Maximized("unverified", pre.factors(eta[None], self.ng)[0],
                                  pre.multipliers((z + lam0)[None], np.array([sigma]), self.nc)[0])
        if best is not None:
            return best[1]
        if unverified and rough is not None:
            return rough
        if last not in _UNBOUNDED and not self.is_empty():
            # The last resort on a set the phase-one program shows non-empty: the program relaxed
            # by the phase-one residual (an outer value, within EMPTINESS_TOL of the set's rows).
            return self._relaxed(pre, q, sigma, lam0)
        raise SolverError(last, context, kind=kind)

    @staticmethod
    def _scaled_objective(pre: Presolved, g: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        """The minimized objective q = −ĝ/σ on ``pre``'s factors for maximizing gᵀξ, its scale
        σ = ‖ĝ‖∞ (1 for a zero objective) and the multipliers' zero offset (one per row)."""
        ghat = pre.objective(g[None, :])[0]
        sigma = float(np.abs(ghat).max(initial=0.0)) or 1.0
        return -ghat / sigma, sigma, np.zeros(pre.A.shape[0])

    def _relaxed_direction(self, pre: Presolved, g: np.ndarray) -> Maximized:
        """`_relaxed` for the objective g on the original factors (scaled as `maximize` does)."""
        return self._relaxed(pre, *self._scaled_objective(pre, g))

    def _relaxed(self, pre: Presolved, q: np.ndarray, sigma: float,
                 lam0: np.ndarray, infeasible: bool = False) -> Maximized:
        """Maximize over {η : |Âη − b̂| ≤ ρ, |η_B| ≤ 1} with ρ the phase-one residual plus
        ``EMPTINESS_TOL``: the outer value for a set the phase-one program calls non-empty.

        ``infeasible``: a solver reported the exact rows infeasible (not merely unsettled); if the
        warm simplex method has also run out of time on them in this batch, the batch's later
        bracketed and escalated directions come here directly (`_relaxed_batch`)."""
        m, p = pre.A.shape
        rho = max(self._phase_one or 0.0, 0.0) + tol.EMPTINESS_TOL * pre.data_scale
        M, rhs, _ = self._program(pre)
        rows = sp.vstack([pre.A, -pre.A, M[m:]], format="csc")
        r = np.concatenate([pre.b + rho, rho - pre.b, rhs[m:]])
        context = "computing a support function of a nearly empty constrained zonotope"
        solver = clarabel.DefaultSolver(_zero_cost(p), q, rows, r,
                                        [clarabel.NonnegativeConeT(rows.shape[0])],
                                        clarabel_lp.settings(refine=True))
        sol = solver.solve()
        name = str(sol.status).split(".")[-1]
        x, z = np.asarray(sol.x), np.asarray(sol.z)
        if name != "Solved":
            # The relaxed program is feasible (ρ covers the phase-one residual) and bounded: the
            # simplex method settles what the interior-point method did not (reliability case 069
            # at noise 1e3, a set the measurements pin to a sliver).
            fallback, x, z = simplex_inequalities(q, rows, r)
            if fallback != "optimal":
                raise SolverError(name, context, kind="support")
        if infeasible and simplex_timed_out(self.presolved):
            # Only where solving the exact rows is costly (a time-out of 32 s or more): programs
            # without one are solved as before.
            self._relaxed_batch = current_batch()
        lam_hat = z[:m] - z[m:2 * m] + lam0  # Âᵀ(z⁺ − z⁻) cancels the objective as Âᵀλ̂ would
        return Maximized("relaxed", pre.factors(x[None, :], self.ng)[0],
                         pre.multipliers(lam_hat[None], np.array([sigma]), self.nc)[0])

    # -- emptiness ---------------------------------------------------------------------------------
    def is_empty(self) -> bool:
        """Whether {ξ : Aξ = b, |ξ| ≤ h} is empty, by the elastic phase-one program (cached)."""
        if self._empty is None:
            self._empty = self._decide_empty()
        return self._empty

    def _decide_empty(self) -> bool:
        if self.nc == 0:
            return False  # ξ = 0 is feasible since h ≥ 0
        context = "deciding emptiness of a constrained zonotope"
        first = self.presolved
        if first.empty:
            return True
        if first.A.shape[0] and first.A.shape[1]:
            # The common case first, on the kept instance the support LPs reuse: a feasibility
            # solve whose point satisfies the rows to the emptiness tolerance proves non-emptiness.
            # Anything else (infeasible, stalled, inaccurate) is left to the phase-one program.
            name, eta, _ = self._solve_on(first, np.zeros(first.A.shape[1]), False)
            if name == "Solved":
                eta[first.bounded] = np.clip(eta[first.bounded], -1.0, 1.0)
                upper = float(np.abs(first.A @ eta - first.b).max(initial=0.0))
                if upper <= tol.EMPTINESS_TOL * first.data_scale:
                    self._phase_one = upper
                    return False
        attempts = [(first, False), (first, True)]
        if not first.dependent_checked:
            attempts.append((None, True))
        last = "Unknown"
        for planned, refine in attempts:
            if planned is None:
                planned = (self._fully_presolved_if_new(first) if refine is True
                           else self.fully_presolved)
                if planned is None:
                    continue  # `pre`, `rows`, `r` stay those of the last program built
            pre = planned
            if pre.empty:
                return True
            m, p = pre.A.shape
            if m == 0:
                self._phase_one = 0.0
                return False
            limit = tol.EMPTINESS_TOL * pre.data_scale
            M, rhs, _ = self._program(pre)
            ones = sp.csc_matrix(np.ones((m, 1)))
            nb2 = M.shape[0] - m
            t_row = sp.csc_matrix(([-1.0], ([0], [p])), shape=(1, p + 1))
            rows = sp.vstack([sp.hstack([pre.A, -ones]), sp.hstack([-pre.A, -ones]),
                              sp.hstack([M[m:], sp.csc_matrix((nb2, 1))]), t_row], format="csc")
            r = np.concatenate([pre.b, -pre.b, rhs[m:], [0.0]])
            cost = np.zeros(p + 1)
            cost[-1] = 1.0
            solver = clarabel.DefaultSolver(_zero_cost(p + 1), cost, rows, r,
                                            [clarabel.NonnegativeConeT(rows.shape[0])],
                                            clarabel_lp.settings(refine=refine))
            sol = solver.solve()
            last = str(sol.status).split(".")[-1]
            x = np.asarray(sol.x)
            eta = x[:p].copy()
            eta[pre.bounded] = np.clip(eta[pre.bounded], -1.0, 1.0)
            upper = float(np.abs(pre.A @ eta - pre.b).max(initial=0.0))  # attained by a point
            if last == "Solved" or (last == "AlmostSolved" and (upper <= limit
                                                               or x[-1] > 10 * limit)):
                self._phase_one = min(float(x[-1]), upper)
                return bool(x[-1] > limit and upper > limit)
        # The phase-one program is always feasible and bounded; where Clarabel calls it infeasible
        # or stalls (reliability case 072 at offset 1e6: states 1e28, the data consistent only to
        # their rounding), the simplex method decides it.
        status, x, _ = simplex_inequalities(cost, rows, r)
        if status == "optimal":
            eta = x[:p].copy()
            eta[pre.bounded] = np.clip(eta[pre.bounded], -1.0, 1.0)
            upper = float(np.abs(pre.A @ eta - pre.b).max(initial=0.0))
            self._phase_one = min(float(x[-1]), upper)
            return bool(x[-1] > limit and upper > limit)
        raise SolverError(last, context, kind="emptiness")

    # -- recession ---------------------------------------------------------------------------------
    def unbounded_objectives(self, g: np.ndarray, context: str,
                             magnitude: np.ndarray | None = None) -> np.ndarray:
        """Which objectives (rows of ``g``, shape (k, ng)) grow without bound on the factor set.

        The recession cone is {ξ : Aξ = 0, ξ_j = 0 where h_j < ∞}, so only the free factors matter.
        On the presolved program an objective ĝ is unbounded on a non-empty factor set exactly when
        the gain max{ĝ_Fᵀη : Â_F η = 0, |η| ≤ 1} = min_λ ‖ĝ_F − Â_Fᵀλ‖₁ is positive, that is when no
        multiplier cancels the reduced cost on the free factors. This program is feasible (η = 0) and
        bounded, so Clarabel decides it reliably, unlike the dual infeasibility of the support LP.
        Gains above ``REDUCED_COST_TOL·‖ĝ‖∞`` count as positive (the presolve made the free columns
        unit-scaled, so this is scale-free), or, when the ``magnitude`` (shape of ``g``) of the
        computation that produced g is given, above ``REDUCED_COST_TOL·max(1, ‖S·magnitude‖∞)``.
        """
        pre = self.fully_presolved if self._pre_full is not None else self.presolved
        free = np.flatnonzero(~pre.bounded)
        ghat = pre.objective(g)
        k, nf = ghat.shape[0], free.size
        if nf == 0:
            return np.zeros(k, dtype=bool)
        scale = np.abs(ghat if magnitude is None else pre.objective(magnitude)).max(axis=1,
                                                                                      initial=0.0)
        if magnitude is not None:  # absolute floor: a direction of norm 1e-16 sees no lineality
            scale = np.maximum(scale, 1.0)
        gF = ghat[:, free] / np.where(scale > 0, scale, 1.0)[:, None]
        AF = pre.A[:, free]
        m = AF.shape[0]
        gains = np.empty(k)
        width = max(k, 1) if k * nf <= STACK_MAX_VARIABLES else 1
        for start in range(0, k, width):
            rows = slice(start, start + width)
            w = gF[rows].shape[0]
            eye = sp.identity(w, format="csc")
            M = sp.vstack([sp.kron(eye, AF), sp.identity(w * nf), -sp.identity(w * nf)],
                          format="csc")
            rhs = np.concatenate([np.zeros(w * m), np.ones(2 * w * nf)])
            sol = solve_lp(-gF[rows].reshape(-1), M, rhs, w * m, 2 * w * nf, context, refine=True,
                           kind="recession")
            if sol.status == "optimal":
                gains[rows] = np.einsum("ij,ij->i", gF[rows], sol.x.reshape(w, nf))
                continue
            # The program is feasible (η = 0) and bounded: the simplex method settles it where the
            # interior-point method could not (reliability case 176 at noise 1e-6: 'inaccurate').
            for i in range(start, start + w):
                status, eta = simplex_box_equalities(-gF[i], AF)
                if status != "optimal":
                    raise SolverError(sol.status, context, kind="recession")
                gains[i] = float(gF[i] @ eta)
        return gains > tol.REDUCED_COST_TOL
