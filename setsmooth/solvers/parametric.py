"""Support values of constrained zonotopes that share G and A and differ in c, b and h.

The OIT-CZ SMF's windows (stability paper (23)) all have the same generator and constraint matrices;
only the right-hand side b (the measurements), the centre c and, for detectable systems, the finite
factor bounds h change from step to step. `ParametricSupport` asks the solver policy's sequence
backends ('along time', `policy.policy`): today HiGHS's dual simplex method with one model per
direction — the LP max{gᵀξ : Aξ = b, |ξ_B| ≤ h_B} with its constraint matrix and objective set up
once — that per step changes only the row bounds b and the column bounds h and re-solves from that
direction's previous optimal basis (`highs.DirectionModels`): a change of b and h leaves a basis
dual feasible (the objective did not change), so the dual method starts at once. Nothing is
presolved or rebuilt per step.

`ParametricPoints` does the same for support points (values at checked points, not bounds) of a
sequence whose matrix also changes in a declared block of entries: the inner windows of the exact
filter's hulls along time (`setsmooth.filters.window_brackets`) and the chords of hit-and-run on a
constrained zonotope (`setsmooth.sets.sampling`), whose direction is a column of the matrix.

The warm bases are state of one run, held by a `ParametricSupport.session` that the run makes and
drops (the OIT-CZ loop makes one per window structure), so a run's answers are a function of its own
data, the same whatever ran before on the same engine and in whichever thread.

Soundness does not rest on the solver: every value returned is the weak-duality bound of
`certify.certified_bound` evaluated at the solver's multipliers (corrected so that they cancel the
free factors' reduced costs), an upper bound on the support value in floating point whatever the
solver did. A direction whose solve does not settle (`highs.SIMPLEX_TOLERANCES`, each rung capped in
iterations, never in time) goes through the constrained zonotope's own verified path
(`ConstrainedZonotope.support_many(certified=True)`), which settles infeasible and hard programs.

Why the dual simplex method and not the kept interior-point instance this module used before: from
one window to the next the optimal active set of a direction changes at almost every step (99.2 %
of 3,000 steps at n = 10), but the warm dual simplex method needs 22 / 52 / 97 pivots per LP at
n = 10 / 20 / 30 (`benchmarks/bench_oit.py --hull-methods`), and an interior-point solve cannot
start from the last answer at all.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from ..floating import U, gamma
from .certify import FREE_BOUND_DENSE_MAX, certified_bound
from .clarabel_lp import SolverError, _csc
from .backends import SEQUENCE_BACKENDS
from .policy import policy

__all__ = ["ParametricPoints", "ParametricSupport", "PointSession", "WarmSession"]


class ParametricSupport:
    """Certified support values h_Z(d_j) of Z(G, c, A, b, h) for fixed G, A, directions D.

    Parameters
    ----------
    G : ndarray, shape (n, ng)
    A : ndarray, shape (nc, ng)
    D : ndarray, shape (K, n)
        The directions (e.g. [I; −I] for the interval hull).
    free : ndarray of bool, shape (ng,)
        Which factors are free (h = ∞) in every (c, b, h) this object will see.

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth.solvers.parametric import ParametricSupport
    >>> G, A = np.eye(2), np.array([[1.0, 1.0]])
    >>> engine = ParametricSupport(G, A, np.vstack([np.eye(2), -np.eye(2)]), np.zeros(2, bool))
    >>> (np.round(engine.values(np.zeros(2), np.array([1.0]), np.ones(2)), 6) + 0.0).tolist()   # no -0.0
    [1.0, 1.0, 0.0, 0.0]
    """

    def __init__(self, G: np.ndarray, A: np.ndarray, D: np.ndarray, free: np.ndarray):
        self.G = np.asarray(G, dtype=float)
        self.A = _csc(A)
        self.D = np.asarray(D, dtype=float)
        self.free = np.asarray(free, dtype=bool)
        self.fin = np.flatnonzero(~self.free)
        nc, ng = self.A.shape
        self.nc, self.ng = nc, ng
        self._q = -(self.D @ self.G)  # HiGHS minimizes: q = −Gᵀd, one row per direction
        self._ops = _DenseOperators(self.G, self.A)
        # What depends on A only is prepared once: the least-squares correction of the multipliers
        # on the free factors and the smallest eigenvalue of A_FᵀA_F behind their rigorous bound.
        free_cols = np.flatnonzero(self.free)
        self._AF = self.A[:, free_cols].toarray()
        self._correction = None
        self._lam_min = None
        if free_cols.size:
            gram = self._AF.T @ self._AF
            try:
                self._correction = self._AF @ np.linalg.inv(gram)  # δ = A_F (A_FᵀA_F)⁻¹ r
            except np.linalg.LinAlgError:
                self._correction = None
            lam_min = _free_lam_min(self.A, free_cols)
            self._lam_min = lam_min if lam_min is not None and lam_min > 0 else None
            rows = np.unique(self.A[:, free_cols].indices)
            self._rows = rows
            self._abs_ARB = abs(sp.csr_matrix(self.A)[rows][:, self.fin]).toarray()

    def session(self) -> "WarmSession":
        """A run's warm models: its `WarmSession.values` re-solve each step from the last step's
        bases. One thread uses a session at a time."""
        return WarmSession(self)

    def values(self, c: np.ndarray, b: np.ndarray, h: np.ndarray, **charges) -> np.ndarray:
        """`WarmSession.values` of a new session: one step's bounds, every direction from scratch."""
        return self.session().values(c, b, h, **charges)

    def _certify(self, c, b, h, lam, ok, charges: dict) -> np.ndarray:
        D = self.D[ok]
        beta = 0.0
        if self._AF.shape[1]:
            gF = (D @ self.G)[:, self.free]
            if self._correction is not None:
                for _ in range(2):  # the second pass removes what the first left by rounding
                    lam = lam + (gF - lam @ self._AF) @ self._correction.T
            beta = self._free_bound(b, h, charges["slack"], charges["slack_free"])
        return certified_bound(D, self.G, c, self.A, b, h, lam, beta, self._ops, **charges)

    def _free_bound(self, b: np.ndarray, h: np.ndarray, slack: np.ndarray | None = None,
                    slack_free: np.ndarray | None = None) -> float | None:
        """β ≥ max ‖ξ_F‖∞ over the (relaxed) factor set, as `certify.free_factor_bound` (its λ_min
        once): the rows' slack adds to the residual, and the free columns' slack per unit of ‖ξ_F‖
        comes off σ_min."""
        if self._lam_min is None:
            return None
        residual = np.abs(b[self._rows]) + self._abs_ARB @ h[self.fin]
        if slack is not None:
            residual = residual + slack[self._rows]
        rhs = np.linalg.norm(residual) * (1.0 + gamma(self.ng + 5))
        sigma = np.sqrt(self._lam_min) * (1.0 - gamma(4))
        if slack_free is not None:
            sigma = sigma - np.linalg.norm(slack_free[self._rows]) * (1.0 + gamma(self._rows.size + 4))
            if not sigma > 0:
                return None
        bound = rhs / sigma * (1.0 + gamma(8))
        return float(bound) if np.isfinite(bound) else None


