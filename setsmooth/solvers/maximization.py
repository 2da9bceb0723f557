"""One objective maximized over a factor set: the attempts of the policy and what settles them.

`Search.run` asks the attempts of `policy.policy` in turn, each through a backend of
`backends.BACKENDS` (or the caller's fakes), and decides what each answer settles:

* **accepted**: a 'solved' answer, or a 'candidate' whose independent check in the presolved units
  (`Presolved.checked_gap`: the point's residual and bound overshoot and its gap to the weak-duality
  bound) is within ``ACCURATE_GAP_TOL``. A candidate checked within ``SOLVER_CHECK_TOL`` but not
  ``ACCURATE_GAP_TOL`` is kept while the later attempts look for a tighter one.
* **infeasible**: settled by the emptiness verdict (`phase_one`); on a set that verdict calls
  non-empty (rows inconsistent only by rounding) the objective is maximized over the set relaxed by
  the phase-one residual, an outer value, so the two verdicts never contradict each other.
* **unbounded**, or multipliers that do not cancel the objective on the free factors: settled by
  the recession program (`recession.unbounded_objectives`); a bounded objective is then solved
  with its free part projected out.

When no attempt is accepted: the tightest kept candidate, else (on request) the last unverified
point for a weak-duality certificate, else the relaxed program on a non-empty set, else a
`SolverError` carrying the last status.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tolerances as tol
from .backends import BACKENDS, Answer
from .clarabel_lp import SolverError
from .policy import Attempt
from .free_factors import project_free
from .presolved import Presolved

__all__ = ["Maximized", "Search", "scaled_objective"]


@dataclass(frozen=True)
class Maximized:
    """One objective maximized over the factor set.

    Attributes
    ----------
    status : str
        'optimal' (accepted, see the module docstring), 'infeasible' (the factor set is empty),
        'unbounded', 'relaxed' (non-empty by the phase-one verdict but its support LP infeasible:
        solved on the set relaxed by the phase-one residual, an outer value) or 'unverified' (only
        on request: no attempt settled the program; ``lam`` is still good for a weak-duality
        certificate).
    xi : ndarray, shape (ng,)
        The maximizer (original factors), NaN unless solved.
    lam : ndarray, shape (nc,)
        Multipliers of Aξ = b for the original rows (zero on dropped rows), NaN unless solved.
    """

    status: str
    xi: np.ndarray
    lam: np.ndarray


def scaled_objective(pre: Presolved, g: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """The minimized objective q = −ĝ/σ on ``pre``'s factors for maximizing gᵀξ, its scale
    σ = ‖ĝ‖∞ (1 for a zero objective) and the multipliers' zero offset (one per row)."""
    q, sigma = pre.minimized(g[None, :])
    return q[0], float(sigma[0]), np.zeros(pre.A.shape[0])


