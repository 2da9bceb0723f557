"""Rescaling (Scott et al. 2016 §4.1): shrink each factor's box to the range the constraints allow.

For Z(G, c, A, b, h), every feasible factor vector ξ lies in a box E = [lo, hi] ⊆ [−h, h]; replacing
ξ_j = m_j + r_j ξ'_j with m = (lo + hi)/2, r = (hi − lo)/2 and |ξ'_j| ≤ 1 gives the same set,

    Z = Z(G diag(r), c + G m, A diag(r), b − A m, 1),

in the form Z(G, c, A, b, h) again. Two ways to find E:

* ``Rescale("iter")`` (CORA's 'iter'): interval propagation through Aξ = b. [A b] is first brought to
  reduced row-echelon form by Gauss–Jordan elimination with full pivoting and its rows scaled by their
  1-norm, then one sweep E_j ← E_j ∩ (b_i − Σ_{l≠j} A_il E_l)/A_ij over the rows i. Each row updates
  all its factors at once from the boxes left by the previous rows (CORA also updates factor by
  factor within a row; after the Gauss–Jordan step a row's pivot factor is the one it tightens most,
  and the row-at-once update is one vectorized operation). Few rows change the box, so rows are
  evaluated a stretch at a time against it and kept up to the first that changes it: the same
  floats as row by row. The propagated range R_j (before the intersection with E_j) is what
  constraint elimination (§4.2) uses.
* ``Rescale("exact")``: the tightest box, by 2·ng certified LPs on the CZ fast path.

Soundness in floating point: the preconditioned rows are P·A and P·b evaluated in floating point, so
each row is treated as an interval equation whose coefficients carry the rounding bound γ·|P||A|, and
every interval sum and quotient is rounded outward. Every computed E_j therefore contains the exact
range of the data as stored, and an empty E_j (lo > hi) proves those data infeasible. The data carry
the rounding of the set algebra that built them, though, and a set that is a single point comes out a
hair infeasible: the result is `EmptySet` only when the emptiness program (`is_empty`, the library's
tolerance policy) agrees, and otherwise the crossed bounds are kept as a (tiny) interval. Free factors
(h = ∞) take part exactly: they stay free unless the constraints bound them, in which case they
become bounded factors of the same set.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ... import tolerances as tol
from ...floating import gamma
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..empty import EmptySet
from ..zonotope import Zonotope
from ...solvers import SolverError
from ._base import CZData, ReductionMethod, certified_margin, round_down, round_up

__all__ = ["Rescale", "FactorBounds", "propagate", "rescale_data"]


#: Smallest rescaled half-width of a factor, relative to its centre and former bound. The emptiness
#: programs accept data consistent to ``EMPTINESS_TOL`` in units of the factor bounds; a factor squeezed
#: below that (a point-like posterior, e.g. noises at their vertices) would turn the accepted
#: inconsistency of the data, and the rounding of b − A m, into a verdict of emptiness.
RESCALE_FLOOR = 10.0 * tol.EMPTINESS_TOL

def gauss_jordan(A: np.ndarray) -> np.ndarray:
    """A row transform P (rank × nc) with P·A in reduced row-echelon form, full pivoting.

    Pivots are the largest remaining entry in magnitude; elimination stops when it falls below
    ``RANK_TOL`` times the largest entry of A. Rows of P are scaled so that each row of P·A has
    1-norm one.
    """
    nc, ng = A.shape
    M = np.hstack([A, np.eye(nc)])
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
    # A divisor interval containing 0 bounds nothing (`_row`); decided for all rows at once.
    ok = (Alo > 0.0) | (Ahi < 0.0)
    bounds_all = (ok | ~seen).all(axis=1)
    sweep = _Sweep(Alo, Ahi, bp, db, ok, bounds_all, lo, hi, Rlo, Rhi)
    rows = Ap.shape[0]
    # Consecutive rows that see the same factors, [start, end) (a batch never crosses one's end).
    ends = np.append(np.flatnonzero(np.any(seen[1:] != seen[:-1], axis=1)) + 1, rows)
    # Rows per batch: after a batch that stopped early, as many as it took (rows evaluated past the
    # stop are evaluated again); after one that did not, twice as many.
    limit = rows
    i = 0
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        while i < rows:
            # Whole rows instead of an index of every column: the same elements in the same order.
            cols = slice(None) if every[i] else seen[i].nonzero()[0]
            end = min(int(ends[np.searchsorted(ends, i, side="right")]), i + limit)
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
        qlo, qhi = _row(self.Alo[i, cols], self.Ahi[i, cols], xlo, xhi, self.bp[i], self.db[i],
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
        or up to the first that `_rows` leaves to `one` (unbounded sums, a zero or NaN range).
        """
        xlo, xhi = self.lo[cols], self.hi[cols]
        Rlo, Rhi = self.Rlo[cols], self.Rhi[cols]
        if not (np.isfinite(xlo).all() and np.isfinite(xhi).all()):
            return 0   # an unbounded factor: its rows' sums are infinite, `one` counts them
        if not ((np.abs(Rlo) > 0.0).all() and (np.abs(Rhi) > 0.0).all()):
            return 0   # a zero (or NaN) range from a row done by itself: row by row from here
        rows = slice(i, end)
        qlo, qhi, fine = _rows(self.Alo[rows, cols], self.Ahi[rows, cols], xlo, xhi, self.bp[rows],
                               self.db[rows], self.ok[rows, cols])
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


