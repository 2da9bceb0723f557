"""Exact vertices of small constrained zonotopes, and the geometry of their convex hulls.

A bounded CZ Z(G, c, A, b, h) is the image under ξ ↦ Gξ + c of its factor polytope
P = {ξ : Aξ = b, |ξ_j| ≤ h_j}, so it is the convex hull of the images of P's vertices. A vertex of P
has ng linearly independent active constraints: the nc (independent) equalities and ng − nc bounds.
Choosing the nc *basic* factors β with A_β invertible, fixing the others at ±h and solving
ξ_β = A_β⁻¹(b − A_N ξ_N) enumerates every vertex (and a few infeasible points, which are dropped):
C(ng, nc)·2^(ng−nc) candidates, a vectorized product per basis. In the few dimensions of the LSU
paper (n = 3, ng ≤ ~12, nc ≤ ~4) that is thousands of candidates, cheaper than the 2n LPs of an
interval hull, and it gives what LPs cannot: the volume, the centroid and an exact uniform sampler
(`HullGeometry`, built on Qhull's triangulated hull).

Rounding: a candidate is kept when its basic factors lie within ``VERTEX_FEASIBILITY_TOL`` (relative)
of their bounds, so the hull is the exact one up to that relative tolerance and the rounding of the
solves; it is geometry for estimates and sampling, not a certified enclosure (use
``interval_hull(certified=True)`` for that).
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.spatial import ConvexHull

from .. import tolerances as tol
from ..linalg import RowBasis, independent_rows

__all__ = ["MAX_VERTEX_CANDIDATES", "vertex_candidate_count", "cz_vertices", "vertices_of", "HullGeometry",
           "hull_geometry", "vertex_bounds"]

#: Above this many candidates (C(ng, nc)·2^(ng−nc)) `cz_vertices` declines (returns None).
MAX_VERTEX_CANDIDATES = 300_000

#: `row_basis` calls rows independent without a QR when their unit rows' Gram matrix has its smallest
#: eigenvalue above this (smallest singular value above ~1e-3).
CLEAR_RANK_GRAM = 1e-6

_TINY = np.finfo(float).tiny


def vertex_candidate_count(ng: int, nc: int) -> int:
    """C(ng, nc)·2^(ng − nc): the basic solutions `cz_vertices` examines (nc independent rows)."""
    return math.comb(ng, nc) * 2 ** (ng - nc) if 0 <= nc <= ng else 0


def cz_vertices(Z, max_candidates: int = MAX_VERTEX_CANDIDATES) -> np.ndarray | None:
    """Points whose convex hull is the constrained zonotope ``Z`` (its vertices, possibly with repeats).

    Parameters
    ----------
    Z : ConstrainedZonotope
        With finite factor bounds h.
    max_candidates : int
        Decline (return None) when the enumeration would examine more basic solutions than this.

    Returns
    -------
    ndarray, shape (k, n), or None
        Images Gξ + c of the vertices of the factor polytope (k = 0 when Z is empty); None when the
        enumeration is too large or a factor is free (h = ∞: Z may be unbounded).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> triangle = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.0])
    >>> sorted(map(tuple, cz_vertices(triangle).round(12).tolist()))
    [(0.0, 1.0), (1.0, 0.0)]

    Notes
    -----
    Sets are immutable: the answer for the default ``max_candidates`` is kept on ``Z`` (the array
    read-only) and returned again by the next call, as LSU-CZ's estimates and the LSU figures'
    containment count both enumerate every support.
    """
    memo = Z.__dict__ if max_candidates == MAX_VERTEX_CANDIDATES else {}
    if "_vertices" not in memo:
        V = vertices_of(Z.G, Z.c, Z.A, Z.b, Z.h, max_candidates)
        if V is not None:
            V.flags.writeable = False
        memo["_vertices"] = V
    return memo["_vertices"]


def vertices_of(G, c, A, b, h, max_candidates: int = MAX_VERTEX_CANDIDATES) -> np.ndarray | None:
    """`cz_vertices` of Z(G, c, A, b, h) given by its arrays, for a caller that has them without the
    set (trusted: the arrays a `ConstrainedZonotope` would hold; its copies of dense arrays keep their
    layout, so these give the same bits)."""
    h = np.asarray(h, dtype=float)
    if not np.all(np.isfinite(h)):
        return None
    G = G.toarray() if sp.issparse(G) else np.asarray(G, dtype=float)
    A = A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)
    b, c = np.asarray(b, dtype=float), np.asarray(c, dtype=float)
    live = np.flatnonzero(h > 0)                      # factors fixed at 0 move nothing
    G, A, h = G[:, live], A[:, live], h[live]
    basis = row_basis(A, b)
    if not basis.consistent:
        return np.zeros((0, c.size))
    # Unit factor bounds (ξ = hη) and rows of unit ∞-norm: the basis and feasibility tests are then
    # relative, whatever the scales of the factors and equations (a row 1e-16·ξ_7 = 0 means ξ_7 = 0).
    A, b, G = A[basis.keep] * h, b[basis.keep], G * h
    norms = np.abs(A).max(axis=1, initial=0.0)
    A, b = A / norms[:, None], b / norms
    ng, nc = h.size, A.shape[0]
    if vertex_candidate_count(ng, nc) > max_candidates:
        return None
    if nc == 0:
        return c + _signs(ng) @ G.T
    slack = tol.VERTEX_FEASIBILITY_TOL * (1.0 + np.abs(b).max(initial=0.0))
    # All bases at once: β (nb, nc) basic factors, ρ (nb, k) the others at every sign pattern S.
    beta, rest = _bases(ng, nc)
    Ab = np.transpose(A[:, beta], (1, 0, 2))                           # (nb, nc, nc)
    is_basis = np.abs(np.linalg.det(Ab)) > tol.RANK_TOL
    if not is_basis.all():   # (the solve copies Ab into LAPACK's layout either way)
        beta, rest, Ab = beta[is_basis], rest[is_basis], Ab[is_basis]
    if beta.shape[0] == 0:
        return np.zeros((0, c.size))
    S = _signs(ng - nc)                                                # (2^k, k)
    rhs = b[None, :, None] - np.transpose(A[:, rest], (1, 0, 2)) @ S.T   # (nb, nc, 2^k)
    eta_beta = np.linalg.solve(Ab, rhs)                                # (nb, nc, 2^k)
    ok = np.all(np.abs(eta_beta) <= 1.0 + slack, axis=1)               # (nb, 2^k)
    basis_of, pattern = np.nonzero(ok)
    # np.clip's values (min(max(η, −1), 1)) without its argument handling.
    eta_b = np.minimum(np.maximum(eta_beta[basis_of, :, pattern], -1.0), 1.0)   # (p, nc)
    Gb = np.transpose(G[:, beta], (1, 0, 2))                           # (nb, n, nc)
    Gr = np.transpose(G[:, rest], (1, 0, 2))                           # (nb, n, k)
    return (c + np.einsum("pnc,pc->pn", Gb[basis_of], eta_b)
            + np.einsum("pnk,pk->pn", Gr[basis_of], S[pattern]))


def row_basis(A: np.ndarray, b: np.ndarray) -> RowBasis:
    """`linalg.independent_rows` (A, b), answered without its rank-revealing QR where the rows are
    clearly independent (every call of the enumeration and of constraint elimination has a few rows).

    With rows of finite norm above the smallest normal float (below it, `independent_rows` calls a row
    zero), normalized as there, and the smallest eigenvalue of their Gram matrix above
    ``CLEAR_RANK_GRAM``, the rows' smallest singular value exceeds ~1e-3 (the Gram matrix's rounding
    is below 1e-12 at any size met here), so every diagonal entry of the pivoted QR's R, the exact R of
    data within ~ng·nc·u of them, exceeds ~1e-3 > RANK_TOL·max(nc, ng)·|R₀₀| (|R₀₀| ≈ 1): the QR can
    only return every row, consistent, which is returned. A single row needs no test. Any other A,
    and a RANK_TOL·max(nc, ng) above 1e-4, goes to `independent_rows`. (The QR cost a third of the
    enumeration on LSUP's strip intersections and a tenth of LSU-CZ's reduction.)
    """
    nc, ng = A.shape
    if nc and tol.RANK_TOL * max(nc, ng) <= 1e-4:
        norms = np.linalg.norm(A, axis=1)           # as independent_rows computes them
        if norms.min() > _TINY and norms.max() < np.inf:    # (False for a NaN)
            if nc == 1:
                return RowBasis(np.zeros(1, dtype=np.intp), True)
            An = A / norms[:, None]
            # Two rows: the Gram matrix [[a, m], [m, d]] with a, d within ng·u of 1 has smallest
            # eigenvalue ≥ min(a, d) − |m|, so 1 − |m| > 2·CLEAR_RANK_GRAM settles it without eigvalsh.
            if (nc == 2 and 1.0 - abs(float(An[0] @ An[1])) > 2.0 * CLEAR_RANK_GRAM) \
                    or np.linalg.eigvalsh(An @ An.T)[0] > CLEAR_RANK_GRAM:
                return RowBasis(np.arange(nc, dtype=np.intp), True)
    return independent_rows(A, b)


@functools.lru_cache(maxsize=64)
def _bases(ng: int, nc: int) -> tuple[np.ndarray, np.ndarray]:
    """Every choice of nc basic factors among ng, and the other factors of each, read-only.

    Returns
    -------
    beta : ndarray of int, shape (C(ng, nc), nc)
        The basic factors of each choice, increasing (``itertools.combinations`` order).
    rest : ndarray of int, shape (C(ng, nc), ng − nc)
        The non-basic factors of each choice, increasing.

    Notes
    -----
    They depend on (ng, nc) alone, and the enumeration meets the same few sizes at every step of a
    filter: they are built once per size.
    """
    beta = np.array(list(itertools.combinations(range(ng), nc)), dtype=int)
    nonbasic = np.ones((beta.shape[0], ng), dtype=bool)
    nonbasic[np.arange(beta.shape[0])[:, None], beta] = False
    rest = np.nonzero(nonbasic)[1].reshape(beta.shape[0], ng - nc)
    beta.flags.writeable = rest.flags.writeable = False
    return beta, rest


@functools.lru_cache(maxsize=64)
def _signs(k: int) -> np.ndarray:
    """All 2^k vectors of ±1, shape (2^k, k), read-only (built once per k)."""
    S = np.ones((1, 0)) if k == 0 else 1.0 - 2.0 * ((np.arange(2 ** k)[:, None] >> np.arange(k)) & 1)
    S.flags.writeable = False
    return S


@dataclass(frozen=True)
class HullGeometry:
    """The convex hull of points in ℝⁿ (n ≥ 1) cut into simplices: volume, centroid, uniform draws.

    Attributes
    ----------
    vertices : ndarray, shape (k, n)
        The hull's vertices.
    simplices : ndarray, shape (s, n + 1, n)
        The hull as s n-simplices (a fan from an interior point over Qhull's triangulated facets).
    volumes : ndarray, shape (s,)
        Their volumes (n-dimensional Lebesgue measure).
    """

    vertices: np.ndarray
    simplices: np.ndarray
    volumes: np.ndarray

    @property
    def volume(self) -> float:
        """The hull's volume."""
        return float(self.volumes.sum())

    @property
    def centroid(self) -> np.ndarray:
        """The centre of mass of the hull (the mean of the uniform distribution on it)."""
        return (self.volumes @ self.simplices.mean(axis=1)) / self.volumes.sum()

    @property
    def covariance(self) -> np.ndarray:
        """The covariance of the uniform distribution on the hull, shape (n, n): each simplex's second
        moment is (Σᵢ vᵢvᵢᵀ + (Σᵢ vᵢ)(Σᵢ vᵢ)ᵀ) / ((n + 1)(n + 2)), weighted by volume."""
        n = self.simplices.shape[2]
        total = self.simplices.sum(axis=1)                                     # (s, n)
        second = (np.einsum("ski,skj->sij", self.simplices, self.simplices)
                  + np.einsum("si,sj->sij", total, total)) / ((n + 1) * (n + 2))
        mean = self.centroid
        return np.einsum("s,sij->ij", self.volumes, second) / self.volume - np.outer(mean, mean)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        """``size`` points drawn exactly uniformly: a simplex with probability ∝ its volume, then
        uniform barycentric weights (flat Dirichlet, normalized exponentials)."""
        which = rng.choice(self.volumes.size, size=size, p=self.volumes / self.volumes.sum())
        weights = rng.exponential(size=(size, self.simplices.shape[1]))
        weights /= weights.sum(axis=1, keepdims=True)
        return np.einsum("sk,skn->sn", weights, self.simplices[which])


def hull_geometry(points: np.ndarray) -> HullGeometry:
    """`HullGeometry` of the convex hull of ``points`` (shape (k, n)).

    Raises
    ------
    ValueError
        When the hull has no interior in ℝⁿ (fewer than n + 1 affinely independent points, up to
        ``VERTEX_TOL`` relative to the set's own extent), naming its dimension: volume, centroid and
        uniform sampling need a full-dimensional set.

    Notes
    -----
    Everything is computed on the points centred at their mean. Qhull's precision is relative to the
    largest coordinate it is given, so a thin set far from the origin (1 by 4·10⁻⁶ at 8.6·10⁹) is flat to it
    however clearly it has an interior, and it raised a QhullError; centred, its extent is its own
    scale. For the same reason the rank is decided relative to the largest singular value alone: with
    a floor of 1, a set 10⁻⁴ wide and 10⁻⁸ thick (an LSU support at small noise) was called flat.
    """
    P = np.asarray(points, dtype=float)
    k, n = P.shape
    if k == 0:
        raise ValueError("the set is empty")
    spread = P - P.mean(axis=0)
    s = np.linalg.svd(spread, compute_uv=False) if k > 1 else np.zeros(1)
    rank = int(np.count_nonzero(s > tol.VERTEX_TOL * s.max(initial=0.0))) if s.size else 0
    if rank < n:
        raise ValueError(f"the set lies in an affine subspace of dimension {rank} < {n} (no interior): "
                         "it has no volume, centroid or uniform distribution in this space")
    if n == 1:
        lo, hi = P.min(), P.max()
        return HullGeometry(np.array([[lo], [hi]]), np.array([[[lo], [hi]]]), np.array([hi - lo]))
    hull = ConvexHull(spread)
    vertices = P[hull.vertices]
    inner = vertices.mean(axis=0)
    facets = P[hull.simplices]                                          # (s, n, n), triangulated
    simplices = np.concatenate([np.broadcast_to(inner, (facets.shape[0], 1, n)), facets], axis=1)
    volumes = (np.abs(np.linalg.det(spread[hull.simplices] - spread[hull.vertices].mean(axis=0)))
               / math.factorial(n))
    keep = volumes > 0
    return HullGeometry(vertices, simplices[keep], volumes[keep])


def vertex_bounds(points: np.ndarray, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ranges [lo, hi] of the linear functionals (rows of ``D``) over the hull of ``points``, widened
    outward by ``VERTEX_FEASIBILITY_TOL`` times their scale (the enumeration's own slack), so that a
    vertex computed a rounding error inside its true place does not shrink the range.

    Parameters
    ----------
    points : ndarray, shape (k, n), k ≥ 1
    D : ndarray, shape (d, n)

    Returns
    -------
    lo, hi : ndarray, shape (d,)
    """
    values = points @ D.T
    scale = 1.0 + np.abs(points).max(axis=0) @ np.abs(D).T
    pad = tol.VERTEX_FEASIBILITY_TOL * scale
    return values.min(axis=0) - pad, values.max(axis=0) + pad
