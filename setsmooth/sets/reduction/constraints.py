"""Constraint elimination (Scott et al. 2016 §4.2): fewer equality constraints, an outer CZ.

Eliminating factor j through a constraint row i with a_ij ≠ 0 solves that row for
ξ_j = (b_i − Σ_{l≠j} a_il ξ_l)/a_ij and substitutes it (Scott (27) with Λ_G = G E_ji / a_ij,
Λ_A = A E_ji / a_ij, (29)):

    Z(G − Λ_G A, c + Λ_G b, A − Λ_A A, b − Λ_A b)   with row i and column j removed.

This drops one constraint and one factor, and only loses the bound |ξ_j| ≤ h_j. So it is exact when
that bound is implied by the others: for a free factor (h_j = ∞), and for a factor whose propagated
range R_j (`propagation.propagate`) lies inside its bound. Otherwise it is an outer approximation, and
the factor to give up is the one of smallest Hausdorff-error heuristic (Scott (A.8)): with
r_j = max(0, max|R_j| − 1) after rescaling, the least-squares displacement δ with Aδ = 0, δ_j = r_j,
minimizing ‖Gδ‖² + ‖δ‖², i.e. the KKT system [[GᵀG + I, Aᵀ], [A, 0]]; its value is r_j² / M_jj with
M = [[GᵀG + I, Aᵀ], [A, 0]]⁻¹.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...floating import gamma
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..cz_vertices import row_basis
from ..empty import EmptySet
from ..zonotope import Zonotope
from ._base import CZData, ReductionMethod
from .exact import DropDependentConstraints, DropZeros
from .propagation import propagate
from .rescale import RESCALE_FLOOR, rescale_data
from ...solvers import SolverError

__all__ = ["EliminateConstraints", "eliminate_factor"]


def eliminate_factor(d: CZData, j: int) -> CZData:
    """Scott et al. 2016 (27)/(29): drop the bound of factor j and eliminate it through a row where it
    appears.

    The row is the one where |a_ij| is largest relative to the row's size: any row gives the same set
    in exact arithmetic (CORA takes the first), this one is the best-conditioned pivot.

    Parameters
    ----------
    d : CZData
        The data Z(G, c, A, b, h), dense.
    j : int
        The factor to eliminate; column j of A must be non-zero.

    Returns
    -------
    CZData
        One factor and one constraint fewer: Z(G − Λ_G A, c + Λ_G b, A − Λ_A A, b − Λ_A b) with row i
        and column j removed (and any row that cancels to 0 = 0, i.e. was dependent on row i). It
        contains Z (exactly Z when the bound |ξ_j| ≤ h_j is implied).

    Notes
    -----
    Floating point: the substitution is evaluated rounded to nearest. The result is the set of the
    substituted data in exact arithmetic, so in floating point it contains Z only up to the roundoff
    of the rank-one updates: within γ_3·(|G_kl| + |g_kj||a_il/a_ij|) per entry of G and A, and alike
    for c and b; entries of A and b within twice that bound are set to zero (cancellation noise of a
    dependent row) (a rigorous margin would be an error in an equality constraint, which a CZ cannot
    hold). The final box of `Girard`/`Combastel`/`IntervalHull` is rigorous for the data it receives.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> from setsmooth.sets.reduction._base import CZData
    >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[0.0], h=[1.0, np.inf])
    >>> out = eliminate_factor(CZData.of(Z), 1)
    >>> out.to_set(), out.G.tolist(), out.c.tolist()
    (ConstrainedZonotope(dim=2, ng=1, nc=0), [[1.0], [-1.0]], [0.0, 0.0])
    """
    col = d.A[:, j]
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(col) / np.abs(d.A).max(axis=1)
    # |a_ij| never exceeds its row's largest entry: the quotient is finite or 0/0 (a zero row).
    rel[np.isnan(rel)] = 0.0
    i = int(rel.argmax())
    a = d.A[i, j]
    row_A, row_b = d.A[i] / a, d.b[i] / a
    # Rank-one updates as broadcast products (np.outer's, without its argument handling).
    G = d.G - d.G[:, j, None] * row_A
    c = d.c + d.G[:, j] * row_b
    update_A, update_b = col[:, None] * row_A, col * row_b
    A = d.A - update_A
    b = d.b - update_b
    # A row dependent on row i cancels to rounding noise (~1e-16 entries), which propagation would
    # take literally once the row is normalized: an entry within the rounding bound of its own
    # computation (γ_3: the division, the product, the subtraction) is zero up to roundoff.
    g = 2.0 * gamma(3)
    A[np.abs(A) <= g * (np.abs(d.A) + np.abs(update_A))] = 0.0
    b[np.abs(b) <= g * (np.abs(d.b) + np.abs(update_b))] = 0.0
    keep_rows = np.arange(d.nc) != i
    # A row that cancelled completely (0 = 0) is dropped with row i.
    keep_rows &= np.any(A != 0.0, axis=1) | (b != 0.0)
    keep_cols = np.arange(d.ng) != j
    return CZData(G[:, keep_cols], c, A[np.ix_(keep_rows, keep_cols)], b[keep_rows], d.h[keep_cols],
                  d.sparse)


def hausdorff_heuristic(d: CZData, r: np.ndarray) -> np.ndarray:
    """Scott (A.8): r_j² / M_jj, the least ‖Gδ‖² + ‖δ‖² over Aδ = 0 with δ_j = r_j (∞ where r_j = ∞)."""
    ng, nc = d.ng, d.nc
    # The KKT matrix [[GᵀG + I, Aᵀ], [A, 0]] and the right-hand side [I; 0], filled in place.
    Q = np.zeros((ng + nc, ng + nc))
    Q[:ng, :ng] = d.G.T @ d.G + np.eye(ng)
    Q[:ng, ng:] = d.A.T
    Q[ng:, :ng] = d.A
    rhs = np.eye(ng + nc, ng)
    try:
        M = np.linalg.solve(Q, rhs)
    except np.linalg.LinAlgError:  # A of numerically deficient rank: the least-squares solution
        M = np.linalg.lstsq(Q, rhs, rcond=None)[0]
    diag = np.diag(M[:ng])
    with np.errstate(invalid="ignore", divide="ignore"):
        H = np.where(r == 0.0, 0.0, r ** 2 / diag)
    return np.where(np.isfinite(r), H, np.inf)


@dataclass(frozen=True)
class EliminateConstraints(ReductionMethod):
    """Reduce a CZ to at most ``max_constraints`` equality constraints (Scott et al. 2016 §4.2). Outer.

    First, exactly: zero and dependent rows are dropped and free factors (h = ∞) that appear in a
    constraint are eliminated. Then, one factor at a time: rescale (`Rescale('iter')`); if some
    factor's propagated range lies inside its bound, eliminate it (exact, taken even below the count
    asked for); otherwise, while more than ``max_constraints`` rows remain, eliminate the factor of
    smallest Hausdorff-error heuristic (A.8) through a row where it appears (eqs. (27)/(29)). The
    result contains the input.

    Parameters
    ----------
    max_constraints : int
        The largest number of constraints the result may keep (≥ 0).

    Raises
    ------
    TypeError
        If ``max_constraints`` is not an integer (a bool or a float is refused).
    ValueError
        If ``max_constraints`` < 0.

    Notes
    -----
    Each step begins with the propagation and rescaling of `Rescale('iter')`. A ``Rescale('iter')``
    placed right before this method in a sequence (as in `CORA_GIRARD`) is still applied
    (`apply_methods` applies every method): on its rescaled data the propagated ranges lie inside the
    factors' bounds, which lets the elimination be exact.
    Floating point: the bounds are rigorous; the substitutions are exact up to the roundoff of the
    data (see `eliminate_factor`).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.ConstrainedZonotope(np.eye(3), np.zeros(3), A=[[1.0, 1.0, 0.0], [0.0, 1.0, 1.0]], b=[0.5, 0.2])
    >>> ss.reduce(Z, ss.EliminateConstraints(1)).nc <= 1
    True
    """

    max_constraints: int = 1

    def __post_init__(self):
        k = self.max_constraints
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise TypeError(f"max_constraints must be an integer ≥ 0, got {k!r} "
                            f"({type(k).__name__})")
        if k < 0:
            raise ValueError(f"max_constraints must be an integer ≥ 0, got {k!r}")

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        return Z  # no constraints

    def _on_box(self, B: Box) -> Box:
        return B

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        S = DropDependentConstraints().apply(DropZeros().apply(Z))
        if isinstance(S, EmptySet) or S.nc == 0:
            return S
        d = CZData.of(S)
        original = _Emptiness(S)
        # Free factors in a constraint: their elimination loses nothing.
        while True:
            free = np.flatnonzero(np.isinf(d.h) & np.any(d.A != 0.0, axis=0))
            if free.size == 0:
                break
            d = eliminate_factor(d, int(free[0]))
        while d.nc:
            step = _rescaled(d, original)
            if step is None:
                return EmptySet(Z.dim)
            d, r, inside = step
            used = np.any(d.A != 0.0, axis=0)
            exact = np.flatnonzero(inside & used)
            if exact.size:  # lossless: always taken, also below the count asked for
                d = eliminate_factor(d, int(exact[0]))
                continue
            if d.nc <= self.max_constraints:
                break
            # Only a factor that appears in a constraint can be eliminated (one always does: rows
            # are independent, hence non-zero).
            candidates = np.flatnonzero(used)
            H = hausdorff_heuristic(d, r)[candidates]
            d = eliminate_factor(d, int(candidates[np.argmin(H)]))
        return DropZeros().apply(d.to_set())


def _rescaled(d: CZData, original: "_Emptiness"):
    """Propagate, rescale to the propagated box, and keep independent rows.

    ``original`` settles emptiness: that of the set the method was given, never that of the
    re-parametrized data ``d``, whose eliminations and re-centrings may have made a flat, non-empty
    set a hair infeasible (a reduction may only return `EmptySet` for an empty input).

    Returns ``(data, r, inside)`` or None when the set is proven empty. ``inside[j]``: the
    propagated range R_j lies inside factor j's bound (compared on outward-rounded bounds, so it is
    never claimed wrongly), which makes eliminating j exact. ``r[j] = max(0, max|R_j| − 1)`` in the
    rescaled coordinates, the measure of the heuristic (A.8); ∞ for a free factor.
    """
    lo, hi, Rlo, Rhi, crossed = propagate(d.A, d.b, d.h)  # FactorBounds
    if crossed and original.proven():
        return None
    out = rescale_data(d, lo, hi, RESCALE_FLOOR)
    bounded = np.isfinite(lo) & np.isfinite(hi)
    inside = bounded & (Rlo >= -d.h) & (Rhi <= d.h)
    with np.errstate(invalid="ignore", divide="ignore"):  # ∞ − ∞ on free factors, masked
        m = np.where(bounded, (lo + hi) / 2, 0.0)
        half = np.where(bounded, (hi - lo) / 2, 1.0)
        reach = np.maximum(np.abs(Rlo - m), np.abs(Rhi - m)) / half
    r = np.where(inside | (half == 0.0), 0.0, np.where(bounded, np.maximum(0.0, reach - 1.0), np.inf))
    if not np.any(bounded & (lo == hi)):
        return out, r, inside  # columns scaled by r > 0: the rank is unchanged
    # A factor pinned to a point has a zero column now, which can leave rows dependent; the
    # heuristic's KKT matrix needs A of full row rank. Dropping a dependent row loses nothing.
    # A dependent row that disagrees is roundoff of the re-centring b − A m (a pinned factor leaves a
    # point-like set, where that roundoff is all there is): emptiness is judged on the data before
    # rescaling, which the rescaled data re-parametrize.
    basis = row_basis(out.A, out.b)   # linalg.independent_rows' answer
    if not basis.consistent and original.proven():
        return None
    return out.keep_rows(basis.keep), r, inside


class _Emptiness:
    """Whether the set a reduction was given is empty, decided once and only when asked.

    Asked only where propagation found the data a hair infeasible, which happens for point-like
    sets (extreme noise realizations) whose emptiness program is degenerate. A `SolverError` counts
    as non-empty: not declaring the set empty keeps a superset, and the caller goes on as for a set
    `is_empty` calls non-empty.
    """

    def __init__(self, S: ConstrainedZonotope):
        self._set = S
        self._verdict: bool | None = None

    def proven(self) -> bool:
        if self._verdict is None:
            try:
                self._verdict = bool(self._set.is_empty())
            except SolverError:
                self._verdict = False
        return self._verdict