def _row(alo, ahi, xlo, xhi, beta, dbeta, ok=None):
    """The range of each ξ_j implied by one row Σ_l [alo_l, ahi_l] ξ_l ∈ [β − dβ, β + dβ] and the
    other factors' boxes ξ_l ∈ [xlo_l, xhi_l], rounded outward; unbounded where ``ok`` is False (the
    divisor interval [alo_j, ahi_j] contains 0; None: every one excludes it). `_rows` on one row.
    """
    qlo, qhi, _ = _rows(alo[None], ahi[None], xlo, xhi, np.array([beta]), np.array([dbeta]),
                        True if ok is None else ok[None])
    return qlo[0], qhi[0]


def _rows(alo, ahi, xlo, xhi, beta, dbeta, ok):
    """The ranges of `_row` for several rows at once (one per row of ``alo``, ``ahi``, ``ok``, entry
    of ``beta``, ``dbeta``) against the same boxes [xlo, xhi]; every row's floats are those the row
    gives by itself.

    Returns ``(qlo, qhi, fine)``; ``fine`` is False from a row on whose sums are not finite or whose
    range holds a zero or NaN (whose sign `batch`'s running maxima might treat differently): those
    rows are to be redone one by one. A single row's infinite sums are counted here
    (`_others_with_infinities`); several rows' are left to that.
    """
    # C order (an index of columns gives F order): a sum along the rows of a C-ordered array is each
    # row's pairwise sum, that of its 1-D sum; along an F-ordered one it adds term by term.
    alo, ahi = np.ascontiguousarray(alo), np.ascontiguousarray(ahi)
    p1, p2, p3, p4 = alo * xlo, alo * xhi, ahi * xlo, ahi * xhi
    # fmin/fmax skip the NaN of 0·∞ (a zero coefficient endpoint against an unbounded box): the
    # other candidates then carry the bound, as the interval product requires.
    tlo = np.fmin(np.fmin(p1, p2), np.fmin(p3, p4))
    thi = np.fmax(np.fmax(p1, p2), np.fmax(p3, p4))
    slo, shi = tlo.sum(axis=1), thi.sum(axis=1)
    finite = np.isfinite(slo) & np.isfinite(shi)
    if finite.all() or tlo.shape[0] > 1:
        olo, ohi = slo[:, None] - tlo, shi[:, None] - thi
        mag = np.abs(tlo).sum(axis=1) + np.abs(thi).sum(axis=1)
    else:  # one row with infinite terms: they are counted, not subtracted
        olo, ohi, m = _others_with_infinities(tlo[0], thi[0])
        olo, ohi, mag = olo[None], ohi[None], np.array([m])
    # One bound for every rounding so far (products, sums, the subtraction of the own term, the two
    # operations below): γ_{k+4} times the magnitudes involved.
    err = gamma(tlo.shape[1] + 4) * (mag + np.abs(beta) + dbeta)
    nlo = (beta - dbeta)[:, None] - ohi - err[:, None]
    nhi = (beta + dbeta)[:, None] - olo + err[:, None]
    q1, q2, q3, q4 = nlo / alo, nlo / ahi, nhi / alo, nhi / ahi
    qlo = np.where(ok, round_down(np.fmin(np.fmin(q1, q2), np.fmin(q3, q4))), -np.inf)
    qhi = np.where(ok, round_up(np.fmax(np.fmax(q1, q2), np.fmax(q3, q4))), np.inf)
    fine = finite & (np.abs(qlo) > 0.0).all(axis=1) & (np.abs(qhi) > 0.0).all(axis=1)
    return qlo, qhi, np.logical_and.accumulate(fine)


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


