"""Support values certified in floating point: weak-duality bounds with rigorous rounding terms.

For the factor set F = {ξ : Aξ = b, |ξ_j| ≤ h_j} and any multiplier λ, weak duality gives

    max{gᵀξ : ξ ∈ F} = max{bᵀλ + (g − Aᵀλ)ᵀξ : ξ ∈ F} ≤ bᵀλ + Σ_j h_j |(g − Aᵀλ)_j|,

so h_Z(d) ≤ dᵀc + bᵀλ + Σ_j h_j |r_j| with r = Gᵀd − Aᵀλ, whatever λ the solver returned. Two things
stand between this and a number that is an upper bound in floating point:

* **free factors** (h_j = ∞): the bound is finite only if r_j = 0 there, which no computed λ achieves
  exactly. λ is first corrected by a least-squares step so that A_Fᵀλ ≈ g_F to rounding, and the
  remaining residual is charged against a rigorous bound ‖ξ_F‖∞ ≤ β: when the free factors are
  determined by the bounded ones (A_F has full column rank, as the trajectory set's states are),
  ‖ξ_F‖₂ ≤ ‖ |b_R| + |A_RB| h_B ‖₂ / σ_min(A_F) over the rows R that see a free factor. Without
  such a bound the value is uncertifiable and `SolverError('UncertifiableReducedCost')` is raised.
* **rounding**: every computed sum s̃ of N products obeys |s̃ − s| ≤ γ_N Σ|terms| with
  γ_N = N·u/(1 − N·u) (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.1); the bound adds
  these terms, computed from absolute values, and is finally rounded upward.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import lsqr, splu

from ..floating import ETA, U, gamma
from .clarabel_lp import SolverError
from .presolved import CompiledProduct, compiled
from .small_products import SmallProduct

__all__ = ["free_factor_bound", "normal_solver", "correct_multipliers", "certified_bound",
           "FREE_BOUND_DENSE_MAX", "Operators"]

#: The bound on the free factors needs the smallest singular value of A_F, computed densely (an
#: eigenvalue problem of the nF × nF Gram matrix) up to this many free factors; beyond, no rigorous
#: bound is computed and a support with free factors is not certifiable.
FREE_BOUND_DENSE_MAX = 2000


def free_factor_bound(A: sp.csc_matrix, b: np.ndarray, h: np.ndarray,
                      lam_min: float | None = None, AF: sp.csc_matrix | None = None,
                      slack: np.ndarray | None = None,
                      slack_free: np.ndarray | None = None) -> float | None:
    """A rigorous bound β ≥ max_{ξ ∈ F} ‖ξ_F‖∞ on the free factors, or None when none is found.

    Parameters
    ----------
    A : csc_matrix, shape (nc, ng)
    b : ndarray, shape (nc,)
    h : ndarray, shape (ng,)
    lam_min : float, optional
        A rigorous lower bound on λ_min(A_FᵀA_F) of the exact data, computed by the caller (e.g. by
        a shifted banded Cholesky for trajectory sets, `setsmooth.trajectories`); replaces the dense
        eigenvalue computation and its size limit.
    AF : csc_matrix, optional
        A[:, free] when the caller has it.
    slack : ndarray, shape (nc,), optional
        The rows' rounding slack (`setsmooth.sets.rounding`): the bound then holds on the relaxed set
        {ξ : |Aξ − b| ≤ slack, |ξ| ≤ h}, whose rows differ from b by at most the slack.
    slack_free : ndarray, shape (nc,), optional
        The rows' slack per unit of ‖ξ_F‖∞ (rounded free columns): ‖ξ_F‖₂ σ_min ≤ ‖r‖ + ‖s_F‖₂‖ξ_F‖₂
        on the relaxed set, so the bound divides by σ_min − ‖s_F,R‖₂ (None when that is not positive).

    Returns
    -------
    float or None
        None when the free factors are not determined by the bounded ones (A_F rank deficient to
        working accuracy) or there are more than `FREE_BOUND_DENSE_MAX` of them.

    Notes
    -----
    λ_min(A_FᵀA_F) is bounded below by the computed smallest eigenvalue of the computed Gram matrix
    minus the Gram matrix's rounding error (≤ γ_nc ‖|A_F|ᵀ|A_F|‖_F) and the symmetric eigensolver's
    backward error (a generous 8·nF·u·‖Gram‖_F), both Frobenius bounds on the 2-norm.
    """
    free = np.flatnonzero(~np.isfinite(h))
    if free.size == 0:
        return 0.0
    if lam_min is None and free.size > FREE_BOUND_DENSE_MAX:
        return None
    AF = sp.csc_matrix(A[:, free]) if AF is None else AF
    if lam_min is None:
        gram = (AF.T @ AF).toarray()
        absAF = abs(AF)
        gram_err = float(gamma(A.shape[0] + 2) * np.linalg.norm((absAF.T @ absAF).toarray()))
        eig_err = 8.0 * free.size * U * np.linalg.norm(gram)
        lam_min = float(np.linalg.eigvalsh(gram)[0]) - gram_err - eig_err
    if not lam_min > 0:
        return None
    # Only the rows that see a free factor constrain it: A_RF ξ_F = b_R − A_RB ξ_B, and σ_min(A_RF) =
    # σ_min(A_F). So ‖ξ_F‖₂ ≤ ‖ |b_R| + |A_RB| h_B ‖₂ / σ_min(A_F): the other rows (the noises' own
    # constraints, of their factors' scale) would only loosen it.
    rows = np.flatnonzero(np.bincount(AF.indices, minlength=A.shape[0]))
    bounded = np.where(np.isfinite(h), h, 0.0)  # the free columns contribute exact zeros
    residual = np.abs(b[rows]) + (abs(A) @ bounded)[rows]
    if slack is not None:
        residual = residual + slack[rows]
    rhs = np.linalg.norm(residual) * (1.0 + gamma(A.shape[1] + 5))
    sigma = np.sqrt(lam_min) * (1.0 - gamma(4))
    if slack_free is not None:
        sigma = sigma - np.linalg.norm(slack_free[rows]) * (1.0 + gamma(rows.size + 4))
        if not sigma > 0:
            return None
    bound = rhs / sigma * (1.0 + gamma(8))
    return float(bound) if np.isfinite(bound) else None


def normal_solver(AF: sp.csc_matrix):
    """A solver of (A_FᵀA_F) y = r by sparse LU, or None when A_F is rank deficient (or empty)."""
    if AF.shape[1] == 0 or AF.shape[0] < AF.shape[1]:
        return None
    try:
        lu = splu(sp.csc_matrix(AF.T @ AF))
    except RuntimeError:  # exactly singular
        return None
    return lu.solve


def correct_multipliers(AF: sp.csc_matrix, gF: np.ndarray, lam: np.ndarray,
                        solve_normal=None, AFt: sp.csr_matrix | None = None) -> np.ndarray:
    """λ + δ with δ the least-norm solution of A_Fᵀδ = g_F − A_Fᵀλ (per row of ``lam``).

    The correction is small when the solver's λ nearly cancels the free factors' reduced cost. With
    ``solve_normal`` (a solver of A_FᵀA_F y = r, `normal_solver`, for one right-hand side per column)
    δ = A_F y, refined once, for all rows at a time; otherwise by sparse least squares (lsqr), row by
    row, for rank-deficient A_F. ``AFt`` is A_Fᵀ in CSR form when the caller keeps it.
    """
    if AF.shape[1] == 0:
        return lam
    out = lam.copy()
    AFt = sp.csr_matrix(AF.T) if AFt is None else AFt
    AFc = AF.tocsc()
    # The products by scipy's kernels called directly (`presolved.CompiledProduct`), bit for bit.
    times, times_t = CompiledProduct(AFc), CompiledProduct(AFt)
    res = gF - np.asarray(times_t @ lam.T).T
    active = np.any(res != 0, axis=1)
    # Two passes: the second removes what the first left by rounding or stopping tolerance. A row
    # stops at its first pass without progress (it keeps the better multiplier).
    for _ in range(2):
        rows = np.flatnonzero(active)
        if rows.size == 0:
            break
        if solve_normal is not None:
            y = np.asarray(solve_normal(np.ascontiguousarray(res[rows].T))).reshape(AF.shape[1], -1)
            finite = np.all(np.isfinite(y), axis=0)
            delta = np.asarray(times @ np.where(finite, y, 0.0)).T
        else:
            finite = np.ones(rows.size, dtype=bool)
            delta = np.array([lsqr(AFt, res[i], atol=1e-15, btol=1e-15,
                                   iter_lim=10 * AF.shape[1] + 50)[0] for i in rows])
        candidate = out[rows] + delta
        new_res = gF[rows] - np.asarray(times_t @ candidate.T).T
        progress = finite & (np.abs(new_res).max(axis=1) < np.abs(res[rows]).max(axis=1))
        better = rows[progress]
        out[better], res[better] = candidate[progress], new_res[progress]
        active[rows[~progress]] = False
    return out


class Operators:
    """Gᵀ, |G|ᵀ, Aᵀ, |A|ᵀ and the per-column γ factors of one CZ, prepared once for `certified_bound`
    (scipy's sparse conversions cost more than the bound itself on small sets).

    ``factor_part``: the A-dependent part (`Operators.factor_part`) when the caller keeps it for a
    factor set shared by many CZs (the projections of one trajectory set)."""

    def __init__(self, G, A: sp.csc_matrix, factor_part: tuple | None = None):
        if sp.issparse(G):  # by scipy's kernels (`CompiledProduct`); |Gᵀ| first, as abs(Gᵀ) sums
            Gt = sp.csr_matrix(G.T)  # the duplicates of Gᵀ (sharing G's arrays) in place
            self.absGt = CompiledProduct(Gt, absolute=True)
            self.Gt = CompiledProduct(Gt)
        else:
            self.Gt = np.ascontiguousarray(G.T)
            self.absGt = np.abs(self.Gt)
        self.At, self.absAt, self.gamma_cols = (Operators.factor_part(A) if factor_part is None
                                                else factor_part)

    @staticmethod
    def factor_part(A: sp.csc_matrix) -> tuple:
        """(Aᵀ, |A|ᵀ, γ_{m_j+2} per column): what `certified_bound` needs of the factor set (the
        products as `small_products.SmallProduct`s, `presolved.compiled`: scipy's, bit for bit)."""
        col_nnz = np.diff(A.indptr) if A.shape[0] else np.zeros(A.shape[1], dtype=int)
        return (compiled(SmallProduct(A, transpose=True)),
                compiled(SmallProduct(A, transpose=True, absolute=True)), gamma(col_nnz + 2))


def certified_bound(d: np.ndarray, G, c: np.ndarray, A: sp.csc_matrix, b: np.ndarray,
                    h: np.ndarray, lam: np.ndarray, free_bound: float | None,
                    ops: Operators | None = None, *, pad: np.ndarray | None = None,
                    slack: np.ndarray | None = None, pad_free: np.ndarray | None = None,
                    slack_free: np.ndarray | None = None, with_charge: bool = False):
    """Upper bounds on h_Z(d_i) for Z(G, c, A, b, h), rigorous in floating point (module docstring).

    Parameters
    ----------
    d : ndarray, shape (k, n)
        Directions.
    G, c, A, b, h
        The CZ's data (exact as stored).
    lam : ndarray, shape (k, nc)
        Any multipliers (one row per direction).
    free_bound : float or None
        β ≥ ‖ξ_F‖∞ over the factor set (`free_factor_bound`); None if unknown.
    ops : Operators, optional
        The prepared transposes of G and A (built here when not given).
    pad, slack, pad_free, slack_free : ndarray, optional
        The set's rounding charges (`setsmooth.sets.rounding`): the bound is then one on the exact
        set they enclose, |d|ᵀpad + |λ|ᵀslack + β(|d|ᵀpad_free + |λ|ᵀslack_free) more (β the free
        factors' bound; without one, free charges make the value uncertifiable).
    with_charge : bool
        Also return the bound of the stored set alone (without the charges) and the part of it that
        covers the certificate's own rounding (the floor of any bracket on the stored set).

    Returns
    -------
    ndarray, shape (k,)
        (and the stored set's bound and its rounding allowance, shape (k,) each, with
        ``with_charge``)

    Raises
    ------
    SolverError
        'UncertifiableReducedCost' when free factors carry a nonzero reduced cost (or rounding
        uncertainty) and no bound on them is known.
    """
    n = d.shape[1]
    nc, ng = A.shape
    ops = Operators(G, A) if ops is None else ops
    g = np.asarray((ops.Gt @ d.T).T)
    # + (n + 1)·η per column: products that underflowed (their factor bound h_j multiplies it)
    g_err = gamma(n + 1) * np.asarray((ops.absGt @ np.abs(d).T).T) + (n + 1) * ETA
    Atl = np.asarray((ops.At @ lam.T).T)
    absAtl = np.asarray((ops.absAt @ np.abs(lam).T).T)
    reduced = g - Atl
    # |computed r_j − exact r_j| ≤ γ_{m_j+2}(|g_j| + (|A|ᵀ|λ|)_j) + |g̃_j − g_j|; the computed |A|ᵀ|λ|
    # is itself inflated by (1 + γ) for its own rounding.
    gc = ops.gamma_cols
    r_err = gc * (np.abs(g) + absAtl * (1.0 + gc)) + g_err + (nc + 1) * ETA
    r_abs = np.abs(reduced) + r_err
    finite = np.isfinite(h)
    terms = r_abs[:, finite] @ h[finite]
    free = ~finite
    if free.any():
        charge = r_abs[:, free].sum(axis=1)
        if free_bound is None:
            # No bound on the free factors: certifiable only if their reduced costs are exactly
            # zero, decided in exact rational arithmetic (strips, half-spaces, lines: free factors
            # with a lineality that the direction does not see).
            if np.any(charge > 0) and not _exactly_cancelled(d, G, A, lam, np.flatnonzero(free)):
                raise SolverError("UncertifiableReducedCost",
                                  "certifying a support value: the free factors carry a reduced cost "
                                  f"up to {charge.max():.3g} and no finite bound on them is known",
                                  kind="support")
            charge = np.zeros_like(charge)
        else:
            terms = terms + charge * free_bound
    # The rounding charges of the set algebra (`setsmooth.sets.rounding`): |d|ᵀpad + |λ|ᵀslack,
    # and β(|d|ᵀpad_free + |λ|ᵀslack_free) for rounded free columns; sums of nonnegative terms
    # whose own rounding the (1 + γ) below covers. (Imported here: `setsmooth.sets` is built on
    # `setsmooth.solvers`, so a module-level import would start the sets package half-way.)
    from ..sets.rounding import abs_matvec

    rounding_charge = np.zeros(d.shape[0])
    if pad is not None:
        rounding_charge = rounding_charge + abs_matvec(d, pad)
    if slack is not None:
        rounding_charge = rounding_charge + abs_matvec(lam, slack)
    if pad_free is not None or slack_free is not None:
        free_charge = np.zeros(d.shape[0])
        if pad_free is not None:
            free_charge = free_charge + abs_matvec(d, pad_free)
        if slack_free is not None:
            free_charge = free_charge + abs_matvec(lam, slack_free)
        if np.any(free_charge > 0):
            if free_bound is None:
                raise SolverError("UncertifiableReducedCost",
                                  "certifying a support value: rounded columns of free factors carry "
                                  f"a charge up to {free_charge.max():.3g} per unit of the free "
                                  "factors and no finite bound on them is known", kind="support")
            rounding_charge = rounding_charge + free_charge * free_bound * (1.0 + gamma(2))
    added = rounding_charge * (1.0 + gamma(n + nc + 4))
    offset = d @ c
    blam = lam @ b
    total = offset + blam + terms
    # Rounding of each sum by its own length: dᵀc (n products), bᵀλ (nc), Σ_j h_j |r_j| (+ the
    # charge: ng products and a few operations, doubled for the rounding of r's bound itself), and
    # the two additions of the total. One γ of the longest sum on everything made dᵀc's term
    # γ_{n+nc+ng}·|dᵀ||c| ≈ 6e-7 at a centre 1.9e6 from the origin (1.3e-6 of a hull's width);
    # per sum it is γ_n·|dᵀ||c|. The magnitudes are themselves computed sums: the factor
    # (1 + γ_N) on the whole error term covers their rounding and that of this expression.
    mag_c, mag_b = np.abs(d) @ np.abs(c), np.abs(lam) @ np.abs(b)
    err = (gamma(n) * mag_c + gamma(nc) * mag_b + 2.0 * gamma(ng + 4) * np.abs(terms)
           + gamma(3) * (np.abs(offset) + np.abs(blam) + np.abs(terms) + np.abs(total)))
    nterms = n + nc + ng + 8
    err = err + (n + nc + 4) * ETA  # dᵀc and bᵀλ products that underflowed
    bound = np.nextafter(total + err * (1.0 + gamma(nterms)), np.inf)
    # The charges are added last, so that the bound of the stored set stays available as it was
    # (a bracket on the solver's answer), however large they are: one addition, rounded up.
    with np.errstate(invalid="ignore"):
        charged = bound + added
        charged = np.where(added > 0, np.nextafter(charged + 2.0 * U * np.abs(charged), np.inf),
                           bound)
    if with_charge:
        with np.errstate(invalid="ignore"):
            own = np.where(np.isfinite(bound), bound - total, np.inf)
        return charged, bound, own
    return charged


#: Free factors whose reduced costs are checked for exact cancellation, at most.
EXACT_CHECK_MAX = 200


def _exactly_cancelled(d: np.ndarray, G, A: sp.csc_matrix, lam: np.ndarray, free: np.ndarray) -> bool:
    """Whether (Gᵀd − Aᵀλ)_j = 0 exactly for every free j and every row of d, in rational arithmetic."""
    if free.size > EXACT_CHECK_MAX:
        return False
    Gc = sp.csc_matrix(G)
    for i in range(d.shape[0]):
        for j in free:
            total = Fraction(0)
            for p in range(Gc.indptr[j], Gc.indptr[j + 1]):
                total += Fraction(float(Gc.data[p])) * Fraction(float(d[i, Gc.indices[p]]))
            for p in range(A.indptr[j], A.indptr[j + 1]):
                total -= Fraction(float(A.data[p])) * Fraction(float(lam[i, A.indices[p]]))
            if total != 0:
                return False
    return True