class WarmSession:
    """The sequence backends of a `ParametricSupport` for one run: the attempts of the solver
    policy's 'along time' purpose (`policy.policy`), each backend's state (e.g. its warm models)
    kept from step to step."""

    def __init__(self, engine: ParametricSupport):
        self.engine = engine
        self.states: dict = {}

    def values(self, c: np.ndarray, b: np.ndarray, h: np.ndarray, *, pad: np.ndarray | None = None,
               slack: np.ndarray | None = None, pad_free: np.ndarray | None = None,
               slack_free: np.ndarray | None = None) -> np.ndarray:
        """Upper bounds on h_Z(d_j), j = 1..K, for Z = Z(G, c, A, b, h) (certified), each direction
        asked of the policy's sequence backends in turn (HiGHS's dual simplex method from the
        direction's basis of the last call), what they leave to the set's verified path.

        Parameters
        ----------
        c : ndarray, shape (n,)
        b : ndarray, shape (nc,)
        h : ndarray, shape (ng,)
            Finite exactly where ``free`` is False.
        pad, slack, pad_free, slack_free : ndarray, optional
            Rounding charges (`setsmooth.sets.rounding`): the bounds then hold for the exact set the
            stored one encloses (e.g. `setsmooth.filters._window.Window.charged_data`).

        Returns
        -------
        ndarray, shape (K,)
            −inf for every direction when Z is empty.
        """
        e = self.engine
        h = np.asarray(h, dtype=float)
        if not np.array_equal(np.isinf(h), e.free):
            raise ValueError("h must be infinite exactly on the free factors this engine was built for")
        K = e.D.shape[0]
        lam = np.zeros((K, e.nc))
        ok = np.zeros(K, dtype=bool)
        for attempt in policy(e, "along time"):
            state = self.states.get(attempt.backend)
            if state is None:
                state = self.states[attempt.backend] = SEQUENCE_BACKENDS[attempt.backend](
                    e.A, e._q, e.free)
            for j in np.flatnonzero(~ok):
                answer = state.solve(j, b, h)
                if answer.status == "candidate" and np.all(np.isfinite(answer.z)):
                    lam[j], ok[j] = answer.z, True
            if ok.all():
                break
        charges = {"pad": pad, "slack": slack, "pad_free": pad_free, "slack_free": slack_free}
        out = np.empty(K)
        if ok.any():
            try:
                out[ok] = e._certify(c, b, h, lam[ok], ok, charges)
            except SolverError:  # an uncertifiable multiplier: the verified path decides
                ok[:] = False
        if not ok.all():
            from ..sets.constrained_zonotope import ConstrainedZonotope

            Z = ConstrainedZonotope._trusted(e.G, c, e.A, b, h, **charges)
            out[~ok] = Z.support_many(e.D[~ok], certified=True)
        return out