def rescale_data(d: CZData, lo: np.ndarray, hi: np.ndarray, floor: float = 0.0) -> CZData:
    """Z(G diag(r), c + G m, A diag(r), b − A m, 1) for factor boxes [lo, hi] (free where unbounded).

    Parameters
    ----------
    d : CZData
        The data Z(G, c, A, b, h).
    lo, hi : ndarray, shape (ng,)
        A box containing every feasible factor vector (e.g. `propagate`'s E); infinite entries leave
        the factor free (m_j = 0, r_j = 1, h_j = ∞).
    floor : float
        Smallest half-width relative to max(|m_j|, h_j) (0: none; see the notes).

    Returns
    -------
    CZData
        The rescaled data, bounds 1 (∞ for free factors).

    Notes
    -----
    Floating point: r is rounded up so that [m − r, m + r] ⊇ [lo, hi] exactly, so no feasible factor
    is lost. A factor pinned to a point (lo = hi) gets a zero column, which is what lets
    `EliminateConstraints` remove its constraints exactly; with ``floor`` > 0 every other factor keeps
    a half-width of at least ``floor · max(|m|, h)``, the slack that the emptiness tolerance and the
    re-centring's rounding need when bounds squeeze a factor nearly to a point (an outer widening of
    at most that relative size). `Rescale('exact')` (LP bounds) and the rescaling inside
    `EliminateConstraints` pass `RESCALE_FLOOR`; `Rescale('iter')` passes none, because the
    elimination that follows it in CORA's pipeline must see the propagated bounds as they are (with
    the floor, the CORA filter of `benchmarks/bench_reduction.py` was 2.7× looser at n = 20). The products G diag(r), A diag(r) and the re-centred data c + G m, b − A m are rounded to
    nearest: the result is the set of the data up to roundoff of those operations, i.e. within
    γ_{ng+1}·(|c| + |G||m|) of each centre coordinate and γ_{ng+1}·(|b| + |A||m|) of each right-hand
    side (Higham's bound), not a rigorous superset. Rounding margins here would be errors in an equality
    constraint, which a CZ cannot hold; the outer methods that end in a box (`Girard`, `Combastel`,
    `IntervalHull`) are rigorous for the data they receive.
    """
    bounded = np.isfinite(lo) & np.isfinite(hi)
    point = bounded & (lo == hi)
    with np.errstate(invalid="ignore"):  # ∞ − ∞ on free factors, masked by `bounded`
        m = np.where(bounded, np.where(point, lo, (lo + hi) / 2), 0.0)
        # r with [m − r, m + r] ⊇ [lo, hi] despite the rounding of m. A factor fixed to a point gets
        # an exactly zero column (so its constraints can be eliminated exactly); any other is kept
        # at least floor·max(|m|, h): bounds squeezed to within the solver's or the propagation's
        # accuracy would leave b − A m inconsistent and a flat but non-empty set read as empty.
        least = floor * np.maximum(np.abs(m), np.where(np.isfinite(d.h), d.h, 0.0))
        r = np.where(bounded, np.where(point, 0.0,
                                       np.maximum(round_up(np.maximum(hi - m, m - lo)), least)), 1.0)
    h = np.where(bounded, 1.0, np.inf)
    return CZData(d.G * r, d.c + d.G @ m, d.A * r, d.b - d.A @ m, h, d.sparse)


