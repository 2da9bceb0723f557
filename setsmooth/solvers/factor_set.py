"""The fast path's factor set {ξ : Aξ = b, |ξ| ≤ h} of a constrained zonotope, and its queries.

The fast path substitutes ``x = Gξ + c`` out, so every query of a CZ Z(G, c, A, b, h) is a linear
program over its factor set. `FactorConstraints` owns that set: it presolves it once (`presolve`:
fixed factors and zero rows dropped, bounds scaled out, rows and free factors equilibrated, free
factors in deviation coordinates, dependent rows dropped for small programs), and answers

* `maximize`: one objective, through the attempts of the solver policy (`policy.policy`), each
  answered by a backend (`backends.BACKENDS`) and judged by `maximization.Search`;
* `is_empty`: the elastic phase-one verdict (`phase_one.decide_empty`), cached;
* `unbounded_objectives`: the recession program (`recession.unbounded_objectives`).

Solver instances live in the per-thread, bounded cache of `instances.cached_instance`, never on the
object, so a factor set can be queried from several threads and pickled; no other state than these
caches and the cached verdicts is kept between queries.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from .clarabel_lp import _csc
from .certify import Operators, free_factor_bound
from .maximization import Maximized, Search
from .phase_one import decide_empty, relaxed_point
from .policy import Attempt, policy
from .presolve import presolve
from .presolved import Presolved
from .recession import STACK_MAX_VARIABLES
from .recession import unbounded_objectives as _unbounded_objectives

__all__ = ["FactorConstraints", "Maximized", "STACK_MAX_VARIABLES", "DENSE_PRESOLVE_MAX",
           "NOISE_FACTOR", "CHEAP_FREE_BOUND_MAX"]

#: Objective entries below NOISE_FACTOR·eps·(|G|ᵀ|d|)_j are the rounding noise of an exact zero
#: (a direction orthogonal to the free factors' lineality, computed in floating point).
NOISE_FACTOR = 64

_EPS = np.finfo(float).eps

#: A part of a joined factor set (`FactorConstraints.joined`) with at most this many free factors has
#: its dense free-factor bound computed when the parts are joined.
CHEAP_FREE_BOUND_MAX = 60

#: Linearly dependent rows are looked for up front (dense rank-revealing QR) when nc·ng is at most
#: this; larger (sparse, trajectory-sized) programs look for them only when an attempt of the policy
#: on the fully presolved program is reached.
DENSE_PRESOLVE_MAX = 5_000


class FactorConstraints:
    """The factor set {ξ : Aξ = b, -h ≤ ξ ≤ h} of a constrained zonotope, presolved for Clarabel.

    It depends on (A, b, h) only, so every linear map, translation and projection of a CZ shares one
    instance, and with it the presolve, the emptiness verdict and the Clarabel instance (kept per
    thread by `instances.cached_instance`).
    """

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
        betas = [p.cheap_free_bound() for p in parts]
        if all(beta is not None for beta in betas):
            joined._free_bound = (max(betas, default=0.0),)
        return joined

    def cheap_free_bound(self) -> float | None:
        """`free_bound` when it is known or cheap to compute (see `joined`), else None."""
        if self.free.size == 0:
            return 0.0
        if self._free_bound is not None or type(self).free_bound is not FactorConstraints.free_bound \
                or self.free.size <= CHEAP_FREE_BOUND_MAX:
            return self.free_bound()
        return None

    def fully_presolved_if_new(self, first: Presolved) -> Presolved | None:
        """`fully_presolved` when it differs from ``first`` (dependent rows dropped, or found
        empty), else None."""
        pre = self.fully_presolved
        return None if pre.rows.size == first.rows.size and not pre.empty else pre

    def free_bound(self) -> float | None:
        """β ≥ ‖ξ_F‖∞ on the free factors (`certify.free_factor_bound`; cached), or None."""
        if self._free_bound is None:
            self._free_bound = (free_factor_bound(self.A, self.b, self.h, slack=self.slack,
                                                  slack_free=self.slack_free),)
        return self._free_bound[0]

    def certificate_operators(self) -> tuple[sp.csc_matrix, sp.csr_matrix, tuple]:
        """(A_F, A_Fᵀ, `certificate_part`): the free factors' part of a certificate, prepared
        once and shared by every CZ over this factor set (the projections of one trajectory set
        each certify against the same A)."""
        ops = self.__dict__.get("_certificate_ops")
        if ops is None:
            AF = self.A[:, self.free]  # CSC already, and its transpose CSR: no further conversion
            ops = self.__dict__["_certificate_ops"] = (AF, AF.T, self.certificate_part())
        return ops

    def certificate_part(self) -> tuple:
        """`certify.Operators.factor_part` of A, prepared once (all a certificate needs of the
        factor set when no factor is free)."""
        part = self.__dict__.get("_certificate_part")
        if part is None:
            part = self.__dict__["_certificate_part"] = Operators.factor_part(self.A)
        return part

    # -- queries -----------------------------------------------------------------------------------
    def program_for(self, attempt: Attempt, kept: Presolved) -> Presolved:
        """The program an attempt runs on: ``kept``, or the fully presolved one (`policy`)."""
        if not attempt.on_full:
            return kept
        return self.fully_presolved_if_new(kept) or kept

    def maximize(self, g: np.ndarray, context: str, kind: str = "support", *,
                 magnitude: np.ndarray | None = None, unverified: bool = False,
                 tight: bool = False, purpose: str = "plain", batch: object = None,
                 backends: dict | None = None) -> Maximized:
        """Maximize gᵀξ over the factor set.

        Parameters
        ----------
        g : ndarray, shape (ng,)
            The objective on the original factors.
        context, kind : str
            For a `SolverError`.
        magnitude : ndarray, shape (ng,), optional
            |G|ᵀ|d| when g = Gᵀd was computed in floating point: entries of g below its rounding
            level (``NOISE_FACTOR``·eps times this) are rounding noise of an exact zero and are
            taken as zero, and boundedness is judged relative to this magnitude.
        unverified : bool
            Return the last attempt's point and multipliers with status 'unverified' instead of
            raising when no attempt settles (for weak-duality certificates, valid for any λ).
        tight : bool
            The multipliers will certify a bound (`maximization.Search`).
        purpose : {'plain', 'bracketed', 'escalated'}
            What the caller does with the answer: it selects the attempts (`policy.policy`).
        batch : object, optional
            The caller's batch token: the warm-started simplex method starts every batch from the
            program's feasible basis (`warm_simplex`).
        backends : dict, optional
            Backends by name (default `backends.BACKENDS`).

        Raises
        ------
        SolverError
            When no attempt and no last resort settles the program.
        """
        if magnitude is not None:
            g = np.where(np.abs(g) <= NOISE_FACTOR * _EPS * magnitude, 0.0, g)
        else:
            magnitude = np.abs(g)
        kept = self.presolved
        search = Search(self, g, magnitude, context, tight=tight, batch=batch, backends=backends)
        return search.run(policy(kept, purpose), kept, unverified=unverified, kind=kind)

    def relaxed(self, pre: Presolved, q: np.ndarray, sigma: float, lam0: np.ndarray) -> Maximized:
        """min qᵀη over the program ``pre`` relaxed by the phase-one residual plus
        ``EMPTINESS_TOL`` (`phase_one.relaxed_point`): the outer value of a non-empty set whose
        support LP no backend settled, as a `Maximized` with status 'relaxed'."""
        x, lam_hat = relaxed_point(pre, q, self.relaxation(pre))
        return Maximized("relaxed", pre.factors(x[None, :], self.ng)[0],
                         pre.multipliers((lam_hat + lam0)[None], np.array([sigma]), self.nc)[0])

    def relaxation(self, pre: Presolved) -> float:
        """ρ, the relaxation |Âη − b̂| ≤ ρ of ``pre``'s rows on which a non-empty set is answered
        when its stored rows are not settled as they are: the phase-one residual plus
        ``EMPTINESS_TOL`` of the data's scale (asks the emptiness verdict)."""
        self.is_empty()
        return max(self._phase_one or 0.0, 0.0) + tol.EMPTINESS_TOL * pre.data_scale

    def is_empty(self) -> bool:
        """Whether {ξ : Aξ = b, |ξ| ≤ h} is empty, by the phase-one verdict (cached)."""
        if self._empty is None:
            self._empty, self._phase_one = decide_empty(self)
        return self._empty

    def unbounded_objectives(self, g: np.ndarray, context: str,
                             magnitude: np.ndarray | None = None) -> np.ndarray:
        """Which objectives (rows of ``g``, shape (k, ng)) grow without bound on the factor set
        (`recession.unbounded_objectives`, on the fully presolved program when it was built)."""
        pre = self.fully_presolved if self._pre_full is not None else self.presolved
        return _unbounded_objectives(pre, g, context, magnitude)
