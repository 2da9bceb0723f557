"""The exact optimal filter and smoother of a linear system whose x_0 and noises have a joint range.

For x_{k+1} = A_k x_k + B_k w_k + u_k, y_k = C_k x_k + D_k v_k (rethinking (23)–(24)) and a convex joint
range J = ⟦x_0, w_{0:T−1}, v_{0:T}⟧ (`setsmooth.models.JointRange`), Theorem 1's optimal posterior
⟦x_k | y_{0:k}⟧ is the set of x_k over all ξ ∈ J that reproduce y_{0:k}: the projection on x_k of the set
of trajectories consistent with the data under J,

    ⟦x_{0:k} | y_{0:k}⟧ = { (x_0, …, x_k) : ξ ∈ J,  x_0 = ξ_{x_0},  x_{l+1} = A_l x_l + B_l ξ_{w_l} + u_l,
                                             y_l = C_l x_l + D_l ξ_{v_l} }                              (★)

— the trajectory set of `setsmooth.trajectories` with J in place of X0 × W^k × V^{k+1}. The smoothed range
⟦x_l | y_{0:T}⟧ is the projection of the same set with k = T. With J = `JointRange.unrelated(...)` this is
the classical filter (Theorem 2); with any other J the classical posterior contains it (Theorem 3).

When J flattens to a constrained zonotope Z(G_J, c_J, A_J, b_J, h_J), (★) is one sparse extended CZ, written
like `trajectory_set` about the nominal trajectory x̄ (the noises at the centre c_J): factors s_0..s_k
(state deviations, free) and η (J's factors), rows A_J η = b_J and

    s_0 − G_{x_0} η                        = 0
    s_{l+1} − A_l s_l − B_l G_{w_l} η       = 0
    C_l s_l + D_l G_{v_l} η                 = y_l − D_l c_{v_l} − C_l x̄_l,

where G_{x_0}, G_{w_l}, G_{v_l} are J's generator rows of those coordinates. For other J it is the lazy
generalized intersection of ℝ^{n(k+1)} × J with the same rows (one CVXPY program).

The paper's own construction for Section IV-B, state augmentation (33)–(35), is
`augment_identical_process_noise`; the tests check that both give the same sets.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from .._validation import check_system, measured
from ..models.related_noise import JointRange
from ..results import SetEstimates
from ..sets import rounding
from ..sets.algebra import cartesian_product
from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..sets.empty import EmptySet
from ..sets.reals import Reals
from ..models.linear_system import LinearSystem
from .classical import _first_empty
from .steps import _check_state_set

__all__ = ["joint_trajectory_set", "joint_trajectory_sets", "JointTrajectoryRows", "optimal_filter",
           "optimal_joint_smoother", "augment_identical_process_noise"]


def joint_trajectory_set(system, joint_range: JointRange, ys: Any, stop: int | None = None) -> ConvexSet:
    """⟦x_{0:stop} | y_{0:stop}⟧: the trajectories consistent with y_0..y_stop under the joint range (★).

    Parameters
    ----------
    system : LinearSystem
        Its matrices (and input u) are used; its W and V are not (the joint range replaces them).
    joint_range : JointRange
        ⟦x_0, w_{0:T−1}, v_{0:T}⟧ with the system's n, p, q and T ≥ stop.
    ys : array_like, shape (T'+1, m)
        Measurements y_0.. (rows after ``stop`` are not used).
    stop : int, optional
        The last time k; defaults to the last row of ``ys``.

    Returns
    -------
    ConvexSet
        Of dimension n(stop + 1), coordinates l·n..(l+1)·n − 1 holding x_l: a sparse extended CZ when
        the joint range flattens to one, else a lazy set.

    Raises
    ------
    ValueError
        When the joint range's n, p, q differ from the system's, ``stop`` lies outside
        [0, min(T, len(ys) − 1)], or ``ys`` has the wrong shape.

    Examples
    --------
    >>> import setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> J = ss.JointRange.identical_process_noise(ss.Box([-5.0], [5.0]), box, box, T=2)
    >>> Z = ss.joint_trajectory_set(system, J, [[0.0], [0.0], [0.0]])
    >>> Z.dim, round(Z.support([0.0, 0.0, 1.0]), 6)   # (x_0, x_1, x_2); x_2 ≤ y_2 + 1
    (3, 1.0)
    """
    return joint_trajectory_sets(system, joint_range, ys, [stop])[0]


def joint_trajectory_sets(system, joint_range: JointRange, ys: Any, stops) -> list[ConvexSet]:
    """`joint_trajectory_set` for every stop in ``stops``, from one assembly of the rows of (★).

    The rows of a time l (its dynamics and its measurement, with their rounding slack) do not depend
    on the stop, so they are computed once, up to the last stop, and the set of stop k stacks those of
    l ≤ k: the same constrained zonotope as ``joint_trajectory_set(system, joint_range, ys, k)``, bit
    for bit, without assembling the rows of times 0..k again for every k.

    Parameters
    ----------
    system : LinearSystem
    joint_range : JointRange
    ys : array_like, shape (T'+1, m)
    stops : sequence of int
        The last times k, each as ``stop`` of `joint_trajectory_set` (None: the last row of ``ys``).

    Returns
    -------
    list of ConvexSet
        ``⟦x_{0:k} | y_{0:k}⟧`` for k in ``stops``, in their order.

    Raises
    ------
    ValueError
        As `joint_trajectory_set`, for any of the stops.

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth.filters.optimal import joint_trajectory_sets
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> J = ss.JointRange.identical_process_noise(ss.Box([-5.0], [5.0]), box, box, T=2)
    >>> [Z.dim for Z in joint_trajectory_sets(system, J, [[0.0], [0.0], [0.0]], [0, 2])]
    [1, 3]
    """
    system, ys = measured(system, ys)
    stops = [_check(system, joint_range, ys, stop)[1] for stop in stops]
    return JointTrajectoryRows(system, joint_range, max(stops, default=0))._checked_sets(system, ys, stops)


class JointTrajectoryRows:
    """The rows of (★) of a system under a joint range for the times 0..last, before the data.

    Only the measurement rows' right-hand sides y_l − D_l c_{v_l} − C_l x̄_l (and their rounding
    bounds) depend on the measurements: the rows' entries, the nominal trajectory x̄, the dynamics
    rows and the rounding charges of B·G_J and D·G_J are computed once here, and `sets` completes
    them for a data set. Many data sets of one system and joint range (Monte Carlo runs) share one
    instance; `joint_trajectory_sets` makes one per call.

    Parameters
    ----------
    system : LinearSystem
    joint_range : JointRange
        With the system's n, p, q.
    last : int, optional
        The last time whose rows are prepared; defaults to the joint range's T.

    Raises
    ------
    ValueError
        When the joint range's n, p, q differ from the system's or ``last`` lies outside
        [0, joint_range.T].

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth.filters.optimal import JointTrajectoryRows
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> J = ss.JointRange.identical_process_noise(ss.Box([-5.0], [5.0]), box, box, T=2)
    >>> rows = JointTrajectoryRows(system, J)
    >>> [Z.dim for Z in rows.sets([[0.0], [0.0], [0.0]], [0, 2])], rows.sets([[0.5]], [0])[0].dim
    ([1, 3], 1)
    """

    def __init__(self, system, joint_range: JointRange, last: int | None = None):
        check_system(system)
        _check_joint(system, joint_range)
        last = joint_range.T if last is None else last
        if isinstance(last, bool) or not isinstance(last, (int, np.integer)) or not 0 <= last <= joint_range.T:
            raise ValueError(f"last must be an integer in [0, {joint_range.T}], got {last!r}")
        self.system, self.joint_range, self.last = system, joint_range, int(last)
        cz = joint_range.set._flat_cz
        self._rows = None if cz is None else _JointRows(system, joint_range, cz, self.last)

    def sets(self, ys: Any, stops) -> list[ConvexSet]:
        """``joint_trajectory_set(system, joint_range, ys, k)`` for every k in ``stops`` (k ≤ last):
        the same sets, bit for bit, from the prepared rows.

        Parameters
        ----------
        ys : array_like, shape (T'+1, m)
        stops : sequence of int
            As ``stop`` of `joint_trajectory_set` (None: the last row of ``ys``), at most ``last``.

        Returns
        -------
        list of ConvexSet

        Raises
        ------
        ValueError
            As `joint_trajectory_set`, or for a stop after ``last``.
        """
        system, ys = measured(self.system, ys)
        stops = [_check(system, self.joint_range, ys, stop)[1] for stop in stops]
        if max(stops, default=0) > self.last:
            raise ValueError(f"the rows are prepared up to k = {self.last}, got stops {stops}")
        return self._checked_sets(system, ys, stops)

    def _checked_sets(self, system, ys: np.ndarray, stops: list[int]) -> list[ConvexSet]:
        """`sets` on the system and measurements past the door (`measured`) and stops already
        checked (k ≤ last)."""
        if self._rows is None:
            return [_lazy(system, self.joint_range, ys, k) for k in stops]
        return self._rows.sets(ys, stops)


def optimal_filter(system, joint_range: JointRange, ys: Any, *, detect_empty: bool = True) -> SetEstimates:
    """The optimal posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, under a joint range (rethinking Theorem 1).

    Exact: ``posteriors[k]`` is the projection on x_k of `joint_trajectory_set` with stop = k.

    Parameters
    ----------
    system : LinearSystem
    joint_range : JointRange
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T (T ≤ the joint range's T).
    detect_empty : bool
        Return `EmptySet` from the first empty posterior on (the measurements contradict the joint
        range). Emptiness is monotone in k, so this is one feasibility program on the last posterior
        when the data are consistent.

    Returns
    -------
    SetEstimates
        Constrained zonotopes when the joint range flattens to one. Under
        `JointRange.unrelated` they equal `classical_filter`'s posteriors (Theorem 2); otherwise
        they are contained in them (Theorem 3).

    Raises
    ------
    ValueError
        As `joint_trajectory_set`.

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth.papers.rethinking_examples import (rethinking_example_30, rethinking_example_30_x0,
    ...                                                   rethinking_example_30_joint_range)
    >>> system, X0 = rethinking_example_30(), rethinking_example_30_x0()
    >>> ys = [[0.0], [0.5], [1.5], [3.0], [4.0]]
    >>> optimal = ss.optimal_filter(system, rethinking_example_30_joint_range(4), ys)
    >>> classical = ss.classical_filter(system, X0, ys)
    >>> round(optimal[4].area(), 3), round(classical[4].area(), 3)     # Theorem 3: optimal ⊆ classical
    (4.215, 5.375)
    """
    system, ys = measured(system, ys)
    _check(system, joint_range, ys, None)
    n = system.n
    steps = range(ys.shape[0])
    posteriors = [trajectories.project(range(k * n, (k + 1) * n))
                  for k, trajectories in zip(steps, joint_trajectory_sets(system, joint_range, ys, steps))]
    if detect_empty:
        first = _first_empty(posteriors)
        posteriors[first:] = [EmptySet(n) for _ in range(first, len(posteriors))]
    return SetEstimates(posteriors, system=system, ys=ys, kind="filtered")


def optimal_joint_smoother(system, joint_range: JointRange, ys: Any) -> SetEstimates:
    """The optimal smoothed ranges ⟦x_k | y_{0:T}⟧, k = 0..T, under a joint range.

    The projections on x_0..x_T of one set, `joint_trajectory_set` with stop = T (the smoothing paper's
    Theorem 1 with the joint range in place of unrelated noises).

    Parameters
    ----------
    system : LinearSystem
    joint_range : JointRange
    ys : array_like, shape (T+1, m)

    Returns
    -------
    SetEstimates
        Each inside the optimal posterior of the same k, equal to it at k = T; all empty when the data
        contradict the joint range.

    Raises
    ------
    ValueError
        As `joint_trajectory_set`.
    """
    check_system(system)
    trajectories = joint_trajectory_set(system, joint_range, ys)
    n = system.n
    steps = trajectories.dim // n
    sets = [EmptySet(n) for _ in range(steps)] if trajectories.is_empty() else \
        [trajectories.project(range(k * n, (k + 1) * n)) for k in range(steps)]
    return SetEstimates(sets, system=system, ys=ys, kind="smoothed")


def augment_identical_process_noise(system, X0: ConvexSet) -> tuple[LinearSystem, ConvexSet]:
    """Rethinking (33)–(35): the identical process noise w as extra states, x̄_k = [x_k; w].

        x̄_{k+1} = [[A, B], [0, I]] x̄_k,   y_k = [C, 0] x̄_k + D v_k,   ⟦x̄_0⟧ = ⟦x_0⟧ × ⟦w⟧.

    The classical filter of the augmented system (Corollary 1 with B = 0) is the optimal filter of
    Section IV-B; its posteriors projected on the first n coordinates are ⟦x_k | y_{0:k}⟧.

    Parameters
    ----------
    system : LinearSystem
        Time-invariant, without input; its W is ⟦w⟧ and V is ⟦v_k⟧.
    X0 : ConvexSet
        ⟦x_0⟧, of dimension n.

    Returns
    -------
    augmented : LinearSystem
        n + p states; its process-noise range is {0} (B = 0 of (35)).
    prior : ConvexSet
        ⟦x_0⟧ × ⟦w⟧.

    Raises
    ------
    ValueError
        When the system is time-varying or has an input, or X0 is not a set of dimension n.
    """
    if not isinstance(system, LinearSystem) or not system.is_time_invariant:
        raise ValueError("system must be a time-invariant LinearSystem without input u")
    _check_state_set(X0, "X0", system.n)
    n, p = system.n, system.p
    A = np.block([[system.A_at(0), system.E_at(0)], [np.zeros((p, n)), np.eye(p)]])
    C = np.hstack([system.C_at(0), np.zeros((system.m, p))])
    augmented = LinearSystem(A, None, C, E=np.zeros((n + p, 1)), F=system.F_at(0), W=Box([0.0], [0.0]),
                             V=system.V)
    return augmented, cartesian_product(X0, system.W)


def _check_joint(system, joint_range: JointRange) -> None:
    if not isinstance(joint_range, JointRange):
        raise TypeError(f"joint_range must be a JointRange, got {type(joint_range).__name__}")
    if (joint_range.n, joint_range.p, joint_range.q) != (system.n, system.p, system.q):
        raise ValueError(f"joint_range has (n, p, q) = {(joint_range.n, joint_range.p, joint_range.q)} but "
                         f"the system has {(system.n, system.p, system.q)}")


def _check(system, joint_range: JointRange, ys: Any, stop: int | None) -> tuple[np.ndarray, int]:
    _check_joint(system, joint_range)
    last = min(joint_range.T, ys.shape[0] - 1)
    if ys.shape[0] - 1 > joint_range.T:
        raise ValueError(f"ys has {ys.shape[0]} rows (T = {ys.shape[0] - 1}) but joint_range covers only "
                         f"k = 0..{joint_range.T}")
    stop = last if stop is None else stop
    if isinstance(stop, bool) or not isinstance(stop, (int, np.integer)) or not 0 <= stop <= last:
        raise ValueError(f"stop must be an integer in [0, {last}], got {stop!r}")
    return ys, int(stop)


def _rows(system, joint_range: JointRange, ys: np.ndarray, stop: int):
    """The rows of (★) in the variables (x_0..x_stop, ξ): M [x; ξ] = rhs (dense blocks, sparse result)."""
    n = system.n
    n_states = n * (stop + 1)
    width = n_states + joint_range.dim
    blocks, rhs = [], []

    def select(dims) -> sp.csr_matrix:
        dims = list(dims)
        return sp.csr_matrix((np.ones(len(dims)), (np.arange(len(dims)), dims)), shape=(len(dims), width))

    def state(l: int) -> sp.csr_matrix:
        return select(range(l * n, (l + 1) * n))

    shift = n_states
    blocks.append(state(0) - select(shift + i for i in joint_range.x0_dims()))
    rhs.append(np.zeros(n))
    for l in range(stop):
        blocks.append(state(l + 1) - system.A_at(l) @ state(l)
                      - system.E_at(l) @ select(shift + i for i in joint_range.w_dims(l)))
        rhs.append(system.input_term(l))
    for l in range(stop + 1):
        blocks.append(system.C_at(l) @ state(l) + system.F_at(l) @ select(shift + i for i in joint_range.v_dims(l)))
        rhs.append(ys[l])
    return sp.vstack(blocks).tocsr(), np.concatenate(rhs)


def _lazy(system, joint_range: JointRange, ys: np.ndarray, stop: int) -> ConvexSet:
    M, rhs = _rows(system, joint_range, ys, stop)
    n_states = system.n * (stop + 1)
    stacked = cartesian_product(Reals(n_states), joint_range.set)
    consistent = stacked.intersect_preimage(M.toarray(), Box(rhs, rhs))
    return consistent.project(range(n_states))


class _JointRows:
    """The rows of (★) for the times 0..last that do not depend on the data, and `sets`, which adds
    the measurements' right-hand sides and stacks the rows of the times 0..k for every stop k.

    Blocks, in the CZ's row order: x_0's rows, the dynamics of l = 0..last−1, the measurements of
    l = 0..last. Only the measurement rows' right-hand sides y_l − D_l c_{v_l} − C_l x̄_l and their
    rounding bounds depend on y; the entries, the nominal trajectory x̄, the dynamics rows' bounds
    and the charges of the products B·G_J, D·G_J do not, nor does any row depend on the stop. A
    block's entries are kept as (rows within the block, state columns, values) and (rows, η columns,
    values): the state columns of time l are l·n.. whatever the stop, the η columns follow the
    n(k+1) state columns of stop k."""

    def __init__(self, system, joint_range: JointRange, cz: ConstrainedZonotope, last: int):
        n = system.n
        G_J = sp.csr_matrix(cz.G)
        if not G_J.has_canonical_format:  # duplicate entries: summed once, for the rows and their charges alike
            G_J = G_J.copy()
            G_J.sum_duplicates()
        c_J = cz.c
        # Nominal trajectory x̄ (noises at the centre of J): the centre of the trajectory CZ.
        nominal = np.empty((last + 1, n))
        nominal[0] = c_J[list(joint_range.x0_dims())]
        for l in range(last):
            nominal[l + 1] = (system.A_at(l) @ nominal[l] + system.E_at(l) @ c_J[list(joint_range.w_dims(l))]
                              + system.input_term(l))

        def entries(block: np.ndarray, column: int):
            r, c = np.nonzero(block)
            return r, c + column, block[r, c]

        # The rows' rounding slack (as in `trajectories.sparse_cz._assemble`): J's own charges where its
        # coordinates enter a row, the nominal trajectory's rounding, and that of the products B·G_J,
        # D·G_J and of the measurement rows' right-hand sides.
        def charge(M, dims, G_dims):
            pad = None if cz.pad is None else cz.pad[dims]
            pad_free = None if cz.pad_free is None else cz.pad_free[dims]
            bounded, free = rounding.linear_image(M, G_dims, np.zeros(len(dims)), cz.h, pad, pad_free)
            zeros = np.zeros(M.shape[0])
            return (zeros if bounded is None else bounded), (zeros if free is None else free)

        x0 = list(joint_range.x0_dims())
        head = [(entries(np.eye(n), 0), entries(-G_J[x0].toarray(), 0), n)]   # (state, η entries, rows)
        residuals, charges = [], []
        for l in range(last):
            A_l, B_l, w = system.A_at(l), system.E_at(l), list(joint_range.w_dims(l))
            G_w = G_J[w]
            states = np.hstack([-np.asarray(A_l, dtype=float), np.eye(n)])   # x_l, x_{l+1}
            head.append((entries(states, n * l), entries(-_sparse_product(B_l, G_w.toarray()), 0), n))
            residuals.append([(A_l, nominal[l]), (B_l, c_J[w]), (np.ones(n), system.input_term(l)),
                              (-np.ones(n), nominal[l + 1])])
            charges.append(charge(B_l, w, G_w))
        # Dot2 bounds each row on its own (`rounding.residual_bounds`): the dynamics rows' now, the
        # measurement rows' with the data, bit for bit the bounds of all rows in one pass.
        self.head_slack = np.concatenate([rounding.zeros_or(None if cz.pad is None else cz.pad[x0], n),
                                          *(rounding.add(error, bounded) for error, (bounded, _) in
                                            zip(rounding.residual_bounds(residuals), charges))])
        self.head_slack_free = np.concatenate([
            rounding.zeros_or(None if cz.pad_free is None else cz.pad_free[x0], n),
            *(free for _, free in charges)])
        tail, self.measurements = [], []
        for l in range(last + 1):
            C_l, D_l, v = system.C_at(l), system.F_at(l), list(joint_range.v_dims(l))
            G_v = G_J[v]
            tail.append((entries(np.asarray(C_l, dtype=float), n * l),
                         entries(_sparse_product(D_l, G_v.toarray()), 0), C_l.shape[0]))
            self.measurements.append((C_l, D_l, c_J[v], charge(D_l, v, G_v)))
        self.n, self.nominal, self.nc, self.ng, self.h_J = n, nominal, cz.nc, cz.ng, cz.h
        self.runs = [self._run(head), self._run(tail)]
        self.J = sp.coo_matrix(cz.A)
        self.J_rows = (cz.b, rounding.zeros_or(cz.slack, cz.nc), rounding.zeros_or(cz.slack_free, cz.nc))

    @staticmethod
    def _run(blocks: list) -> dict:
        """A run of blocks as one array of entries (rows from the run's start, η columns from 0), with
        the counts of entries and rows up to every block: the stop k takes a prefix of the run."""
        sizes = np.array([rows for *_, rows in blocks])
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        parts = [(r + start, c, v, np.full(r.size, eta))
                 for block, start in zip(blocks, starts) for eta, (r, c, v) in enumerate(block[:2])]
        r, c, v, eta = (np.concatenate(part) for part in zip(*parts))
        return {"r": r, "c": c, "v": v, "eta": eta.astype(bool), "rows": np.cumsum(sizes),
                "entries": np.cumsum([state[0].size + eta[0].size for state, eta, _ in blocks])}

    def sets(self, ys: np.ndarray, stops) -> list[ConstrainedZonotope]:
        """The trajectory CZs of (★) for the data ``ys`` and every stop k ≤ last in ``stops``."""
        used = self.measurements[:max(stops, default=-1) + 1]   # the measurement rows of l ≤ max(stops)
        rhs = [ys[l] - D_l @ c_v - C_l @ self.nominal[l] for l, (C_l, D_l, c_v, _) in enumerate(used)]
        residuals = [[(np.ones(b.size), ys[l]), (-D_l, c_v), (-C_l, self.nominal[l]), (-np.ones(b.size), b)]
                     for l, ((C_l, D_l, c_v, _), b) in enumerate(zip(used, rhs))]
        slack = [rounding.add(error, bounded)
                 for error, (*_, (bounded, _)) in zip(rounding.residual_bounds(residuals), used)]
        tail_b, tail_slack = np.concatenate([np.zeros(0), *rhs]), np.concatenate([np.zeros(0), *slack])
        tail_slack_free = np.concatenate([np.zeros(0), *(free for *_, (_, free) in used)])
        return [self._trajectories(k, tail_b, tail_slack, tail_slack_free) for k in stops]

    def _trajectories(self, k: int, tail_b: np.ndarray, tail_slack: np.ndarray,
                      tail_slack_free: np.ndarray) -> ConstrainedZonotope:
        """The trajectory CZ with stop = k: J's own rows, then x_0's, the dynamics l < k and the
        measurements l ≤ k."""
        n = self.n
        n_states = n * (k + 1)
        head, tail = self.runs
        # the blocks of stop k: 1 + k of the first run (x_0, dynamics), k + 1 of the second
        head_rows, tail_rows = head["rows"][k], tail["rows"][k]
        row, r, c, v = self.nc, [self.J.row], [self.J.col + n_states], [self.J.data]
        for run in (head, tail):
            entries = run["entries"][k]
            r.append(run["r"][:entries] + row)
            c.append(run["c"][:entries] + n_states * run["eta"][:entries])
            v.append(run["v"][:entries])
            row += run["rows"][k]
        A = sp.csc_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))),
                          shape=(row, n_states + self.ng))
        A.eliminate_zeros()
        b_J, slack_J, slack_free_J = self.J_rows
        b = np.concatenate([b_J, np.zeros(head_rows), tail_b[:tail_rows]])
        slack = np.concatenate([slack_J, self.head_slack[:head_rows], tail_slack[:tail_rows]])
        slack_free = np.concatenate([slack_free_J, self.head_slack_free[:head_rows],
                                     tail_slack_free[:tail_rows]])
        G = sp.hstack([sp.identity(n_states, format="csc"), sp.csc_matrix((n_states, self.ng))]).tocsc()
        h = np.concatenate([np.full(n_states, np.inf), self.h_J])
        trajectories = ConstrainedZonotope._trusted(G, self.nominal[:k + 1].reshape(-1), A, b, h,
                                                    slack=slack, slack_free=slack_free)
        trajectories.factors  # created now, so that every projection shares one factor set
        return trajectories


def _sparse_product(M, X: np.ndarray) -> np.ndarray:
    """fl(M·X) as scipy's sparse product csr(M)·csr(X) forms it, on dense arrays: each entry the sum,
    from zero and in increasing j, of its terms M_ij·X_jk with both factors nonzero. (The skipped terms
    would add zeros: only a zero's sign could differ, and zeros are not stored.)"""
    M = np.asarray(M, dtype=float)
    out = np.zeros((M.shape[0], X.shape[1]))
    with np.errstate(invalid="ignore", over="ignore", under="ignore"):
        for j in range(M.shape[1]):
            m, x = M[:, j:j + 1], X[j:j + 1, :]
            out = out + np.where((m != 0) & (x != 0), m * x, 0.0)
    return out