@dataclass(frozen=True)
class Rescale(ReductionMethod):
    """Rescale the factors to the range the constraints allow (Scott et al. 2016 §4.1). Exact.

    Parameters
    ----------
    method : {'iter', 'exact'}
        'iter': interval propagation through Aξ = b after full-pivoting Gauss–Jordan preconditioning
        of [A b] (CORA's ``rescale(·, 'iter')``); 'exact': the tightest factor box, 2·ng certified
        LPs on the fast path.

    Raises
    ------
    ValueError
        If ``method`` is not 'iter' or 'exact'.

    Notes
    -----
    The set is unchanged (up to the roundoff of the re-centring, see `rescale_data`); a factor whose
    propagated range is unbounded keeps its bound (a free factor
    stays free). An empty propagated range gives `EmptySet` when `is_empty` agrees (see the module notes).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.5])
    >>> R = ss.reduce(Z, ss.Rescale("iter"))
    >>> np.round(R.h, 6).tolist(), round(R.support([1.0, 0.0]), 6)
    ([1.0, 1.0], 1.0)
    """

    method: str = "iter"
    exact = True

    def __post_init__(self):
        if self.method not in ("iter", "exact"):
            raise ValueError(f"Rescale method must be 'iter' or 'exact', got {self.method!r}")

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        return Z  # no constraints: every factor already ranges over all of [−1, 1]

    def _on_box(self, B: Box) -> Box:
        return B

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        if Z.nc == 0:
            return Z
        d = CZData.of(Z)
        bounds = propagate(d.A, d.b, d.h) if self.method == "iter" else _exact_bounds(Z, d)
        if bounds.crossed and Z.is_empty():
            return EmptySet(Z.dim)
        floor = RESCALE_FLOOR if self.method == "exact" else 0.0
        return rescale_data(d, bounds.lo, bounds.hi, floor).to_set()


def _exact_bounds(Z: ConstrainedZonotope, d: CZData) -> FactorBounds:
    """The factor box by certified LPs: the interval hull of Z(I, 0, A, b, h), rounded outward.

    A factor whose LP the solver cannot settle (`SolverError`) keeps its interval-propagation bound,
    which is valid (and rigorous) but may be looser.
    """
    factors = ConstrainedZonotope._trusted(np.eye(Z.ng), np.zeros(Z.ng), Z.A, Z.b, Z.h)
    eye = np.eye(Z.ng)
    try:
        values = factors.support_many(np.vstack([eye, -eye]), certified=True)
    except SolverError:
        values = _one_by_one(factors, np.vstack([eye, -eye]))
    iter_lo, iter_hi, _, _, crossed = propagate(d.A, d.b, d.h)
    if np.isneginf(values).any():
        return FactorBounds(iter_lo, iter_hi, None, None, True)
    hi, lo = values[:Z.ng], -values[Z.ng:]
    # The weak-duality bound is itself evaluated in floating point: widen by its rounding bound.
    scale = 1.0 + np.abs(Z.b).max(initial=0.0) + np.max(Z.h[np.isfinite(Z.h)], initial=0.0)
    margin = certified_margin(Z.ng + Z.nc + 2, scale)
    with np.errstate(invalid="ignore"):
        lo = np.where(np.isnan(lo), iter_lo, np.maximum(iter_lo, round_down(lo - margin)))
        hi = np.where(np.isnan(hi), iter_hi, np.minimum(iter_hi, round_up(hi + margin)))
    crossed = crossed or bool(np.any(lo > hi))
    return FactorBounds(np.minimum(lo, hi), np.maximum(lo, hi), None, None, crossed)


def _one_by_one(S: ConstrainedZonotope, D: np.ndarray) -> np.ndarray:
    """Certified support values one direction at a time; NaN where the solver gives up."""
    out = np.full(D.shape[0], np.nan)
    for i, d in enumerate(D):
        try:
            out[i] = S.support_many(d[None, :], certified=True)[0]
        except SolverError:
            pass
    return out
