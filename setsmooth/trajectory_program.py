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

import numpy as np
import scipy.sparse as sp

from .sets.base import ConvexSet

__all__ = ["TrajectorySet"]


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
        import cvxpy as cp

        sys, n = self.system, self.n
        states = [x[j * n:(j + 1) * n] for j in range(self.steps + 1)]
        cons = list(self.prior.constraints(states[0]))
        for j in range(self.steps):
            k = self.start + j
            w = cp.Variable(sys.p)
            cons += list(sys.W.constraints(w))
            cons.append(states[j + 1] == sys.A(k) @ states[j] + sys.B(k) @ w + sys.input_term(k))
        for j in range(self.steps + 1):
            k = self.start + j
            v = cp.Variable(sys.q)
            cons += list(sys.V.constraints(v))
            cons.append(sys.C(k) @ states[j] + sys.D(k) @ v == self.ys[j])
        return cons

    @property
    def _generic(self):
        from .solvers.generic import GenericProgram
        from .solvers.instances import cached_instance

        def build() -> GenericProgram:
            program = GenericProgram(self)
            if self._states_bounded():
                # A bounded set has no recession direction: the generic path's recession test (2·dim
                # conic forms of a program this size) is skipped, soundly.
                program._recession = False
            return program

        return cached_instance(self, "trajectory program", build)

    def _states_bounded(self) -> bool:
        """Whether the states are bounded because x_start and every w_l are (sufficient, not needed).

        x_start ∈ prior and x_{l+1} = A_l x_l + B_l w_l + u_l: bounded prior and W bound every state
        whatever V is. Decided by the interval hulls of the prior and W (small programs, each cached).
        """
        for S in (self.prior, self.system.W):
            hull = S.interval_hull()
            if hull.is_empty():
                return True  # an empty trajectory set is bounded
            if not (np.isfinite(hull.lo).all() and np.isfinite(hull.hi).all()):
                return False
        return True

    def _project(self, idx: np.ndarray) -> ConvexSet:
        from .sets.lazy import LinearMap

        M = sp.csr_matrix((np.ones(idx.size), (np.arange(idx.size), idx)), shape=(idx.size, self.dim))
        return LinearMap(M, self)

    def state(self, k: int) -> ConvexSet:
        """The projection on x_k (absolute time k, start ≤ k ≤ stop)."""
        if not self.start <= k <= self.stop:
            raise ValueError(f"k must lie in [{self.start}, {self.stop}], got {k}")
        j = k - self.start
        return self._project(np.arange(j * self.n, (j + 1) * self.n))
