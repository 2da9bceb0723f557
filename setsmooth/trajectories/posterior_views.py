"""The exact filter's posteriors as views of one trajectory set: O(T) memory for all of them (and the
smoothed ranges as its projections).

The posterior ⟦x_k | y_{0:k}⟧ is the last projection of the trajectories 0..k consistent with y_{0:k}
(stability paper (7), smoothing paper Theorem 1 with T = k). In the sparse trajectory CZ of
`setsmooth.trajectories` those trajectories are a *prefix* of the trajectories 0..T: the factors and
rows of times 0..k, in the same order. So the posteriors of one data set share one assembled
trajectory CZ, and each posterior is a `PosteriorView` that holds only its time k.

Why not the recursion's CZs (stability (20)–(21))? There the states are eliminated, and each
measurement row C_k G_k is dense over every earlier factor: O(k²) nonzeros per posterior, O(T³) memory
and time over a data set (2.9 GB and 0.3 s per step at T = 400 on example (31)). With the states kept as
free factors every row couples neighbouring times only: O(k) nonzeros per posterior, and the O(k)-sized
matrices of one posterior exist only while it is being queried (its prefix is cut out of the shared
trajectory CZ and kept in the bounded per-thread cache of `solvers.instances`).

The smoothed ranges ⟦x_k | y_{0:T}⟧ are the projections of the whole trajectory set on each x_k
(smoothing paper Theorem 1 and Corollary 1): `smoothed_ranges_from_trajectories`, for any
representation of it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..sets.base import ConvexSet
from ..sets.constrained_zonotope import ConstrainedZonotope
from ..solvers.instances import cached_instance
from .sparse_cz import TrajectoryFactors, _assemble

__all__ = ["PosteriorView", "posterior_views", "smoothed_ranges_from_trajectories"]


class _SharedTrajectories:
    """The trajectories 0..T of one data set (one sparse CZ) and the index layout of its prefixes."""

    def __init__(self, system, Z0: ConstrainedZonotope, Zw: ConstrainedZonotope,
                 Zv: ConstrainedZonotope, ys: np.ndarray):
        T = ys.shape[0] - 1
        self.n, self.T = system.n, T
        full = _assemble(system, Z0, Zw, Zv, ys, 0, T)
        self.A = sp.csc_matrix(full.A)  # canonical CSC: a prefix is cut by index arithmetic
        self.A.sort_indices()
        self.b, self.h, self.nominal = full.b, full.h, full.c.reshape(T + 1, system.n)
        # the rows' rounding slack (`setsmooth.sets.rounding`), and per unit of the free factors
        self.slack, self.slack_free = full.slack, full.slack_free
        n, m = system.n, system.m
        # The layout of `sparse_cz._assemble`: columns [states | ξ_Z | ξ_w,0..T−1 | ξ_v,0..T],
        # rows [A_Z | A_w × T | A_v × (T+1) | x_0 − G_Z ξ_Z | dynamics × T | measurements × (T+1)].
        col_x0 = n * (T + 1)
        col_w = col_x0 + Z0.ng
        col_v = col_w + T * Zw.ng
        row_w = Z0.nc
        row_v = row_w + T * Zw.nc
        row_x0 = row_v + (T + 1) * Zv.nc
        row_dyn = row_x0 + n
        row_meas = row_dyn + T * n
        # (start, length at k = 0, growth per step) of every block, in order.
        self._col_blocks = [(0, n, n), (col_x0, Z0.ng, 0), (col_w, 0, Zw.ng), (col_v, Zv.ng, Zv.ng)]
        self._row_blocks = [(0, row_w, 0), (row_w, 0, Zw.nc), (row_v, Zv.nc, Zv.nc), (row_x0, n, 0),
                            (row_dyn, 0, n), (row_meas, m, m)]

    @staticmethod
    def _indices(blocks: list, k: int) -> np.ndarray:
        return np.concatenate([np.arange(start, start + size + k * growth)
                               for start, size, growth in blocks])

    def _cut(self, k: int) -> tuple:
        """(A, b, h, slack, slack_free) of the trajectories 0..k: the rows and columns of times 0..k, in order.

        Cut from the CSC arrays directly (the kept columns' entries, those in kept rows renumbered):
        scipy's fancy indexing costs more than the posterior's own LPs on short horizons."""
        rows, cols = self._indices(self._row_blocks, k), self._indices(self._col_blocks, k)
        A = self.A
        new_row = np.full(A.shape[0], -1, dtype=np.int64)
        new_row[rows] = np.arange(rows.size)
        starts, counts = A.indptr[cols], np.diff(A.indptr)[cols]
        offsets = np.zeros(cols.size + 1, dtype=np.int64)
        np.cumsum(counts, out=offsets[1:])
        entries = np.arange(int(offsets[-1])) + np.repeat(starts - offsets[:-1], counts)
        renumbered = new_row[A.indices[entries]]
        kept = renumbered >= 0
        column = np.repeat(np.arange(cols.size), counts)
        indptr = np.zeros(cols.size + 1, dtype=np.int64)
        np.cumsum(np.bincount(column[kept], minlength=cols.size), out=indptr[1:])
        itype = np.int32 if max(rows.size, int(indptr[-1])) < np.iinfo(np.int32).max else np.int64
        cut = sp.csc_matrix((A.data[entries[kept]], renumbered[kept].astype(itype),
                             indptr.astype(itype)), shape=(rows.size, cols.size))
        cut.has_sorted_indices = True  # rows keep their order, so each column stays sorted
        return (cut, self.b[rows], self.h[cols], None if self.slack is None else self.slack[rows],
                None if self.slack_free is None else self.slack_free[rows])

    def trajectories(self, k: int) -> ConstrainedZonotope:
        """The trajectory CZ over 0..k: exactly `sparse_cz._assemble` over 0..k, cut out."""
        A, b, h, slack, slack_free = self._cut(k)
        n_states = self.n * (k + 1)
        G = sp.csc_matrix((np.ones(n_states), (np.arange(n_states), np.arange(n_states))),
                          shape=(n_states, A.shape[1]))
        return ConstrainedZonotope._trusted(G, self.nominal[: k + 1].reshape(-1), A, b, h,
                                            TrajectoryFactors(A, b, h, slack, slack_free))

    def posterior(self, k: int) -> ConstrainedZonotope:
        """⟦x_k | y_{0:k}⟧: the projection on x_k of the trajectories 0..k (G selects the states
        of time k, the last n factors of the states' block)."""
        A, b, h, slack, slack_free = self._cut(k)
        n = self.n
        itype = np.int32 if A.shape[1] < np.iinfo(np.int32).max else np.int64
        indptr = np.zeros(A.shape[1] + 1, dtype=itype)
        indptr[k * n + 1:] = np.minimum(np.arange(1, A.shape[1] - k * n + 1), n)
        G = sp.csc_matrix((np.ones(n), np.arange(n, dtype=itype), indptr), shape=(n, A.shape[1]))
        return ConstrainedZonotope._trusted(G, self.nominal[k].copy(), A, b, h,
                                            TrajectoryFactors(A, b, h, slack, slack_free))


class PosteriorView(ConstrainedZonotope):
    """⟦x_k | y_{0:k}⟧ of the exact filter as a view of the data set's shared trajectory CZ.

    A `ConstrainedZonotope` (the projection on x_k of the trajectories 0..k; the states are free
    factors) whose matrices are cut out of the shared trajectory CZ when the set is queried and kept
    only in the bounded per-thread cache of `solvers.instances`: a list of T posteriors holds O(T)
    memory, not O(T²). Immutable and picklable like every set; answers are those of the materialized
    CZ (certified support values included).

    Parameters
    ----------
    shared : _SharedTrajectories
        The data set's trajectories 0..T (made by `posterior_views`).
    k : int
        The time of the posterior.
    """

    def __init__(self, shared: _SharedTrajectories, k: int):
        self._shared, self.k = shared, int(k)
        self.dim = shared.n

    def _materialized(self) -> ConstrainedZonotope:
        return cached_instance(self, "posterior", lambda: self._shared.posterior(self.k))

    # The representation, read through the materialized CZ (never stored on the view).
    G = property(lambda self: self._materialized().G)
    c = property(lambda self: self._materialized().c)
    A = property(lambda self: self._materialized().A)
    b = property(lambda self: self._materialized().b)
    h = property(lambda self: self._materialized().h)
    _factors = property(lambda self: self._materialized().factors)
    pad = property(lambda self: self._materialized().pad)
    _pad_box = property(lambda self: self._materialized()._pad_box)
    _pad_generators = property(lambda self: self._materialized()._pad_generators)
    pad_free = property(lambda self: self._materialized().pad_free)
    _slack = property(lambda self: self._materialized().slack)
    _slack_free = property(lambda self: self._materialized().slack_free)
    factors = property(lambda self: self._materialized().factors)
    _program = property(lambda self: self._materialized()._program)

    def __repr__(self) -> str:
        return f"PosteriorView(k={self.k}, dim={self.dim})"


def posterior_views(system, X0: ConstrainedZonotope, ys: np.ndarray) -> list[PosteriorView]:
    """The exact posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, as views of one trajectory CZ.

    Parameters
    ----------
    system : LinearSystem
        W and V flatten to constrained zonotopes.
    X0 : ConvexSet
        Flattens to a constrained zonotope.
    ys : ndarray, shape (T+1, m)
        Validated measurements.

    Returns
    -------
    list of PosteriorView
    """
    shared = _SharedTrajectories(system, X0.to_constrained_zonotope(), system.W.to_constrained_zonotope(),
                                 system.V.to_constrained_zonotope(), ys)
    return [PosteriorView(shared, k) for k in range(ys.shape[0])]


def smoothed_ranges_from_trajectories(trajectories: ConvexSet, n: int) -> list[ConvexSet]:
    """Project the trajectory set onto each x_k: ⟦x_k | y_{0:T}⟧ = π_k(⟦x_{0:T} | y_{0:T}⟧)."""
    T = trajectories.dim // n - 1
    return [trajectories.project(range(k * n, (k + 1) * n)) for k in range(T + 1)]
