"""Interval propagation through Aξ = b (Scott et al. 2016 §4.1, CORA's 'iter'): the factor box E and
the propagated ranges R that `rescale.Rescale("iter")` and constraint elimination (§4.2) use.

[A b] is brought to reduced row-echelon form by Gauss–Jordan elimination with full pivoting
(`gauss_jordan`) and its rows scaled by their 1-norm, then one sweep E_j ← E_j ∩ (b_i − Σ_{l≠j}
A_il E_l)/A_ij over the rows i (`propagate`). Each row updates all its factors at once from the boxes
left by the previous rows. Few rows change the box, so rows are evaluated a stretch at a time against
it and kept up to the first that changes it: the same floats as row by row.

Soundness in floating point: the preconditioned rows are P·A and P·b evaluated in floating point, so
each row is treated as an interval equation whose coefficients carry the rounding bound γ·|P||A|, and
every interval sum and quotient is rounded outward: every computed E_j contains the exact range of
the data as stored (`rescale` says what is done with a crossed, i.e. empty, box).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ... import tolerances as tol
from ...floating import gamma
from ._base import round_down, round_up

__all__ = ["FactorBounds", "gauss_jordan", "propagate"]


def gauss_jordan(A: np.ndarray) -> np.ndarray:
    """A row transform P (rank × nc) with P·A in reduced row-echelon form, full pivoting.

    Pivots are the largest remaining entry in magnitude; elimination stops when it falls below
    ``RANK_TOL`` times the largest entry of A. Rows of P are scaled so that each row of P·A has
    1-norm one.
    """
    nc, ng = A.shape
    M = np.concatenate((A, np.eye(nc)), axis=1)
    # |entries| of the rows and columns still available; used ones are marked −1.
    free = np.abs(A)
    threshold = tol.RANK_TOL * free.max(initial=0.0)
    rows = []
    used_rows, used_cols = np.zeros(nc, dtype=bool), np.zeros(ng, dtype=bool)
    pivots = min(nc, ng)
    for step in range(pivots):
        i, j = divmod(int(free.argmax()), ng)
        if free[i, j] <= threshold:
            break
        M[i] /= M[i, j]
        factor = M[:, j].copy()
        factor[i] = 0.0
        M -= factor[:, None] * M[i]   # np.outer's products, without its argument handling
        rows.append(i)
        if step + 1 < pivots:         # no search follows the last pivot
            used_rows[i] = used_cols[j] = True
            free = np.abs(M[:, :ng])
            free[used_rows] = -1.0    # (two masks: cheaper than a row or column at a time)
            free[:, used_cols] = -1.0
    order = rows
    P = M[order, ng:]
    norms = np.abs(M[order, :ng]).sum(axis=1)
    return P / norms[:, None]


class FactorBounds(NamedTuple):
    """Factor ranges found by `propagate` (or by LPs in `Rescale('exact')`).

    Attributes
    ----------
    lo, hi : ndarray, shape (ng,)
        E = [lo, hi] ⊇ the range of every feasible ξ_j (⊆ [−h_j, h_j]).
    Rlo, Rhi : ndarray, shape (ng,) or None
        R = [Rlo, Rhi] ⊇ the range the rows imply for ξ_j from the other factors' boxes, before the
        intersection with its own bound (Scott et al. 2016 §4.2); None when not computed (LP bounds).
    crossed : bool
        Some E_j came out empty, which proves the stored data infeasible; the crossed bounds are
        then returned swapped (the caller settles emptiness with `is_empty`).
    """

    lo: np.ndarray
    hi: np.ndarray
    Rlo: np.ndarray | None
    Rhi: np.ndarray | None
    crossed: bool


def propagate(A: np.ndarray, b: np.ndarray, h: np.ndarray) -> FactorBounds:
    """One sweep of preconditioned interval propagation through Aξ = b, |ξ| ≤ h (Scott et al. 2016 §4.1).

    Parameters
    ----------
    A : ndarray, shape (nc, ng)
        Dense constraint matrix.
    b : ndarray, shape (nc,)
        Right-hand side.
    h : ndarray, shape (ng,)
        Factor bounds, ``inf`` for a free factor.

    Returns
    -------
    FactorBounds
        E = [lo, hi] and R = [Rlo, Rhi], rigorous in floating point for the data as stored (every
        interval operation rounded outward, the preconditioned rows carried as interval equations).

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth.sets.reduction import propagate
    >>> fb = propagate(np.array([[1.0, 1.0]]), np.array([1.5]), np.ones(2))
    >>> bool(fb.lo[0] <= 0.5 <= fb.lo[0] + 1e-12), bool(fb.Rhi[0] >= 2.5), fb.crossed
    (True, True, False)
    """
    nc, ng = A.shape
    lo, hi = -h.astype(float), h.astype(float)
    Rlo, Rhi = np.full(ng, -np.inf), np.full(ng, np.inf)
    if nc == 0:
        return FactorBounds(lo, hi, Rlo, Rhi, False)
    P = gauss_jordan(A)
    Ap, bp = P @ A, P @ b
    # fl(P·A) = P·A + E with |E| ≤ γ_nc |P||A| (and alike for b): each row is an interval equation
    # Σ_l [alo_l, ahi_l] ξ_l ∋ bp_i ± db_i.
    # The factor 2 covers the rounding of |P||A| itself; an exact zero stays zero.
    g = 2.0 * gamma(nc + 1)
    absP = np.abs(P)
    dA = g * (absP @ np.abs(A))
    db = g * (absP @ np.abs(b))
    # dA = 0 only where every term of the product was zero: that coefficient is exactly 0.
    exact = dA == 0.0
    Alo = np.where(exact, Ap, round_down(Ap - dA))
    Ahi = np.where(exact, Ap, round_up(Ap + dA))
    seen = (Alo != 0.0) | (Ahi != 0.0)   # the factors of each row, found for all rows at once
    every = seen.all(axis=1)             # a row that sees every factor works on whole arrays
    # A divisor interval containing 0 bounds nothing (`_rows`); decided for all rows at once.
    ok = (Alo > 0.0) | (Ahi < 0.0)
    bounds_all = (ok | ~seen).all(axis=1)
    sweep = _Sweep(Alo, Ahi, bp, db, ok, bounds_all, lo, hi, Rlo, Rhi)
    rows = Ap.shape[0]
    # Consecutive rows that see the same factors, [start, end) (a batch never crosses one's end).
    ends = np.concatenate(((seen[1:] != seen[:-1]).any(axis=1).nonzero()[0] + 1, [rows]))
    # Rows per batch: after a batch that stopped early, as many as it took (rows evaluated past the
    # stop are evaluated again); after one that did not, twice as many.
    limit = rows
    i = 0
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        while i < rows:
            # Whole rows instead of an index of every column: the same elements in the same order.
            cols = slice(None) if every[i] else seen[i].nonzero()[0]
            end = min(int(ends[ends.searchsorted(i, side="right")]), i + limit)
            done = sweep.batch(i, end, cols) if end - i > 1 else 0
            if done == 0:
                sweep.one(i, cols)
                done = 1
            limit = 2 * limit if i + done == end else done
            i += done
    return FactorBounds(lo, hi, Rlo, Rhi, sweep.crossed)


class _Sweep:
    """The sweep of `propagate` over the preconditioned rows, in order, on the arrays it updates in
    place (the box [lo, hi] and the ranges [Rlo, Rhi]).

    A row's ranges depend on the box left by the rows before it, and the box changes at few rows (a
    row seldom tightens a factor's bound): `batch` evaluates the rows of a stretch at once against the
    current box and keeps them up to the first row that changes it; `one` is a row by itself. Either
    gives the same floats as the rows one by one: the row formulas are the same element by element,
    and a batch's running maxima and minima of the ranges, and its comparisons with the box, see no
    zero or NaN range (a batch stops before one, and ranges holding one go row by row), so no ±0 tie
    can come out differently and a row that keeps the box keeps it bit for bit.
    """

    def __init__(self, Alo, Ahi, bp, db, ok, bounds_all, lo, hi, Rlo, Rhi):
        self.Alo, self.Ahi, self.bp, self.db, self.ok, self.bounds_all = Alo, Ahi, bp, db, ok, bounds_all
        self.lo, self.hi, self.Rlo, self.Rhi = lo, hi, Rlo, Rhi
        self.crossed = False

    def one(self, i: int, cols) -> None:
        """Row i by itself, on its factors ``cols``."""
        lo, hi, Rlo, Rhi = self.lo, self.hi, self.Rlo, self.Rhi
        xlo, xhi = lo[cols], hi[cols]
        qlo, qhi, _ = _rows(self.Alo[i, cols], self.Ahi[i, cols], xlo, xhi, self.bp[i], self.db[i],
                            None if self.bounds_all[i] else self.ok[i, cols])
        qlo = np.maximum(qlo, Rlo[cols])
        qhi = np.minimum(qhi, Rhi[cols])
        Rlo[cols], Rhi[cols] = qlo, qhi
        self._settle(cols, np.maximum(xlo, qlo), np.minimum(xhi, qhi))

    def _settle(self, cols, nlo, nhi) -> None:
        crossed = nlo > nhi
        if crossed.any():
            # Rigorous for the data as stored, but the data carry the rounding of the set algebra
            # that built them: a set that is a single point (extreme noise realizations) comes
            # out a hair empty. The caller decides (by the LP's emptiness policy); meanwhile the
            # crossed bounds are swapped, which keeps every estimate between them.
            self.crossed = True
            nlo[crossed], nhi[crossed] = nhi[crossed], nlo[crossed]
        self.lo[cols], self.hi[cols] = nlo, nhi

    def batch(self, i: int, end: int, cols) -> int:
        """Rows i..end−1, all seeing the factors ``cols``, at once against the current box.

        Returns how many rows were taken: those up to and including the first that changes the box,
        or up to the first whose floats it cannot vouch for (`_fine`), left to `one`.
        """
        xlo, xhi = self.lo[cols], self.hi[cols]
        Rlo, Rhi = self.Rlo[cols], self.Rhi[cols]
        if not (np.isfinite(xlo).all() and np.isfinite(xhi).all()):
            return 0   # an unbounded factor: its rows' sums are infinite, `one` counts them
        if not ((np.abs(Rlo) > 0.0).all() and (np.abs(Rhi) > 0.0).all()):
            return 0   # a zero (or NaN) range from a row done by itself: row by row from here
        rows = slice(i, end)
        qlo, qhi, finite = _rows(self.Alo[rows, cols], self.Ahi[rows, cols], xlo, xhi, self.bp[rows],
                                 self.db[rows], self.ok[rows, cols])
        fine = _fine(qlo, qhi, finite)
        taken = int(fine.argmin()) if not fine.all() else end - i
        if taken == 0:
            return 0
        # R after each row: the running max/min over the rows (no zero among them: no ±0 tie).
        Rlo = np.maximum.accumulate(np.vstack([Rlo, qlo[:taken]]), axis=0)[1:]
        Rhi = np.minimum.accumulate(np.vstack([Rhi, qhi[:taken]]), axis=0)[1:]
        changes = np.flatnonzero((Rlo > xlo).any(axis=1) | (Rhi < xhi).any(axis=1))
        if changes.size:
            taken = int(changes[0]) + 1
        self.Rlo[cols], self.Rhi[cols] = Rlo[taken - 1], Rhi[taken - 1]
        if changes.size:
            self._settle(cols, np.maximum(xlo, Rlo[taken - 1]), np.minimum(xhi, Rhi[taken - 1]))
        return taken


def _rows(alo, ahi, xlo, xhi, beta, dbeta, ok):
    """The range of each ξ_j implied by a row Σ_l [alo_l, ahi_l] ξ_l ∈ [β − dβ, β + dβ] and the other
    factors' boxes ξ_l ∈ [xlo_l, xhi_l], rounded outward; unbounded where ``ok`` is False (the divisor
    interval [alo_j, ahi_j] contains 0; None: every one excludes it).

    One row (``alo``, ``ahi``, ``ok`` of shape (k,), scalar ``beta``, ``dbeta``) or several against the
    same boxes (shape (r, k) and (r,)): the formula runs along the last axis, and every row's floats
    are those it gives by itself.

    Returns ``(qlo, qhi, finite)``; ``finite``: the row's sums are finite. A single row's infinite
    sums are counted here (`_others_with_infinities`); several rows' are left to that (`_fine`).
    """
    # C order (an index of columns gives F order): a sum along the rows of a C-ordered array is each
    # row's pairwise sum, that of its 1-D sum; along an F-ordered one it adds term by term.
    alo, ahi = np.ascontiguousarray(alo), np.ascontiguousarray(ahi)
    p1, p2, p3, p4 = alo * xlo, alo * xhi, ahi * xlo, ahi * xhi
    # fmin/fmax skip the NaN of 0·∞ (a zero coefficient endpoint against an unbounded box): the
    # other candidates then carry the bound, as the interval product requires.
    tlo = np.fmin(np.fmin(p1, p2), np.fmin(p3, p4))
    thi = np.fmax(np.fmax(p1, p2), np.fmax(p3, p4))
    slo, shi = tlo.sum(axis=-1), thi.sum(axis=-1)
    finite = np.isfinite(slo) & np.isfinite(shi)
    if tlo.ndim > 1 or finite:
        olo, ohi = slo[..., None] - tlo, shi[..., None] - thi
        mag = np.abs(tlo).sum(axis=-1) + np.abs(thi).sum(axis=-1)
    else:  # one row with infinite terms: they are counted, not subtracted
        olo, ohi, mag = _others_with_infinities(tlo, thi)
    # One bound for every rounding so far (products, sums, the subtraction of the own term, the two
    # operations below): γ_{k+4} times the magnitudes involved.
    err = (gamma(tlo.shape[-1] + 4) * (mag + np.abs(beta) + dbeta))[..., None]
    nlo = (beta - dbeta)[..., None] - ohi - err
    nhi = (beta + dbeta)[..., None] - olo + err
    q1, q2, q3, q4 = nlo / alo, nlo / ahi, nhi / alo, nhi / ahi
    qlo = round_down(np.fmin(np.fmin(q1, q2), np.fmin(q3, q4)))
    qhi = round_up(np.fmax(np.fmax(q1, q2), np.fmax(q3, q4)))
    if ok is not None:
        qlo, qhi = np.where(ok, qlo, -np.inf), np.where(ok, qhi, np.inf)
    return qlo, qhi, finite


def _fine(qlo, qhi, finite):
    """Rows of a batch (`_rows` on several) whose floats it vouches for, up to the first that is not:
    finite sums and a range holding no zero or NaN (whose sign `batch`'s running maxima might treat
    differently)."""
    fine = finite & (np.abs(qlo) > 0.0).all(axis=1) & (np.abs(qhi) > 0.0).all(axis=1)
    return np.logical_and.accumulate(fine)


def _others_with_infinities(tlo: np.ndarray, thi: np.ndarray):
    """Σ_{l≠j} [tlo_l, thi_l] for each j when some terms are infinite (counted, not subtracted)."""
    flo, fhi = np.isfinite(tlo), np.isfinite(thi)
    slo, shi = tlo[flo].sum(), thi[fhi].sum()
    nlo, nhi = np.count_nonzero(~flo), np.count_nonzero(~fhi)
    olo = np.where(flo, slo - np.where(flo, tlo, 0.0), slo)
    ohi = np.where(fhi, shi - np.where(fhi, thi, 0.0), shi)
    olo = np.where(nlo - (~flo) > 0, -np.inf, olo)
    ohi = np.where(nhi - (~fhi) > 0, np.inf, ohi)
    return olo, ohi, np.abs(tlo[flo]).sum() + np.abs(thi[fhi]).sum()