class _DenseOperators:
    """`certify.Operators` with dense transposes (small windows: dense products beat sparse ones)."""

    def __init__(self, G: np.ndarray, A: sp.csc_matrix):
        self.Gt = np.ascontiguousarray(G.T)
        self.absGt = np.abs(self.Gt)
        self.At = np.ascontiguousarray(A.toarray().T)
        self.absAt = np.abs(self.At)
        col_nnz = np.diff(A.indptr) if A.shape[0] else np.zeros(A.shape[1], dtype=int)
        self.gamma_cols = gamma(col_nnz + 2)


def _free_lam_min(A: sp.csc_matrix, free_cols: np.ndarray) -> float | None:
    """A rigorous lower bound on λ_min(A_FᵀA_F) (the computation of `certify.free_factor_bound`)."""
    if free_cols.size > FREE_BOUND_DENSE_MAX:
        return None
    AF = A[:, free_cols]
    gram = (AF.T @ AF).toarray()
    absAF = abs(AF)
    gram_err = float(gamma(A.shape[0] + 2) * np.linalg.norm((absAF.T @ absAF).toarray()))
    eig_err = 8.0 * free_cols.size * U * np.linalg.norm(gram)
    return float(np.linalg.eigvalsh(gram)[0]) - gram_err - eig_err


