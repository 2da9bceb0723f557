"""Trajectory sets and the filtering map, one floor below filters and smoothers.

The set of all state trajectories x_i..x_k consistent with y_i..y_k from a prior Z at time i,

    ⟦x_{i:k} | Z, y_{i:k}⟧ = { (x_i, …, x_k) : x_i ∈ Z,  x_{l+1} = A_l x_l + B_l w_l + u_l,
                                               y_l = C_l x_l + D_l v_l,  w_l ∈ W,  v_l ∈ V },

is one sparse extended CZ (`trajectory_set`) when the prior, W and V flatten to CZs, and otherwise the
lazy `TrajectorySet` of `setsmooth.trajectories.generic_program` (one CVXPY problem over the stacked
trajectory, compiled once and shared by its projections). Two projections carry the theory:

* with i = 0 and Z = X0, its projection on x_l is the optimal smoothed range ⟦x_l | y_{0:k}⟧ (smoothing
  paper Theorem 1: the smoothed range is the set of x_l over all consistent trajectories);
* its projection on x_k is the filtering map F_{k,i}(Z) of the stability paper (7), the posterior at k
  of the classical filter started at i from the prior Z (`filtering_map`; in CZ form stability (22)–(23),
  here with the states kept as free factors instead of eliminated).

The states themselves are free factors (h = ∞) of the extended CZ (stability paper Definition 7), so
every constraint couples only neighbouring time steps: O(k − i) factors and sparse rows, instead of the
dense O((k − i)²) blocks of (23) that eliminating the states would create.

The states are written about the nominal trajectory x̄ (the noises at their centres: x̄_i = c_Z,
x̄_{l+1} = A_l x̄_l + B_l c_w + u_l), which becomes the CZ's centre: x_l = x̄_l + s_l. The LP then only
sees deviations of the noises' scale, however far the states are from the origin (an offset of 1e6 in
the states cost the solver 1e-3 of absolute accuracy when the states themselves were the factors).

Factors, in order: s_i..s_k (the state deviations, h = ∞), ξ_Z (the prior), ξ_{w,i..k−1} (W),
ξ_{v,i..k} (V). Rows: A_Z ξ_Z = b_Z, A_w ξ_{w,l} = b_w, A_v ξ_{v,l} = b_v, then::

    s_i − G_Z ξ_Z                       = 0
    s_{l+1} − A_l s_l − B_l G_w ξ_{w,l} = 0
    C_l s_l + D_l G_v ξ_{v,l}           = y_l − D_l c_v − C_l x̄_l
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from .._validation import check_system, measured
from ..sets.base import ConvexSet
from ..sets import rounding
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..solvers.factor_set import FactorConstraints
from .free_factor_bound import banded_free_factor_bound
from .generic_program import TrajectorySet

__all__ = ["trajectory_set", "filtering_map", "TrajectorySet"]


def trajectory_set(system, prior: ConvexSet, ys: Any, start: int = 0,
                   stop: int | None = None) -> ConstrainedZonotope | TrajectorySet:
    """The set of trajectories (x_start, …, x_stop) consistent with y_start..y_stop from ``prior``.

    Parameters
    ----------
    system : LinearSystem
        Any W and V (`ConvexSet`s). Time-varying matrices are read at the absolute times start..stop.
    prior : ConvexSet
        The prior range of x_start (⟦x_0⟧ = X0 when ``start`` = 0).
    ys : array_like, shape (T+1, m)
        Measurements indexed by absolute time: ``ys[l]`` = y_l. Rows before ``start`` and after
        ``stop`` are not used.
    start : int
        The first time i of the trajectories, 0 ≤ start ≤ T.
    stop : int, optional
        The last time k, start ≤ stop ≤ T; defaults to T.

    Returns
    -------
    ConstrainedZonotope or TrajectorySet
        Of dimension n(stop − start + 1); coordinates (l − start)·n .. (l − start + 1)·n − 1 hold x_l.
        A sparse CZ when prior, W and V flatten to CZs (all its projections share one factor set);
        otherwise a lazy `TrajectorySet` (all its projections share one compiled CVXPY problem).

    Raises
    ------
    ValueError
        If ``prior`` is not a ConvexSet of dimension n, or ``start``/``stop`` lie outside [0, T] or
        ``stop`` < ``start``.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> Z = ss.trajectory_set(system, ss.Box([-5.0], [5.0]), [[0.0], [0.5], [1.0]])
    >>> Z.dim
    3
    >>> round(Z.support([0.0, 0.0, 1.0]), 6)   # x_2 ≤ y_2 + 1
    2.0
    """
    system, ys = measured(system, ys)
    if not isinstance(prior, ConvexSet) or prior.dim != system.n:
        raise ValueError(f"prior must be a ConvexSet of dimension n = {system.n}, got "
                         f"{prior.dim if isinstance(prior, ConvexSet) else type(prior).__name__}")
    start, stop = _window(start, stop, ys.shape[0] - 1)
    if any(S._flat_cz is None for S in (prior, system.W, system.V)):
        return TrajectorySet(system, prior, ys, start, stop)
    return _assemble(system, prior.to_constrained_zonotope(), system.W.to_constrained_zonotope(),
                     system.V.to_constrained_zonotope(), ys, start, stop)


def filtering_map(system, prior: ConvexSet, ys: Any, i: int, k: int) -> ConvexSet:
    """F_{k,i}(prior): the posterior at time k of the classical filter started at time i from ``prior``.

    F_{k,i}(Z) = f_k ∘ … ∘ f_{i+1}(X_i(y_i) ∩ Z) for k > i and X_i(y_i) ∩ Z for k = i (stability paper
    (7)), where X_l(y_l) = {x : y_l − C_l x ∈ F_l V} and f_l(S) = X_l(y_l) ∩ (A_{l−1} S ⊕ E_{l−1} W ⊕
    B_{l−1} u_{l−1}). With ``prior`` = ⟦x_i | y_{0:i−1}⟧ it is the exact posterior ⟦x_k | y_{0:k}⟧; the OIT
    filters apply it to an outer bound of that prior. Computed as the projection on x_k of
    `trajectory_set` (the CZ of stability (22)–(23), with the states kept as free factors).

    Parameters
    ----------
    system : LinearSystem
    prior : ConvexSet
        Z, a range of x_i (before y_i is used).
    ys : array_like, shape (T+1, m)
        Measurements indexed by absolute time (``ys[l]`` = y_l); rows i..k are used.
    i, k : int
        Start and end times, 0 ≤ i ≤ k ≤ T.

    Returns
    -------
    ConvexSet
        F_{k,i}(prior), of dimension n (an extended CZ when prior, W and V flatten to CZs, otherwise a
        projection of a `TrajectorySet`; empty when the data contradict the prior).

    Raises
    ------
    ValueError
        As `trajectory_set`.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
    >>> F = ss.filtering_map(system, ss.Box([-5.0], [5.0]), [[0.0], [0.5], [1.0]], 1, 2)
    >>> hull = F.interval_hull()          # y_1 = 0.5 gives x_1 ∈ [−0.5, 1.5], then x_2 ∈ [0, 2]
    >>> (hull.lo.round(6) + 0.0).tolist(), (hull.hi.round(6) + 0.0).tolist()   # + 0.0: no −0.0
    ([0.0], [2.0])
    """
    check_system(system)
    traj = trajectory_set(system, prior, ys, i, k)
    n = system.n
    return traj.project(range(traj.dim - n, traj.dim))


def window_posterior(system, prior: ConstrainedZonotope, Zw: ConstrainedZonotope,
                     Zv: ConstrainedZonotope, ys: np.ndarray, i: int, k: int,
                     layout: "WindowLayout | None" = None) -> ConstrainedZonotope:
    """`filtering_map` F_{k,i}(prior) for trusted arguments (a checked system whose measurements
    ``ys`` are already as measured, the CZ forms of the prior and of W and V, 0 ≤ i ≤ k ≤ T): the
    trajectory CZ of times i..k with G selecting x_k, without projecting through a linear map.
    ``layout``: a `WindowLayout` of an earlier window with the same matrices, to reuse."""
    traj = _assemble(system, prior, Zw, Zv, ys, i, k, layout)
    n, p = system.n, traj.A.shape[1]
    first = (k - i) * n
    G = sp.csc_matrix((np.ones(n), (np.arange(n), np.arange(first, first + n))), shape=(n, p))
    return ConstrainedZonotope._trusted(G, traj.c[first:first + n].copy(), traj.A, traj.b, traj.h,
                                        traj.factors)


def _window(start: Any, stop: Any, T: int) -> tuple[int, int]:
    """Validated (start, stop) with 0 ≤ start ≤ stop ≤ T."""
    stop = T if stop is None else stop
    for name, value in (("start", start), ("stop", stop)):
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"{name} must be an integer time index, got {value!r}")
    if not 0 <= start <= stop <= T:
        raise ValueError(f"need 0 <= start <= stop <= T = {T} (the last row of ys), "
                         f"got start = {start}, stop = {stop}")
    return int(start), int(stop)


class _Triplets:
    """Nonzero (row, column, value) triplets of a sparse matrix, gathered block by block.

    The matrix is built once from the concatenated index arrays: assembling it from many small scipy
    blocks costs more than every LP that follows on short horizons.
    """

    def __init__(self) -> None:
        self.rows: list[np.ndarray] = []
        self.cols: list[np.ndarray] = []
        self.vals: list[np.ndarray] = []

    def put(self, row0: int, col0: int, M) -> None:
        """Place the nonzeros of ``M`` (dense or sparse) with its top-left corner at (row0, col0)."""
        if sp.issparse(M):
            M = sp.coo_matrix(M)
            keep = M.data != 0
            r, c, v = M.row[keep], M.col[keep], M.data[keep]
        else:
            M = np.asarray(M, dtype=float)
            r, c = np.nonzero(M)
            v = M[r, c]
        self.rows.append(r + row0)
        self.cols.append(c + col0)
        self.vals.append(v)

    def put_repeated(self, row0: int, col0: int, M, times: int, row_step: int, col_step: int) -> None:
        """Place ``M`` ``times`` times, shifted by (row_step, col_step) each time (block diagonal)."""
        if times == 0:
            return
        probe = _Triplets()
        probe.put(0, 0, M)
        r, c, v = probe.rows[0], probe.cols[0], probe.vals[0]
        shifts = np.arange(times)
        self.rows.append((r[None, :] + row0 + row_step * shifts[:, None]).ravel())
        self.cols.append((c[None, :] + col0 + col_step * shifts[:, None]).ravel())
        self.vals.append(np.tile(v, times))

    def put_blocks(self, row0: int, col0: int, blocks: np.ndarray, row_step: int, col_step: int) -> None:
        """Place the dense ``blocks[j]`` (an array of shape (k, r, c)) with its top-left corner at
        (row0 + j·row_step, col0 + j·col_step), j = 0..k−1 (a block diagonal of distinct blocks)."""
        j, r, c = np.nonzero(blocks)
        self.rows.append(r + row0 + row_step * j)
        self.cols.append(c + col0 + col_step * j)
        self.vals.append(blocks[j, r, c])

    def to_csc(self, shape: tuple[int, int]) -> sp.csc_matrix:
        rows = np.concatenate(self.rows) if self.rows else np.zeros(0, int)
        cols = np.concatenate(self.cols) if self.cols else np.zeros(0, int)
        vals = np.concatenate(self.vals) if self.vals else np.zeros(0)
        M = sp.coo_matrix((vals, (rows, cols)), shape=shape).tocsc()
        M.sum_duplicates()  # blocks never overlap; this puts the matrix in canonical (sorted) form
        return M


def _assemble(system, Z0: ConstrainedZonotope, Zw: ConstrainedZonotope, Zv: ConstrainedZonotope,
              ys: np.ndarray, start: int, stop: int, layout: "WindowLayout | None" = None
              ) -> ConstrainedZonotope:
    """The trajectory CZ over start..stop: `WindowLayout` (given, or made here) and `window_data`."""
    if layout is None:
        layout = WindowLayout(system, Z0, Zw, Zv, start, stop)
    c, b, h, slack, slack_free = window_data(system, Z0, Zw, Zv, ys, start, stop, layout)
    # The factor set is created now, so that every projection shares one.
    return ConstrainedZonotope._trusted(layout.G, c, layout.A, b, h,
                                        TrajectoryFactors(layout.A, b, h, slack, slack_free))


class WindowLayout:
    """What the trajectory CZ over start..stop (stability paper (22)–(23) with the states kept as
    free factors) takes from the matrices alone: the constraint matrix
    A, the generators G (selecting the states) and the rounding charges of the products E G_w and
    F G_v. The same for every window of one length when A, C, E, F do not vary and the prior's A and
    G are the same (`window_data` gives the rest).

    Columns: [states x_start..x_stop | the prior's factors | ξ_w per step | ξ_v per time]; rows: the
    prior's rows, the noises' rows, x_start − G_0 ξ_0 = 0 (states about the nominal trajectory), the
    dynamics, the measurements.
    """

    def __init__(self, system, Z0: ConstrainedZonotope, Zw: ConstrainedZonotope, Zv: ConstrainedZonotope,
                 start: int, stop: int):
        n, m = system.n, system.m
        steps = stop - start  # number of transitions
        # Column offsets of each factor group.
        n_states = n * (steps + 1)
        col_x0 = n_states
        col_w = col_x0 + Z0.ng
        col_v = col_w + steps * Zw.ng
        n_factors = col_v + (steps + 1) * Zv.ng

        A = _Triplets()
        row = 0
        # Constraints of the prior's and the noises' factor sets.
        A.put(row, col_x0, Z0.A)
        row += Z0.nc
        A.put_repeated(row, col_w, Zw.A, steps, Zw.nc, Zw.ng)
        row += steps * Zw.nc
        A.put_repeated(row, col_v, Zv.A, steps + 1, Zv.nc, Zv.ng)
        row += (steps + 1) * Zv.nc
        # x_start ∈ prior
        self.prior_row = row
        A.put(row, 0, np.eye(n))
        A.put(row, col_x0, -Z0.G)
        row += n
        Gw, Gv = _dense(Zw.G), _dense(Zv.G)
        # The matrices of every step (one array each, repeated where the system does not vary).
        self.As = np.array([system.A_at(k) for k in range(start, stop)]).reshape(steps, n, n)
        self.Bs = np.array([system.E_at(k) for k in range(start, stop)]).reshape(steps, n, Zw.c.size)
        self.Ds = np.array([system.F_at(k) for k in range(start, stop + 1)]).reshape(steps + 1, m, Zv.c.size)
        self.Cs = np.array([system.C_at(k) for k in range(start, stop + 1)]).reshape(steps + 1, m, n)
        # dynamics: x_{j+1} − A x_j − E G_w ξ_w − E e_w = A x̄_j + E c_w + u − x̄_{j+1}
        A.put_blocks(row, n, np.broadcast_to(np.eye(n), (steps, n, n)), n, n)
        A.put_blocks(row, 0, -self.As, n, n)
        A.put_blocks(row, col_w, -np.array([Bk @ Gw for Bk in self.Bs]).reshape(steps, n, Zw.ng), n, Zw.ng)
        row += steps * n
        # measurements
        A.put_blocks(row, 0, self.Cs, m, n)
        A.put_blocks(row, col_v, np.array([Dk @ Gv for Dk in self.Ds]), m, Zv.ng)
        row += (steps + 1) * m
        self.A = A.to_csc((row, n_factors))
        self.G = sp.csc_matrix((np.ones(n_states), (np.arange(n_states), np.arange(n_states))),
                               shape=(n_states, n_factors))
        # the products' charges, once per step where the system varies
        self.Bw = _step_charges(self.Bs, Gw, Zw, "E" in system.time_varying)
        self.Dv = _step_charges(self.Ds, Gv, Zv, "F" in system.time_varying)


def window_data(system, Z0: ConstrainedZonotope, Zw: ConstrainedZonotope, Zv: ConstrainedZonotope,
                ys: np.ndarray, start: int, stop: int, layout: WindowLayout, charged: bool = True
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """(c, b, h, slack, slack_free) of the trajectory CZ over start..stop on ``layout``: the nominal
    trajectory from the prior's centre (the CZ's centre), the right-hand sides, the factor bounds and
    the rows' rounding slack (`setsmooth.sets.rounding`; None for both without ``charged``: only
    certified bounds need them)."""
    n, m = system.n, system.m
    steps = stop - start
    n_states = n * (steps + 1)
    As, Bs, Cs, Ds = layout.As, layout.Bs, layout.Cs, layout.Ds
    rhs = [Z0.b, np.tile(Zw.b, steps), np.tile(Zv.b, steps + 1), np.zeros(n), np.zeros(steps * n)]
    nominal = np.empty((steps + 1, n))  # x̄_start..x̄_stop, the CZ's centre
    nominal[0] = Z0.c
    us = np.array([system.input_term(k) for k in range(start, stop)]).reshape(steps, n)
    for j in range(steps):
        nominal[j + 1] = As[j] @ nominal[j] + Bs[j] @ Zw.c + us[j]
    b_meas = np.array([ys[start + j] - Ds[j] @ Zv.c - Cs[j] @ nominal[j] for j in range(steps + 1)])
    b_meas = b_meas.reshape(steps + 1, m)
    rhs.append(b_meas.reshape(-1))
    b = np.concatenate(rhs)
    h = np.concatenate([np.full(n_states, np.inf), Z0.h, np.tile(Zw.h, steps), np.tile(Zv.h, steps + 1)])
    if not charged:
        return nominal.reshape(-1), b, h, None, None
    # The rows' rounding slack: the operands' own (their rows, and their pads where they enter a
    # row), the nominal trajectory's rounding, and the rounding of the products B G_w, D G_v and of
    # the measurement rows' right-hand sides.
    slack = [rounding.zeros_or(Z0.slack, Z0.nc), np.tile(rounding.zeros_or(Zw.slack, Zw.nc), steps),
             np.tile(rounding.zeros_or(Zv.slack, Zv.nc), steps + 1), rounding.zeros_or(Z0.pad, n)]
    # per unit of ‖ξ_F‖∞, where an operand's free columns were rounded (none in the estimators)
    slack_free = [rounding.zeros_or(Z0.slack_free, Z0.nc), np.tile(rounding.zeros_or(Zw.slack_free, Zw.nc), steps),
                  np.tile(rounding.zeros_or(Zv.slack_free, Zv.nc), steps + 1), rounding.zeros_or(Z0.pad_free, n)]
    # the nominal's error bounded as accurately as in twice the working precision: the residuals'
    # terms, row by row in the order of `rounding.residual_bound`'s pairs (all rows in one pass)
    dyn_terms = (np.concatenate([As, Bs, np.ones((steps, n, 1)), -np.ones((steps, n, 1))], axis=2),
                 np.concatenate([np.broadcast_to(nominal[:-1, None, :], (steps, n, n)),
                                 np.broadcast_to(Zw.c, (steps, n, Zw.c.size)), us[:, :, None],
                                 nominal[1:, :, None]], axis=2))
    meas_terms = (np.concatenate([np.ones((steps + 1, m, 1)), -Ds, -Cs, -np.ones((steps + 1, m, 1))],
                                 axis=2),
                  np.concatenate([ys[start:stop + 1, :, None],
                                  np.broadcast_to(Zv.c, (steps + 1, m, Zv.c.size)),
                                  np.broadcast_to(nominal[:, None, :], (steps + 1, m, n)),
                                  b_meas[:, :, None]], axis=2))
    errors = [rounding.row_sums_bound(X.reshape(-1, X.shape[2]), Y.reshape(-1, Y.shape[2]))
              for X, Y in (dyn_terms, meas_terms)]
    slack.append(rounding.add(errors[0], layout.Bw[0].reshape(-1)))
    slack.append(rounding.add(errors[1], layout.Dv[0].reshape(-1)))
    slack_free.extend([layout.Bw[1].reshape(-1), layout.Dv[1].reshape(-1)])
    return nominal.reshape(-1), b, h, np.concatenate(slack), np.concatenate(slack_free)


def _step_charges(Ms: np.ndarray, G: np.ndarray, Z: ConstrainedZonotope, varying: bool
                  ) -> tuple[np.ndarray, np.ndarray]:
    """`_product_charge` of every step's matrix ``Ms[j]``, computed once when the matrix does not
    vary: arrays of shape (steps, rows) each."""
    if not varying or Ms.shape[0] < 2:
        charge, free = _product_charge(Ms[0], G, Z) if Ms.shape[0] else (np.zeros(0), np.zeros(0))
        return (np.broadcast_to(charge, (Ms.shape[0], charge.size)),
                np.broadcast_to(free, (Ms.shape[0], free.size)))
    pairs = [_product_charge(M, G, Z) for M in Ms]
    return np.array([c for c, _ in pairs]), np.array([f for _, f in pairs])


def _product_charge(M: np.ndarray, G: np.ndarray, Z: ConstrainedZonotope
                    ) -> tuple[np.ndarray, np.ndarray]:
    """What the row M·(c + Gξ + e) loses to the rounding of M G and to Z's pad e (`linear_image`):
    Σ_j h_j |fl(M G)_j − (M G)_j| + |M| pad, and the part per unit of ‖ξ_F‖∞."""
    charge, free = rounding.linear_image(M, G, np.zeros(G.shape[0]), Z.h, Z.pad, Z.pad_free)
    return (np.zeros(M.shape[0]) if charge is None else charge,
            np.zeros(M.shape[0]) if free is None else free)


class TrajectoryFactors(FactorConstraints):
    """The factor set of a trajectory CZ: its free factors are the states, in time order.

    Every row couples neighbouring times only, so the states' Gram matrix A_FᵀA_F is banded and the
    bound on the free factors that certified support values need costs O(length) instead of the
    dense eigenvalue problem (`free_factor_bound`); the dense bound remains the fallback.
    """

    def free_bound(self) -> float | None:
        if self._free_bound is None:
            bound = banded_free_factor_bound(self.A, self.b, self.h, self.slack, self.slack_free)
            if bound is None:
                return super().free_bound()
            self._free_bound = (bound,)
        return self._free_bound[0]


def _dense(M) -> np.ndarray:
    return M.toarray() if sp.issparse(M) else np.asarray(M)
