"""Rigorous bounds on the rounding of the closed-form set algebra, carried by the sets it builds.

A constrained zonotope computed by the algebra (a linear map, a Minkowski sum, a generalized
intersection, ...) is stored with floating-point data, and the set those data describe is not the exact
result: M·G, M·c, c₁ + c₂ and y − C·c are rounded. At a state 1e6 from the origin a rounded centre is off
by 1e-10, and a generalized intersection can amplify such an error by the conditioning of its rows, so
a bound valid for the set as stored can sit inside the exact set's (docs/numerical_core.md).

So the algebra charges its own rounding, and a set states what it contains in two vectors:

* ``pad`` (one entry per coordinate): every point of the exact set is within ``pad`` (componentwise)
  of a point c + Gξ with ξ in the relaxed factor set below (zonotopes, constrained zonotopes);
* ``slack`` (one entry per constraint row, on the factor set): the relaxed factor set is
  {ξ : |Aξ − b| ≤ slack, |ξ_j| ≤ h_j}.

For these, weak duality still gives, for any multiplier λ,

    h_exact(d) ≤ dᵀc + bᵀλ + Σ_j h_j |(Gᵀd − Aᵀλ)_j| + |λ|ᵀ slack + |d|ᵀ pad,

which `setsmooth.solvers.certify.certified_bound` evaluates. A set built from user data has neither
(its data are exact by definition); every closed-form operation adds what its own floating-point
operations can have lost, bounded as in Higham, *Accuracy and Stability of Numerical Algorithms*
(2nd ed., §2.2, §3.1): a sum of k products is off by at most γ_k times the sum of their magnitudes,
γ_k = k·u / (1 − k·u), u = 2⁻⁵³. Where a result is exact the charge is exactly zero (an entry of a
product with one nonzero term whose error-free transformation (Dekker's TwoProduct) leaves nothing, a
sum whose TwoSum leaves nothing), so selections, negations and additions of exact data cost nothing. Subnormal products are charged
their absolute error bound too (η = 2⁻¹⁰⁷⁴ per term).

Free factors (h_j = ∞) are unbounded, so the rounding of their columns is charged per unit of
‖ξ_F‖∞ (``pad_free``, ``slack_free``) and multiplied, in a certificate, by the rigorous bound β on the
free factors that certificates of such sets need anyway (`setsmooth.solvers.certify`); β itself is
computed for the relaxed set. Selections of states (the trajectory views) are never rounded.

Charges are sound, not tight. A pad is a box, and a box carried through a linear map M is enclosed by
the box |M|·pad: carried through k maps it grows like ‖|A|‖^k (the wrapping effect of interval
arithmetic) where the rounding itself does not. So a set's pad has two parts: the box of the rounding
of the last operation, and **pad generators** P (one column per earlier charge, factors ε ∈ [−1, 1]
independent of ξ): every point of the exact set is within box(pad) ⊕ Z(P) of c + Gξ. A linear map
carries the earlier charges exactly, as columns fl(M·[P, diag(pad)]) whose own rounding is the new
box (`mapped_pad`), the way affine arithmetic carries its error symbols: the charges then grow like
the set's own generators, ‖A^k‖, not ‖|A|‖^k. Along coordinate directions ‖Pᵀe_i‖₁ = (|P|·1)_i, so
the box hull of both parts (`pad_hull`, what ``pad`` reads elsewhere) loses nothing for interval
hulls. The estimators of the recursion certify their sets against the model data
(`setsmooth.trajectories.recursion_certificates`); the pad generators are what keeps a recursion
written by hand with the set algebra certified as tightly.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..floating import ETA, U, gamma  # u = 2⁻⁵³; η = 2⁻¹⁰⁷⁴; γ_k = k·u / (1 − k·u)

__all__ = ["two_sum", "sum_with_error", "sum_down", "sum_up", "abs_matvec", "zeros_or",
           "product_error", "products_exact", "rounded_up", "upper_bound", "residual_bound", "row_sums_bound",
           "extended_residual_bound",
           "chained_product_error", "add", "linear_image", "box_center_radius", "pad_hull", "mapped_pad",
           "PAD_GENERATORS_PER_DIM"]


def two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(s, e) with s = fl(a + b) and a + b = s + e exactly (Knuth's TwoSum; no overflow assumed)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(invalid="ignore", over="ignore"):
        s = a + b
        bb = s - a
        e = (a - (s - bb)) + (b - bb)
    # inf − inf in the transformation: an infinite sum has no finite error to charge.
    e = np.where(np.isfinite(s), e, 0.0)
    return s, e


def sum_with_error(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(fl(a + b), |error|): the error is exact (TwoSum), zero where the sum is exact."""
    s, e = two_sum(a, b)
    return s, np.abs(e)


