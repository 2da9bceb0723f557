"""The Clarabel adapter: settings, one-shot LP solves, and the status policy shared by every path.

Status policy: a solved LP gives a value, an infeasible one means the set is empty (``-inf``), a dual
infeasible one means the support is unbounded (``+inf``); any other status raises `SolverError`
carrying it.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import clarabel
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol

__all__ = ["SolverError", "LPSolution", "solve_lp"]


class SolverError(RuntimeError):
    """A convex program ended in a status that yields no trustworthy answer.

    One status vocabulary on every path: ``status`` is Clarabel's ``SolverStatus`` name
    ('AlmostSolved', 'MaxIterations', 'InsufficientProgress', 'NumericalError', ...) or one of
    setsmooth's own verdicts ('UncertifiableReducedCost': no sound finite certificate exists;
    'UnverifiedSolution': a reduced-accuracy answer failed our independent check).

    Parameters
    ----------
    status : str
        The status name.
    context : str, optional
        What was being computed, for the message.
    kind : str, optional
        The program kind: 'support', 'emptiness', 'membership', 'recession', 'closest point', ...

    Attributes
    ----------
    status : str
    kind : str or None
    context : str

    Examples
    --------
    >>> err = SolverError("MaxIterations", "computing a support function", kind="support")
    >>> err.status, err.kind
    ('MaxIterations', 'support')
    """

    def __init__(self, status: str, context: str = "", *, kind: str | None = None):
        self.status = str(status)
        self.context = str(context)
        self.kind = None if kind is None else str(kind)
        where = f" while {context}" if context else ""
        what = f" ({self.kind} program)" if self.kind else ""
        super().__init__(f"solver returned status {self.status!r}{what}{where}")

    def __reduce__(self):
        # Exceptions pickle through their args; keep status, context and kind across processes.
        return (_rebuild_solver_error, (self.status, self.context, self.kind))


def _rebuild_solver_error(status: str, context: str, kind: str | None) -> SolverError:
    return SolverError(status, context, kind=kind)


_SOLVED = "Solved"
_ALMOST_SOLVED = "AlmostSolved"
_INFEASIBLE = ("PrimalInfeasible",)
_UNBOUNDED = ("DualInfeasible",)


def settings(*, refine: bool = False) -> clarabel.DefaultSettings:
    """Clarabel's settings; ``refine`` turns iterative refinement back on (membership programs).

    Every path looks them up through this module, so that a test can patch them in one place.
    """
    s = clarabel.DefaultSettings()
    s.verbose = False
    s.direct_solve_method = "qdldl"
    # Iterative refinement of the KKT solves takes ~40% of Clarabel's time on CZ support LPs
    # (measured at ng = 100, nc = 40) and did not change any support value beyond 1e-12 on 1,300
    # random, vertex-degenerate, badly scaled and filter-generated CZ LPs checked against HiGHS; with
    # it on, two of the badly scaled ones stalled (InsufficientProgress). Tolerances are unchanged.
    s.iterative_refinement_enable = refine
    s.tol_gap_abs = tol.SOLVER_TOL
    s.tol_gap_rel = tol.SOLVER_TOL
    s.tol_feas = tol.SOLVER_TOL
    s.max_iter = 200
    return s


@dataclass(frozen=True)
class LPSolution:
    """What one Clarabel call returned: ``status`` in {'optimal', 'inaccurate', 'infeasible',
    'unbounded'}, the primal ``x``, the equality multipliers ``z_eq`` and Clarabel's ``solve_time``."""

    status: str
    x: np.ndarray
    z_eq: np.ndarray
    solve_time: float


def solve_lp(q: np.ndarray, A: sp.csc_matrix, b: np.ndarray, n_eq: int, n_ineq: int,
             context: str, refine: bool = False) -> LPSolution:
    """Minimize ``qᵀx`` subject to the first ``n_eq`` rows of ``Ax = b`` and the rest ``Ax ≤ b``
    (``refine``: with Clarabel's iterative refinement, see `settings`)."""
    cones = []
    if n_eq:
        cones.append(clarabel.ZeroConeT(n_eq))
    if n_ineq:
        cones.append(clarabel.NonnegativeConeT(n_ineq))
    nvar = q.shape[0]
    if not cones:  # no constraint at all: bounded only for q == 0
        x = np.zeros(nvar)
        status = "optimal" if not np.any(q) else "unbounded"
        return LPSolution(status, x, np.zeros(0), 0.0)
    solver = clarabel.DefaultSolver(_zero_cost(nvar), q, A, b, cones, settings(refine=refine))
    return _lp_solution(solver.solve(), n_eq, context)


def _lp_solution(sol, n_eq: int, context: str, solve_time: float | None = None) -> LPSolution:
    """Translate a Clarabel solution into an `LPSolution` (status policy in the module docstring);
    ``solve_time`` replaces Clarabel's own when given."""
    name = str(sol.status).split(".")[-1]
    if name == _SOLVED:
        status = "optimal"
    elif name == _ALMOST_SOLVED:
        status = "inaccurate"
    elif name in _INFEASIBLE:
        status = "infeasible"
    elif name in _UNBOUNDED:
        status = "unbounded"
    else:
        raise SolverError(name, context)
    return LPSolution(status, np.asarray(sol.x), np.asarray(sol.z)[:n_eq],
                      float(sol.solve_time) if solve_time is None else solve_time)


def _csc(M) -> sp.csc_matrix:
    """M as a canonical CSC matrix (sorted, unique row indices), built directly from a dense array:
    scipy's generic conversion costs as much as Clarabel's whole solve of a small CZ."""
    if sp.issparse(M):
        M = sp.csc_matrix(M)
        if not M.has_canonical_format:
            M = M.copy()
            M.sum_duplicates()
        return M
    M = np.asarray(M, dtype=float)
    cols, rows = np.nonzero(M.T)
    itype = _index_type(M.size)
    indptr = np.zeros(M.shape[1] + 1, dtype=itype)
    np.cumsum(np.bincount(cols, minlength=M.shape[1]), out=indptr[1:])
    return sp.csc_matrix((M[rows, cols], rows.astype(itype), indptr), shape=M.shape)


def _index_type(largest: int) -> type:
    # scipy stores indices as int32 when they fit and checks (costly) whatever it is given.
    return np.int32 if largest < np.iinfo(np.int32).max else np.int64


@lru_cache(maxsize=64)
def _zero_cost(n: int) -> sp.csc_matrix:
    """The zero quadratic cost of an LP with n variables (shared: Clarabel copies its input)."""
    itype = _index_type(n)
    return sp.csc_matrix((np.zeros(0), np.zeros(0, dtype=itype), np.zeros(n + 1, dtype=itype)),
                         shape=(n, n))
