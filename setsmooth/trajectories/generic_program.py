"""The trajectory set of any representation: one CVXPY problem over the stacked trajectory.

When the prior, W or V has no exact constrained-zonotope form (an `Ellipsoid`, an `HPolytope`, a user
set given only by ``constraints(x)``), the set of trajectories consistent with y_start..y_stop,

    ⟦x_{i:k} | Z, y_{i:k}⟧ = { (x_i, …, x_k) : x_i ∈ Z,  x_{l+1} = A_l x_l + B_l w_l + u_l,
                                               y_l = C_l x_l + D_l v_l,  w_l ∈ W,  v_l ∈ V }

(smoothing paper Theorem 1; stability paper (7) for its last projection), is the lazy `TrajectorySet`:
its ``constraints(x)`` state exactly that, with one CVXPY variable per noise sample, each constrained
by its own set's ``constraints``. O(k − i) variables and constraints, every one coupling neighbouring
times only.

Its support problem maximizes dᵀx with the direction as a ``cp.Parameter``: compiled once (per thread,
`solvers.instances`) and re-solved for every direction. A projection (a smoothed range ⟦x_l | y⟧, or a
posterior as the last state) is a `LinearMap` of the trajectory set, whose support along d is the
trajectory set's support along the embedded direction Mᵀd, so every projection is answered by the
one compiled problem.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..sets.base import ConvexSet
from ..sets.lazy import LinearMap
from ..solvers.clarabel_lp import SolverError
from ..solvers.cvxpy_problems import conic_form, solve_problem
from ..solvers.generic import GenericProgram
from ..solvers.instances import cached_instance

__all__ = ["TrajectorySet", "FilteredState", "filtered_ranges"]


class TrajectorySet(ConvexSet):
    """The trajectories (x_start, …, x_stop) consistent with y_start..y_stop, for any set types.

    Build it with `setsmooth.trajectories.trajectory_set`, which returns the sparse CZ form instead
    when the prior, W and V all flatten to constrained zonotopes.

    Parameters
    ----------
    system : LinearSystem
        Its W and V may be any `ConvexSet`s; time-varying matrices are read at absolute times.
    prior : ConvexSet
        The range of x_start, of dimension n.
    ys : ndarray, shape (T+1, m)
        Validated measurements indexed by absolute time.
    start, stop : int
        Validated window 0 ≤ start ≤ stop ≤ T.

    Notes
    -----
    Coordinates (l − start)·n .. (l − start + 1)·n − 1 hold x_l. Projections (`project`) are linear
    maps of this set and share its compiled support problem. Support values are not certified (the
    CVXPY path has no certificate); the CZ form is kept for sets that flatten.
    """

    def __init__(self, system, prior: ConvexSet, ys: np.ndarray, start: int, stop: int):
        self.system, self.prior = system, prior
        self.ys = ys[start: stop + 1].copy()
        self.ys.flags.writeable = False
        self.start, self.stop = start, stop
        self.n = system.n
        self.dim = system.n * (stop - start + 1)

    @property
    def steps(self) -> int:
        """Number of transitions stop − start."""
        return self.stop - self.start

    def constraints(self, x):
        return self._stacked_constraints(x, self.steps)

    def _stacked_constraints(self, x, last: int, relaxed=None) -> list:
        """Constraints of the trajectories x_start..x_{start+last} (``x`` of length n(last + 1)).

        With ``relaxed`` (a CVXPY parameter of length steps + 1), measurement l − start holds exactly
        when relaxed[l − start] = 0 and is dropped when it is 1 (a free slack enters it): one compiled
        program then serves every filtering time (`FilteredState`).
        """
        sys, n = self.system, self.n
        states = [x[j * n:(j + 1) * n] for j in range(last + 1)]
        cons = list(self.prior.constraints(states[0]))
        for j in range(last):
            k = self.start + j
            w = cp.Variable(sys.p)
            cons += list(sys.W.constraints(w))
            cons.append(states[j + 1] == sys.A_at(k) @ states[j] + sys.E_at(k) @ w + sys.input_term(k))
        for j in range(last + 1):
            k = self.start + j
            v = cp.Variable(sys.q)
            cons += list(sys.V.constraints(v))
            measured = sys.C_at(k) @ states[j] + sys.F_at(k) @ v
            if relaxed is not None:
                measured = measured + relaxed[j] * cp.Variable(sys.m)
            cons.append(measured == self.ys[j])
        return cons

    @property
    def _generic(self):
        def build() -> GenericProgram:
            program = GenericProgram(self)
            if self._states_bounded():
                # A bounded set has no recession direction: the generic path's recession test (2·dim
                # conic forms of a program this size) is skipped, soundly.
                program._recession = False
            return program

        return cached_instance(self, "trajectory program", build)

    def _states_bounded(self, *, needs_w: bool = False) -> bool:
        """Whether the states are bounded because x_start and every w_l are (sufficient, not needed).

        x_start ∈ prior and x_{l+1} = A_l x_l + B_l w_l + u_l: bounded prior and W bound every state
        whatever V is. Decided by the interval hulls of the prior and W (small programs, each cached).
        With ``needs_w``, also require W to be non-empty (every x_l then extends to a trajectory).
        """
        for S in (self.system.W, self.prior):
            hull = S.interval_hull()
            if hull.is_empty():
                return S is self.prior or not needs_w  # an empty trajectory set is bounded
            if not (np.isfinite(hull.lo).all() and np.isfinite(hull.hi).all()):
                return False
        return True

    def _project(self, idx: np.ndarray) -> ConvexSet:
        M = sp.csr_matrix((np.ones(idx.size), (np.arange(idx.size), idx)), shape=(idx.size, self.dim))
        return LinearMap(M, self)

    def state(self, k: int) -> ConvexSet:
        """The projection on x_k (absolute time k, start ≤ k ≤ stop)."""
        if not self.start <= k <= self.stop:
            raise ValueError(f"k must lie in [{self.start}, {self.stop}], got {k}")
        j = k - self.start
        return self._project(np.arange(j * self.n, (j + 1) * self.n))


class FilteredState(ConvexSet):
    """⟦x_k | Z, y_{start:k}⟧: the last state of the trajectories start..k, of any set types.

    The filtering map F_{k,start}(prior) of stability paper (7), i.e. with ``start`` = 0 and prior X0
    the posterior ⟦x_k | y_{0:k}⟧ of the classical filter (stability Algorithm 1). Every
    `FilteredState` of one `TrajectorySet` is answered by one compiled program over the whole window,
    in which the measurements after k are relaxed by a parameter (see `filtered_ranges` for why that
    is the same set). Made by `filtered_ranges`; not certified (the CVXPY path has no certificate).
    """

    def __init__(self, trajectories: TrajectorySet, k: int):
        self.trajectories, self.k = trajectories, int(k)
        self.dim = trajectories.n

    @property
    def _index(self) -> int:
        return self.k - self.trajectories.start

    def constraints(self, x):
        n, j = self.dim, self._index
        z = cp.Variable(n * (j + 1))
        return [x == z[j * n:]] + self.trajectories._stacked_constraints(z, j)

    @property
    def _program(self) -> "_FilterProgram":
        traj = self.trajectories
        return cached_instance(traj, "filter program", lambda: _FilterProgram(traj))

    def _support(self, D: np.ndarray, certified: bool):
        if certified:
            raise ValueError("certified support values are not available for FilteredState: its "
                             "sets do not flatten to a constrained zonotope")
        return self._program.support(self._index, D)

    def _is_empty(self) -> bool:
        empty = self.__dict__.get("_empty")
        if empty is None:
            empty = self.__dict__["_empty"] = not self._program.feasible(self._index)
        return empty


class _FilterProgram:
    """max dᵀx_j over the trajectories with the measurements after j relaxed: compiled once.

    The direction and the relaxation pattern are CVXPY parameters, so moving from one filtering time
    to the next re-solves the same compiled problem. Used only when the states are bounded (bounded
    prior, bounded non-empty W), so an 'unbounded' report can only be a solver failure.
    """

    def __init__(self, traj: TrajectorySet):
        self.n, self.steps = traj.n, traj.steps
        self.x = cp.Variable(traj.dim)
        self.d = cp.Parameter(traj.dim)
        self.relaxed = cp.Parameter(traj.steps + 1)
        constraints = traj._stacked_constraints(self.x, traj.steps, self.relaxed)
        self.problem = cp.Problem(cp.Maximize(self.d @ self.x), constraints)

    def _set(self, j: int, d: np.ndarray) -> None:
        self.relaxed.value = (np.arange(self.steps + 1) > j).astype(float)
        full = np.zeros(self.x.size)
        full[j * self.n:(j + 1) * self.n] = d
        self.d.value = full

    def _solve(self, j: int, d: np.ndarray, context: str) -> str:
        self._set(j, d)
        return solve_problem(self.problem, context, "support")

    def feasible(self, j: int) -> bool:
        """Whether the posterior at index j is non-empty (the elastic emptiness program of
        `solvers.conic`)."""
        self._set(j, np.zeros(self.n))
        form = conic_form(self.problem, "deciding emptiness of a filtered range", "emptiness")[0]
        return not form.is_empty()

    def support(self, j: int, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        k = D.shape[0]
        values, points = np.empty(k), np.full((k, self.n), np.nan)
        empty = (np.full(k, -np.inf), np.full((k, self.n), np.nan))
        for i, d in enumerate(D):
            try:
                status = self._solve(j, d, "computing a support function of a filtered range")
            except SolverError:
                if not self.feasible(j):  # a stalled solve of an empty set
                    return empty
                raise
            if status == "infeasible":
                return empty
            if status == "unbounded":
                raise SolverError("unbounded", "computing a support function of a filtered range "
                                  "whose states are bounded (bounded prior and W)", kind="support")
            values[i] = float(self.problem.value)
            points[i] = self.x.value[j * self.n:(j + 1) * self.n]
        return values, points


def filtered_ranges(system, X0: ConvexSet, ys: np.ndarray) -> "list[ConvexSet] | None":
    """Posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, as `FilteredState`s of one trajectory program.

    ⟦x_k | y_{0:k}⟧ = F_{k,0}(X0) is the projection on x_k of the trajectories 0..k consistent with
    y_{0:k} (stability (7); smoothing Theorem 1 with T = k). Appending the steps k+1..T without their
    measurements changes no x_k: when W is non-empty every x_k continues to a trajectory 0..T. So each
    posterior is the projection on x_k of the trajectories 0..T with the measurements after k dropped,
    and one compiled program serves all of them (`classical_filter` then settles emptiness for the
    whole data set at once).

    Parameters
    ----------
    system : LinearSystem
    X0 : ConvexSet
    ys : ndarray, shape (T+1, m)
        Validated measurements.

    Returns
    -------
    list of FilteredState or None
        None when the states are not known to be bounded (an unbounded X0 or W, or an empty W): the
        caller then runs the recursion.
    """
    T = ys.shape[0] - 1
    trajectories = TrajectorySet(system, X0, ys, 0, T)
    if not trajectories._states_bounded(needs_w=True):
        return None
    return [FilteredState(trajectories, k) for k in range(T + 1)]