def sum_down(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The largest float ≤ a + b (directed rounding by the TwoSum error: exact sums stay exact)."""
    s, e = two_sum(a, b)
    return np.where(e < 0, np.nextafter(s, -np.inf), s)


def sum_up(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest float ≥ a + b."""
    s, e = two_sum(a, b)
    return np.where(e > 0, np.nextafter(s, np.inf), s)


def rounded_up(x: np.ndarray, terms: int = 1) -> np.ndarray:
    """An upper bound on a nonnegative quantity computed in floating point as a sum of ``terms``
    nonnegative terms: x·(1 + γ_terms), rounded up by one more ulp; exact zeros stay zero."""
    x = np.asarray(x, dtype=float)
    with np.errstate(over="ignore"):
        out = np.nextafter(x * (1.0 + gamma(terms + 1)), np.inf)
    return np.where(x == 0.0, 0.0, out)


def upper_bound(values: np.ndarray, magnitude: np.ndarray, terms: int,
                absolute: np.ndarray | float = 0.0) -> np.ndarray:
    """Upper bounds on exact sums of ``terms`` products computed as ``values``, whose products'
    magnitudes sum to ``magnitude``: values + 2γ_{terms+1}·magnitude + (terms + absolute)·η, rounded
    up (η for each product that may have underflowed; ``absolute`` more such terms, e.g. the
    products a factor bound multiplies). Infinite and NaN values are returned as they are."""
    values = np.asarray(values, dtype=float)
    err = 2.0 * gamma(terms + 1) * np.asarray(magnitude) + (terms + np.asarray(absolute)) * ETA
    with np.errstate(invalid="ignore", over="ignore"):
        out = np.nextafter(values + rounded_up(err, 2), np.inf)
    return np.where(np.isfinite(values), out, values)


def products_exact(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Elementwise: whether fl(a·b) = a·b exactly (TwoProduct; zero products are exact, products
    that underflow or overflow are not)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        p = a * b
        ah, al = _split(a)
        bh, bl = _split(b)
        err = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return (p == 0) & ((a == 0) | (b == 0)) | ((err == 0) & (np.abs(p) >= _DEKKER_MIN)
                                               & np.isfinite(p))


def _two_product(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(p, e) with p = fl(a·b) and a·b = p + e exactly (Dekker; barring under/overflow)."""
    with np.errstate(over="ignore", invalid="ignore"):
        p = a * b
        ah, al = _split(a)
        bh, bl = _split(b)
        return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def residual_bound(pairs) -> np.ndarray:
    """A rigorous bound on |Σ_t M_t v_t| per row, for the residual of a row whose terms cancel
    (e.g. A x̄_k + B c_w + u_k − x̄_{k+1}, which the nominal trajectory's rounding leaves).

    Computed as accurately as in twice the working precision (Ogita, Rump and Oishi, "Accurate sum
    and dot product", SIAM J. Sci. Comput. 26 (2005), Algorithm Dot2 with TwoSum and TwoProduct), so
    the bound is the residual itself up to u·|res| + γ_N²·Σ|terms| (their Proposition 5.5) and
    N·η for products that may have underflowed, rounded up: near the true rounding (1e-10 at
    states 1e6), where γ_N·Σ|terms| was 100 times more.

    Parameters
    ----------
    pairs : list of (M, v)
        M of shape (rows, k_t) (or a vector, taken as a diagonal), v of shape (k_t,).
    """
    columns, values = [], []
    for M, v in pairs:
        M, v = np.asarray(M, dtype=float), np.asarray(v, dtype=float)
        if M.ndim == 1:  # a vector of per-row terms: M_i · v_i
            columns.append(M[:, None])
            values.append(v[:, None])
        else:
            columns.append(M)
            values.append(np.broadcast_to(v, M.shape))
    return row_sums_bound(np.hstack(columns), np.hstack(values))


def residual_bounds(residuals: list) -> list[np.ndarray]:
    """`residual_bound` of every entry of ``residuals`` (each a list of (M, v) pairs as there), bit
    for bit, with one Dot2 pass over all the rows of the residuals that have the same number of
    terms (rows are independent in Dot2; only the number of terms enters the bound)."""
    blocks = []
    for pairs in residuals:
        columns, values = [], []
        for M, v in pairs:
            M, v = np.asarray(M, dtype=float), np.asarray(v, dtype=float)
            if M.ndim == 1:
                columns.append(M[:, None])
                values.append(v[:, None])
            else:
                columns.append(M)
                values.append(np.broadcast_to(v, M.shape))
        blocks.append((np.hstack(columns), np.hstack(values)))
    out: list = [None] * len(blocks)
    for width in {X.shape[1] for X, _ in blocks}:
        same = [i for i, (X, _) in enumerate(blocks) if X.shape[1] == width]
        bounds = row_sums_bound(np.vstack([blocks[i][0] for i in same]),
                                np.vstack([blocks[i][1] for i in same]))
        ends = np.cumsum([blocks[i][0].shape[0] for i in same])[:-1]
        for i, part in zip(same, np.split(bounds, ends)):
            out[i] = part
    return out


_U_EXT = float(np.finfo(np.longdouble).eps) / 2  # the extended format's unit roundoff (2⁻⁶⁴ on x86)


def extended_residual_bound(pairs) -> np.ndarray:
    """A rigorous bound on |Σ_t M_t v_t| per row, as `residual_bound`, evaluated in NumPy's extended
    format (``np.longdouble``): |S| ≤ |fl_x(S)| + 2γ^x_N·fl_x(Σ|terms|), γ^x of the extended unit
    roundoff (2⁻⁶⁴ on x86-64, 2⁻¹¹³ on aarch64, 2⁻⁵³ where it is plain double: still sound, only
    looser), converted to binary64 rounding up, plus N·η for products that may have underflowed.

    Matrix–vector products instead of Dot2's column loop: ~30 times cheaper for a window step of
    n = 10–30 (`setsmooth.filters._window`), at 2⁻⁶⁴·N·Σ|terms| (1e-11 at states 1e6) where Dot2
    reaches the residual itself. Same ``pairs`` as `residual_bound`; the vectors may also be matrices
    of one column per residual (the bounds then of shape (rows, columns)).
    """
    res, mag, N = None, None, 0
    for M, v in pairs:
        M = np.asarray(M, dtype=float).astype(np.longdouble)
        v = np.asarray(v, dtype=float).astype(np.longdouble)
        if M.ndim == 1:  # a diagonal (v of one column per right-hand side, or a vector)
            Md = M if v.ndim == 1 else M[:, None]
            t, a = Md * v, np.abs(Md) * np.abs(v)
            N += 1
        else:
            t, a = M @ v, np.abs(M) @ np.abs(v)
            N += M.shape[1]
        res = t if res is None else res + t
        mag = a if mag is None else mag + a
    g = N * _U_EXT / (1.0 - N * _U_EXT)
    with np.errstate(over="ignore", invalid="ignore"):
        # the factor 2 covers the rounding of the magnitudes; (1 + 4u_x) the bound's own operations
        bound = (np.abs(res) + np.longdouble(2.0 * g) * mag) * np.longdouble(1.0 + 4.0 * _U_EXT)
        out = np.nextafter(bound.astype(float), np.inf) + N * ETA
    plain = rounded_up(2.0 * gamma(N + 1) * mag.astype(float) + N * ETA, 2)
    return np.where(np.isfinite(out), out, plain)


def row_sums_bound(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """A rigorous bound on |Σ_j X_ij Y_ij| per row i (the core of `residual_bound`, for callers that
    stack the rows of several residuals with different vectors: one Dot2 pass over all of them)."""
    X, Y = np.asarray(X, dtype=float), np.asarray(Y, dtype=float)
    N = X.shape[1]
    p, s = _two_product(X[:, 0], Y[:, 0])
    clean = s == 0  # every product and partial sum so far exact: then p is the sum itself
    for j in range(1, N):
        h, r = _two_product(X[:, j], Y[:, j])
        p, q = two_sum(p, h)
        s = s + (q + r)
        clean &= (q == 0) & (r == 0)
    res = p + s
    magnitude = np.abs(X * Y).sum(axis=1)
    g = gamma(N)
    # products near the underflow range (TwoProduct not error-free there): η each, where any
    with np.errstate(over="ignore", invalid="ignore"):
        tiny = ((np.abs(X * Y) < _DEKKER_MIN) & (X != 0) & (Y != 0)).any(axis=1)
    bound = (np.abs(res) * (1.0 + 2.0 * U) + 2.0 * g * g * magnitude
             + np.where(tiny, 5.0 * N * ETA, 0.0))
    out = rounded_up(bound, 4)
    # an error-free evaluation (exact products and sums, none near underflow) is the sum itself
    out = np.where(clean & ~tiny & np.isfinite(p), np.abs(p), out)
    # overflow or NaN in the transformation: fall back to the plain γ bound of the sum
    plain = rounded_up(2.0 * gamma(N + 1) * magnitude + N * ETA, 2)
    return np.where(np.isfinite(out), out, plain)


def _dense_products_exact(X: np.ndarray, Y: np.ndarray, P: np.ndarray | None = None) -> np.ndarray:
    """Elementwise: whether fl(X·Y) is the exact product, decided by error-free transformations.

    The dot products are re-evaluated term by term with TwoProduct and TwoSum: where no product and no
    partial sum rounds (and none is near underflow), that evaluation's value is the exact sum, and the
    entry is exact iff the BLAS product (``P``, the caller's stored one when given) equals it
    (another summation order may have rounded)."""
    P = X @ Y if P is None else np.asarray(P, dtype=float)
    total = np.zeros(P.shape)
    clean = np.ones(P.shape, dtype=bool)
    for t in range(X.shape[1]):
        prod, err = _two_product(X[:, t:t + 1], Y[t:t + 1, :])
        total, carry = two_sum(total, prod)
        with np.errstate(invalid="ignore"):
            tiny = (np.abs(prod) < _DEKKER_MIN) & (X[:, t:t + 1] != 0) & (Y[t:t + 1, :] != 0)
        clean &= (err == 0) & (carry == 0) & ~tiny & np.isfinite(prod)
    return clean & (P == total)


def chained_product_error(X: np.ndarray, dX: np.ndarray | None, Y: np.ndarray,
                          dY: np.ndarray | None, product: np.ndarray | None = None) -> np.ndarray:
    """An elementwise bound on |fl(X·Y) − X*·Y*| for computed factors X, Y within dX, dY of exact
    ones X*, Y* (None: exact), dense: the rounding of this product plus what the factors carry,
    |X|·dY + dX·(|Y| + dY), each sum of k = X.shape[1] terms rounded up. For chains such as the
    matrix powers of a window, A^j = A·A^{j−1}. Entries computed exactly (`_dense_products_exact`)
    are charged only what the factors carry; ``product`` is the stored fl(X·Y) that exactness is
    decided on (recomputed when not given)."""
    total = np.asarray(product_error(X, Y), dtype=float)
    total = np.where(_dense_products_exact(X, Y, product), 0.0, total)
    if dY is not None:
        total = total + np.abs(X) @ dY
    if dX is not None:
        total = total + dX @ (np.abs(Y) if dY is None else np.abs(Y) + dY)
    return rounded_up(total, X.shape[1] + 3)


def add(*charges) -> np.ndarray | None:
    """The sum of nonnegative charge vectors (None meaning zero), rounded up; None if all are."""
    parts = [np.asarray(c, dtype=float) for c in charges if c is not None]
    if not parts:
        return None
    total = parts[0].copy()
    for p in parts[1:]:
        total = total + p
    return rounded_up(total, len(parts)) if len(parts) > 1 else total


def zeros_or(v: np.ndarray | None, size: int) -> np.ndarray:
    """A charge vector, zeros of ``size`` for None (no charge)."""
    return np.zeros(size) if v is None else np.asarray(v, dtype=float)


def abs_matvec(M, v: np.ndarray) -> np.ndarray:
    """|M|·v for a nonnegative v that may hold +∞, with 0·∞ = 0 (a row that does not see an infinite
    entry stays finite). M may be a dense array (1-D or 2-D) or a sparse matrix; v of M's columns."""
    v = np.asarray(v, dtype=float)
    absM = _abs(M)
    infinite = np.isinf(v)
    if not infinite.any():
        return np.asarray(absM @ v)
    out = np.asarray(absM @ np.where(infinite, 0.0, v))
    sees = np.asarray(absM @ infinite.astype(float))
    return np.where(sees > 0, np.inf, out)


def _abs(M):
    return abs(M) if sp.issparse(M) else np.abs(M)


def _pattern(M):
    """The 0/1 pattern of M's nonzeros."""
    if sp.issparse(M):
        P = sp.csr_matrix(M, copy=True)
        P.eliminate_zeros()
        P.data = np.ones(P.data.size)
        return P
    return (M != 0).astype(float)


_SPLITTER = 2.0 ** 27 + 1.0  # Veltkamp's splitting constant for binary64
_DEKKER_MIN = 2.0 ** -969     # TwoProduct is error-free above this (no subnormal partial product)


def _split(M):
    """(hi, lo) with M = hi + lo exactly, hi and lo of at most 26 significant bits (Veltkamp)."""
    if sp.issparse(M):
        hi, lo = sp.csr_matrix(M, copy=True), sp.csr_matrix(M, copy=True)
        hi.data, lo.data = _split(hi.data)
        return hi, lo
    with np.errstate(over="ignore", invalid="ignore"):
        t = _SPLITTER * M
        hi = t - (t - M)
    return hi, M - hi


def _single_products_exact(M, X, P) -> np.ndarray | sp.spmatrix:
    """Where an entry of P = fl(M X) is a single product, whether it is exact (Dekker's TwoProduct:
    the four partial products of the split factors are exact, so the error is computed exactly)."""
    Mh, Ml = _split(M)
    Xh, Xl = _split(X)
    with np.errstate(over="ignore", invalid="ignore"):
        err = ((Mh @ Xh - P) + Mh @ Xl + Ml @ Xh) + Ml @ Xl
    if sp.issparse(err):
        err = sp.csr_matrix(err)
        err.data = np.where(np.isfinite(err.data), err.data, 1.0)  # overflow: not exact
        err.eliminate_zeros()
        return err
    return np.where(np.isfinite(err), err, 1.0)


def product_error(M, X) -> np.ndarray | sp.spmatrix:
    """An elementwise bound on |fl(M·X) − M·X| for a dense or sparse product (no overflow assumed).

    An entry whose dot product has k ≥ 2 nonzero terms, or one term whose product rounds (decided
    exactly by TwoProduct), is charged 2·γ_k·(|M||X|) + k·η (the factor 2 covers the rounding of
    |M||X| itself and the subnormal range); the other entries are exact and charged zero.
    """
    sparse = sp.issparse(M) or sp.issparse(X)
    if sparse:
        small = _small_sparse_product_error(M, X)
        if small is not None:
            return small
        M, X = sp.csr_matrix(M), sp.csc_matrix(X)
    P = M @ X
    magnitude = _abs(M) @ _abs(X)
    count = _pattern(M) @ _pattern(X)
    single_error = _single_products_exact(M, X, P)
    # Dekker's algorithm needs no underflow: a single product below 2⁻⁹⁶⁹ (a subnormal partial
    # product) or one that underflowed to zero is not taken as exact.
    if sparse:
        magnitude, count = sp.csr_matrix(magnitude), sp.csr_matrix(count)
        single_error = sp.csr_matrix(single_error)
        k = float(count.max()) if count.nnz else 0.0
        seen = count.copy()
        seen.data = np.ones(seen.data.size)
        large = abs(sp.csr_matrix(P)).multiply(seen)
        large.data = (large.data >= _DEKKER_MIN).astype(float)
        small = seen - large
        small.eliminate_zeros()
        # rounded: two or more terms, or one product that is not exact
        one = (count == 1)
        rounded = (count > 1).maximum(one.multiply(single_error != 0)).maximum(
            one.multiply(small > 0)).astype(float)
        E = magnitude.multiply(rounded) * (2.0 * float(gamma(k + 1))) + count.multiply(rounded) * ETA
        return sp.csr_matrix(E)
    magnitude, count = np.asarray(magnitude), np.asarray(count)
    single_error = np.asarray(single_error)
    k = float(count.max(initial=0.0))
    P = np.asarray(P)
    rounded = (count > 1) | ((count == 1) & ((single_error != 0) | (np.abs(P) < _DEKKER_MIN)))
    return np.where(rounded, 2.0 * gamma(k + 1) * magnitude + count * ETA, 0.0)


#: `product_error` of a sparse product with at most this many terms m·k·n is computed on dense copies.
_SMALL_SPARSE_PRODUCT_TERMS = 32768


def _small_sparse_product_error(M, X) -> sp.csr_matrix | None:
    """`product_error`'s sparse answer, bit for bit, from dense copies of a small product; None where
    that is not guaranteed (the caller then takes the sparse path).

    Every term M_ij·X_jk is formed once, in an (m, k, n) array. The sparse path's magnitude sums its
    terms one by one, starting from zero, in the order of M's stored row entries (scipy's csr_matmat,
    no fused multiply-add): for a canonical M (or a dense one) that is increasing j, which the running
    sum below repeats; the terms of absent entries are +0 and leave a nonnegative sum unchanged.
    Counts are exact integers, and fl(M·X) and the TwoProduct error are read only where an entry has
    one term, whose value is then the same however the zero terms are added. The answer is a CSR
    matrix of the nonzero entries in increasing column order: the sparse path's order may differ, so it
    is returned only when no row has more than two nonzeros, where a product E·v (two terms summed
    from zero) does not depend on the order. Non-finite data (0·∞ would become NaN) are left to the
    sparse path.
    """
    dense = []
    for Y in (M, X):
        if sp.issparse(Y):
            if Y.format not in ("csr", "csc") or not Y.has_canonical_format:
                return None
            Y = Y.toarray()
        Y = np.asarray(Y, dtype=float)
        if Y.ndim != 2 or not np.isfinite(Y).all():
            return None
        dense.append(Y)
    Md, Xd = dense
    m, k = Md.shape
    n = Xd.shape[1]
    if k == 0 or m * k * n > _SMALL_SPARSE_PRODUCT_TERMS:
        return None
    M3, X3 = Md[:, :, None], Xd[None, :, :]
    terms = np.abs(M3) * np.abs(X3)
    magnitude = terms[:, 0, :]
    for j in range(1, k):
        magnitude = magnitude + terms[:, j, :]
    count = ((M3 != 0) & (X3 != 0)).sum(axis=1)
    Mh, Ml = _split(M3)
    Xh, Xl = _split(X3)
    if not (np.isfinite(Mh).all() and np.isfinite(Xh).all()):  # |entry| near overflow: 0·NaN below
        return None
    with np.errstate(over="ignore", invalid="ignore"):
        products = M3 * X3
        error = ((Mh * Xh - products) + Mh * Xl + Ml * Xh) + Ml * Xl
        P, single_error = products.sum(axis=1), error.sum(axis=1)
    single_error = np.where(np.isfinite(single_error), single_error, 1.0)  # overflow: not exact
    rounded = (count > 1) | ((count == 1) & ((single_error != 0) | (np.abs(P) < _DEKKER_MIN)))
    k_max = float(count.max(initial=0))
    E = np.where(rounded, magnitude * (2.0 * float(gamma(k_max + 1))) + count * ETA, 0.0)
    per_row = np.count_nonzero(E, axis=1)
    if per_row.max(initial=0) > 2:
        return None
    _, columns = np.nonzero(E)
    return sp.csr_matrix((E[E != 0], columns, np.concatenate(([0], np.cumsum(per_row)))), shape=E.shape)


def _weighted_rows(E, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Σ_{j bounded} E_ij h_j, Σ_{j free} E_ij): the charge of the bounded factors, and the
    coefficient of ‖ξ_F‖∞ for the free ones (h_j = ∞)."""
    finite = np.isfinite(h)
    bounded = np.asarray(E @ np.where(finite, h, 0.0)).reshape(-1)
    free = np.asarray(E @ (~finite).astype(float)).reshape(-1)
    return bounded, free


def linear_image(M, G, c: np.ndarray, h: np.ndarray, pad: np.ndarray | None,
                 pad_free: np.ndarray | None = None):
    """The charges (pad, pad_free) of {fl(M G) ξ + fl(M c)} as an enclosure of M·Z, where Z's own
    points are within pad + pad_free·‖ξ_F‖∞ of c + Gξ (|ξ_j| ≤ h_j, free factors ξ_F).

    pad' = |M|·pad + bound(fl(M c) − M c) + Σ_{j bounded} h_j bound(fl(M G)_j − M G_j),
    pad_free' = |M|·pad_free + Σ_{j free} bound(fl(M G)_j − M G_j), each rounded up; None when zero.
    """
    terms, free_terms = [], []
    if pad is not None:
        terms.append(np.asarray(_abs(M) @ pad).reshape(-1))
    if pad_free is not None:
        free_terms.append(np.asarray(_abs(M) @ pad_free).reshape(-1))
    cc = np.asarray(c, dtype=float)[:, None]
    if cc.any():
        Ec = product_error(M, sp.csc_matrix(cc) if sp.issparse(M) else cc)
        terms.append(np.asarray(Ec.todense() if sp.issparse(Ec) else Ec).reshape(-1))
    else:  # M·0 is exact: `product_error` charges zero
        terms.append(np.zeros(M.shape[0]))
    if G.shape[1]:
        bounded, free = _weighted_rows(product_error(M, G), h)
        terms.append(bounded)
        free_terms.append(free)
    # One γ over every sum that formed these terms (|M|·pad, E·h) and the terms' own additions.
    size = len(terms) + M.shape[1] + G.shape[1]
    total = rounded_up(sum(terms), size)
    total_free = rounded_up(sum(free_terms), size) if free_terms else None
    return (total if np.any(total) else None,
            total_free if total_free is not None and np.any(total_free) else None)


#: The pad generators a set carries (`mapped_pad`) are capped at this many per coordinate; beyond it
#: they are enclosed in n generators in their own frame (`_parallelotope`).
PAD_GENERATORS_PER_DIM = 8


def pad_hull(pad: np.ndarray | None, generators: np.ndarray | None) -> np.ndarray | None:
    """The box that encloses box(pad) ⊕ Z(generators): pad + |P|·1, rounded up; None when both are."""
    if generators is None:
        return pad
    return add(pad, rounded_up(np.abs(generators).sum(axis=1), generators.shape[1]))


def mapped_pad(M, pad: np.ndarray | None, generators: np.ndarray | None
               ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The charges box(pad) ⊕ Z(P) of a set, carried through the linear map M without wrapping.

    M·(box(pad) ⊕ Z(P)) = Z(M·X) exactly, X = [P, diag(pad)] (the padded coordinates only). Returns
    (P', charge): P' = fl(M·X), the image's pad generators, and ``charge``, a box that bounds
    |fl(M·X) − M·X|·1 (to be added to the image's own rounding). When P' has more than
    ``PAD_GENERATORS_PER_DIM`` columns per coordinate, its oldest columns are enclosed in ``charge``.
    Either is None when zero.
    """
    parts = [] if generators is None else [generators]
    if pad is not None:
        rows = np.flatnonzero(pad)
        if rows.size:
            D = np.zeros((pad.size, rows.size))
            D[rows, np.arange(rows.size)] = pad[rows]
            parts.append(D)
    if not parts:
        return None, None
    X = np.hstack(parts) if len(parts) > 1 else parts[0]
    image = np.asarray(M @ X)
    error = product_error(M, X)
    charge = rounded_up(np.asarray(error.sum(axis=1)).reshape(-1), X.shape[1])
    n, q = image.shape
    if q > PAD_GENERATORS_PER_DIM * n:
        image, residual = _parallelotope(image)
        charge = add(charge, residual)
    keep = np.flatnonzero(np.abs(image).max(axis=0) > 0)
    image = image[:, keep] if keep.size else None
    return image, (charge if np.any(charge) else None)


def _parallelotope(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An enclosure of Z(P) by n generators in P's own frame (Lohner's QR method): Z(P) ⊆
    Z(fl(Q·diag(r))) ⊕ box(residual), with Q from a pivoted QR of P, R = fl(QᵀP) and r = |R|·1.

    Z(P) = Z(QR) ⊕ Z(P − QR) ⊆ Q·box(r) ⊕ box(|P − QR|·1) holds for any Q and the computed R; the
    residual box bounds |P − QR|·1 (rounding of QR and of the subtraction charged) and the rounding
    of fl(Q·diag(r)). Boxing happens in the frame of the charges' dominant directions, so it does
    not wrap like a box in the coordinate frame (the residual is at the rounding level of P itself).
    """
    q = P.shape[1]
    Q = scipy.linalg.qr(P, pivoting=True, mode="economic")[0]
    R = Q.T @ P
    r = rounded_up(np.abs(R).sum(axis=1), q)
    QR = Q @ R
    difference, difference_error = sum_with_error(P, -QR)
    residual = rounded_up((np.abs(difference) + difference_error
                           + product_error(Q, R)).sum(axis=1), 3 * q)
    generators = Q * r
    residual = add(residual, product_error(Q, np.diag(r)).sum(axis=1))
    return generators, residual


def box_center_radius(lo: np.ndarray, hi: np.ndarray):
    """(centre, radius, pad) of a bounded box as c ± r: [lo, hi] ⊆ [c − r − pad, c + r + pad].

    c = fl(lo + hi)/2 and r = fl(hi − lo)/2; the halvings are exact (barring underflow, charged by η),
    the sums' errors exactly known (TwoSum), so the pad is zero for every box whose midpoint and
    radius are representable.
    """
    s, es = sum_with_error(lo, hi)
    t, et = sum_with_error(hi, -lo)
    c, r = s / 2, t / 2
    halving_rounded = (2.0 * c != s) | (2.0 * r != t)  # subnormal halves: off by η/2 at most
    pad = rounded_up((es + et) / 2 + np.where(((es + et) > 0) | halving_rounded, ETA, 0.0), 2)
    return c, r, (pad if np.any(pad) else None)