class Search:
    """The attempts for one objective g (original factors) over ``factors`` (`FactorConstraints`).

    Parameters
    ----------
    factors : FactorConstraints
    g : ndarray, shape (ng,)
    magnitude : ndarray, shape (ng,)
        The magnitude of the computation that produced g (boundedness is judged relative to it).
    context : str
        For a `SolverError`.
    tight : bool
        The multipliers will certify a bound: a kept-instance answer leaving more than
        ``CERTIFICATE_LEAK_TOL`` of the objective on the free factors is refined.
    batch : object
        The caller's batch token (`warm_simplex`).
    backends : dict, optional
        Backends by name (default `backends.BACKENDS`; tests pass fakes).
    """

    def __init__(self, factors, g: np.ndarray, magnitude: np.ndarray, context: str, *,
                 tight: bool = False, batch: object = None, backends: dict | None = None):
        self.factors, self.g, self.magnitude, self.context = factors, g, magnitude, context
        self.tight, self.batch = tight, batch
        self.backends = BACKENDS if backends is None else backends
        self.bounded: bool | None = None  # the recession program's verdict on g, asked at most once
        self.best: tuple[float, Maximized] | None = None  # the tightest verified loose answer
        self.rough: Maximized | None = None  # the last unverified point (certificates only)
        self.last = "Unknown"  # the last status name, for a SolverError
        self.objective: tuple | None = None  # (pre, q, σ, λ₀) of the last program solved

    # -- the loop ----------------------------------------------------------------------------------
    def run(self, attempts: tuple[Attempt, ...], kept: Presolved, *, unverified: bool = False,
            kind: str = "support") -> Maximized:
        """The first settled answer of ``attempts`` over ``kept`` (or the fully presolved program
        for ``on_full`` attempts), else the last resorts of the module docstring."""
        asked: set = set()
        for attempt in attempts:
            pre = self.factors.program_for(attempt, kept)
            if (attempt.backend, id(pre)) in asked:
                continue  # the same backend on the same program: the same answer
            asked.add((attempt.backend, id(pre)))
            settled = self.attempt(pre, attempt.backend)
            if settled is not None:
                return settled
        return self.last_resort(unverified, kind)

    def attempt(self, pre: Presolved, backend: str) -> Maximized | None:
        """One backend on one program: a settled `Maximized`, or None to go on."""
        if pre.empty:
            self.factors._empty = True
            return self._nan("infeasible")
        q, sigma, lam0 = scaled_objective(pre, self.g)
        if self.bounded:
            q, lam0 = project_free(pre, q)
        self.objective = (pre, q, sigma, lam0)
        trivial = self._trivial(pre, q)
        if trivial is not None:
            return trivial
        answer, leak = self._solved(pre, q, backend)
        if answer.status != "infeasible" and self._needs_recession(pre, answer, leak):
            verdict = self._recession(answer)
            if verdict is not None:
                return verdict
            q, lam0 = project_free(pre, q)
            self.objective = (pre, q, sigma, lam0)
            answer, leak = self._solved(pre, q, backend)
        if answer.status == "infeasible":
            return self._infeasible()
        return self._judge(pre, sigma, lam0, answer, leak)

    def last_resort(self, unverified: bool, kind: str) -> Maximized:
        """What settles an objective no attempt settled (module docstring)."""
        if self.best is not None:
            return self.best[1]
        if unverified and self.rough is not None:
            return self.rough
        if self.objective is not None and self.last not in ("DualInfeasible", "AlmostDualInfeasible") \
                and not self.factors.is_empty():
            return self.factors.relaxed(*self.objective)
        raise SolverError(self.last, self.context, kind=kind)

    # -- one attempt -------------------------------------------------------------------------------
    def _nan(self, status: str) -> Maximized:
        nan_xi, nan_lam = self.factors._nan
        return Maximized(status, nan_xi, nan_lam)

    def _trivial(self, pre: Presolved, q: np.ndarray) -> Maximized | None:
        """The closed form of a program with no rows and no bounds to solve, else None."""
        m, p = pre.A.shape
        if p and m + np.count_nonzero(pre.bounded):
            return None
        if np.any(q[~pre.bounded]):
            return self._nan("unbounded")
        eta = -np.sign(q)  # every factor bounded (or cost-free): the box's vertex
        return Maximized("optimal", pre.factors(eta[None], self.factors.ng)[0],
                         np.zeros(self.factors.nc))

    def _solved(self, pre: Presolved, q: np.ndarray, backend: str) -> tuple[Answer, float]:
        """The backend's answer and its leak on the free factors; a kept-instance answer that
        leaves too much of the objective there is refined first (cheaper than the recession
        program, and a certificate needs tight multipliers)."""
        answer = self.backends[backend](pre, q, self.batch)
        self.last = answer.detail
        leak = pre.free_residual(q, answer.z)
        limit = tol.CERTIFICATE_LEAK_TOL if self.tight else tol.REDUCED_COST_TOL
        if backend == "clarabel" and answer.status == "solved" and leak > limit:
            again = self.backends["clarabel refined"](pre, q, self.batch)
            again_leak = pre.free_residual(q, again.z)
            if again.status == "solved" and again_leak < leak:
                return again, again_leak
        return answer, leak

    def _needs_recession(self, pre: Presolved, answer: Answer, leak: float) -> bool:
        """Unbounded, or the solver's 'optimum' of an unbounded direction (seen with huge primal
        points), or an objective cancelled on the free factors only up to rounding."""
        if not pre.has_free or self.bounded:
            return False
        return answer.status == "unbounded" or (answer.status in ("solved", "candidate")
                                                 and leak > tol.REDUCED_COST_TOL)

    def _recession(self, answer: Answer) -> Maximized | None:
        """The recession program's verdict: 'infeasible' or 'unbounded', or None when g is bounded
        (to tolerance) and is to be solved with its free part projected out."""
        if answer.status == "unbounded" and self.factors.is_empty():
            return self._nan("infeasible")
        self.bounded = not self.factors.unbounded_objectives(
            self.g[None, :], self.context, self.magnitude[None, :])[0]
        return None if self.bounded else self._nan("unbounded")

    def _infeasible(self) -> Maximized:
        if self.factors.is_empty():
            return self._nan("infeasible")
        return self.factors.relaxed(*self.objective)

    def _judge(self, pre: Presolved, sigma: float, lam0: np.ndarray, answer: Answer,
               leak: float) -> Maximized | None:
        """Accept, keep or pass on one answer (module docstring)."""
        ng, nc = self.factors.ng, self.factors.nc
        finite = np.isfinite(answer.z).all() and np.isfinite(answer.eta).all()
        if not finite or answer.status == "unbounded":
            return None
        result = Maximized("optimal", pre.factors(answer.eta[None], ng)[0],
                           pre.multipliers((answer.z + lam0)[None], np.array([sigma]), nc)[0])
        self.rough = Maximized("unverified", result.xi, result.lam)  # any λ certifies a bound
        if answer.status not in ("solved", "candidate") or leak > tol.REDUCED_COST_TOL:
            return None
        if answer.status == "solved":
            gap = 0.0
        elif answer.checked is not None:  # the backend checked it already (inf: it failed)
            gap = None if np.isinf(answer.checked) else answer.checked
        else:
            gap = pre.checked_gap(self.objective[1], answer.eta, answer.z)
        if gap is None:
            return None
        if gap <= tol.ACCURATE_GAP_TOL:
            return result
        if self.best is None or gap < self.best[0]:
            self.best = (gap, result)  # verified but loose: kept while later attempts try
        return None