class ParametricPoints:
    """Support points of Z(G, c, A, b, h) for fixed G and directions D, where b, c, h and one block
    of entries of A change from program to program (the inner windows of
    `setsmooth.filters.window_brackets`, whose prior's points enter A).

    The values are the solver's, at points checked to satisfy the program to ``SOLVER_CHECK_TOL`` of
    its scale: lower ends of a bracket (points of the set to the solver's accuracy), not bounds.

    Parameters
    ----------
    G : ndarray, shape (n, ng)
    A : ndarray or sparse matrix, shape (nc, ng)
        With the block's entries set to any values but 0 (they are stored entries).
    D : ndarray, shape (K, n)
    free : ndarray of bool, shape (ng,)
    block : (ndarray, ndarray)
        Row and column indices of the entries of A that change (each entry once).
    """

    def __init__(self, G: np.ndarray, A, D: np.ndarray, free: np.ndarray,
                 block: tuple[np.ndarray, np.ndarray]):
        self.G = np.asarray(G, dtype=float)
        self.A = _csc(A)
        self.D = np.asarray(D, dtype=float)
        self.free = np.asarray(free, dtype=bool)
        self.block = tuple(np.asarray(ix, dtype=np.int64) for ix in block)
        self._q = -(self.D @ self.G)
        # The check's products: the entries outside the block (the block's stored as 0), then the
        # block's own terms added row by row, so no program copies A (kept sparse if it came so).
        fixed = self.A.copy()
        rows, cols = self.block
        fixed[rows, cols] = 0.0
        self._fixed, self._abs_fixed = fixed, abs(fixed)

    def session(self) -> "PointSession":
        """A run's warm models (one thread at a time)."""
        return PointSession(self)


class PointSession:
    """The sequence backends of a `ParametricPoints` for one run (the solver policy's 'along time'
    attempts), each backend's models kept from program to program."""

    def __init__(self, engine: ParametricPoints):
        self.engine = engine
        self.states: dict = {}

    def points(self, c: np.ndarray, b: np.ndarray, h: np.ndarray, block: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
        """(values, points) of the support along each direction of Z(G, c, A, b, h) with the block's
        entries ``block``; NaN where no backend gave a point that passes the check."""
        e = self.engine
        K, n = e.D.shape
        block = np.asarray(block, dtype=float)
        values, points = np.full(K, np.nan), np.full((K, n), np.nan)
        bounded = ~e.free
        scale = 1.0 + np.abs(b).max(initial=0.0)
        for attempt in policy(e, "along time"):
            state = self.states.get(attempt.backend)
            if state is None:
                state = self.states[attempt.backend] = SEQUENCE_BACKENDS[attempt.backend](
                    e.A, e._q, e.free, block=e.block)
            state.set_block(block)
            for j in np.flatnonzero(np.isnan(values)):
                answer = state.solve(j, b, h)
                xi = answer.eta
                if answer.status != "candidate" or not np.all(np.isfinite(xi)):
                    continue
                if _satisfies(e, block, b, h, bounded, xi, scale):
                    points[j] = c + e.G @ xi
                    values[j] = e.D[j] @ points[j]
            if not np.isnan(values).any():
                break
        return values, points


def _satisfies(e: ParametricPoints, block: np.ndarray, b: np.ndarray, h: np.ndarray,
               bounded: np.ndarray, xi: np.ndarray, scale: float) -> bool:
    """Whether Aξ = b and |ξ_B| ≤ h_B hold to ``SOLVER_CHECK_TOL`` of the program's scale (the
    check a point of a bracket's lower end passes, as `Presolved.checked_gaps` in presolved units),
    A being ``e``'s matrix with the block's entries ``block``."""
    rows, cols = e.block
    m = e.A.shape[0]
    Axi = e._fixed @ xi + np.bincount(rows, block * xi[cols], minlength=m)
    terms = e._abs_fixed @ np.abs(xi) + np.bincount(rows, np.abs(block * xi[cols]), minlength=m)
    residual = np.abs(Axi - b).max(initial=0.0)
    overshoot = (np.abs(xi[bounded]) - h[bounded]).max(initial=0.0)
    size = scale + terms.max(initial=0.0)
    return bool(residual <= tol.SOLVER_CHECK_TOL * size
                and overshoot <= tol.SOLVER_CHECK_TOL * (1.0 + h[bounded].max(initial=0.0)))
