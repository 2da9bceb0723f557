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
  and the row-at-once update is one vectorized operation; `propagation.propagate`). The propagated
  range R_j (before the intersection with E_j) is what constraint elimination (§4.2) uses.
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

import numpy as np

from ... import tolerances as tol
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..empty import EmptySet
from ..zonotope import Zonotope
from ...solvers import SolverError
from ._base import CZData, ReductionMethod, certified_margin, round_down, round_up
from .propagation import FactorBounds, propagate

__all__ = ["Rescale", "rescale_data"]


#: Smallest rescaled half-width of a factor, relative to its centre and former bound. The emptiness
#: programs accept data consistent to ``EMPTINESS_TOL`` in units of the factor bounds; a factor squeezed
#: below that (a point-like posterior, e.g. noises at their vertices) would turn the accepted
#: inconsistency of the data, and the rounding of b − A m, into a verdict of emptiness.
RESCALE_FLOOR = 10.0 * tol.EMPTINESS_TOL

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
