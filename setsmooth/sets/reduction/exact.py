"""Exact reductions: the set is unchanged, only its representation gets smaller.

* `DropZeros`: factors with a zero generator and a zero constraint column, and zero constraint rows;
* `DropDependentConstraints`: linearly dependent constraint rows (rank-revealing, `linalg.independent_rows`);
* `MergeParallelGenerators`: parallel generators of a zonotope, parallel lifted columns [g; a] of a CZ.

An inconsistent constraint (a zero row with b ≠ 0, or a dependent row whose right-hand side disagrees)
means the set is empty, and the result is `EmptySet` once the emptiness program (`is_empty`, the
library's tolerance policy) agrees. Otherwise the disagreement is rounding left in the data by the set
algebra (a posterior that is a single point, from extreme noise realizations, comes out a hair
inconsistent) and the row is dropped like a dependent one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import tolerances as tol
from ...linalg import independent_rows
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..empty import EmptySet
from ..zonotope import Zonotope
from ._base import CZData, ReductionMethod


def _zero_rows_consistent(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, bool]:
    """Indices of the non-zero rows of A, and whether every zero row reads 0 = b_i.

    A b_i left over by cancellation is rounding: it is judged against the data with the tolerance of
    `linalg.independent_rows` (√RANK_TOL relative), so rounding never turns a set into the empty set.
    """
    zero = ~np.any(A != 0.0, axis=1)
    norms = np.linalg.norm(A[~zero], axis=1)
    scale = 1.0 + np.max(np.abs(b[~zero]) / norms, initial=0.0)
    consistent = bool(np.all(np.abs(b[zero]) <= np.sqrt(tol.RANK_TOL) * scale))
    return np.flatnonzero(~zero), consistent


@dataclass(frozen=True)
class DropZeros(ReductionMethod):
    """Drop zero generators (with zero constraint columns) and zero constraint rows. Exact.

    A factor whose generator and constraint column are both zero does not move the set, whatever its
    bound (free factors included). A zero row 0·ξ = b_i is dropped when b_i = 0 (up to rounding);
    otherwise the result is `EmptySet` when `is_empty` agrees (see the module notes).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.ConstrainedZonotope([[1.0, 0.0]], [0.0], A=[[1.0, 0.0], [0.0, 0.0]], b=[0.5, 0.0])
    >>> ss.reduce(Z, ss.DropZeros())
    ConstrainedZonotope(dim=1, ng=1, nc=1)
    """

    exact = True

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        keep = np.flatnonzero(np.any(Z.G != 0.0, axis=0))
        return Z if keep.size == Z.ng else Zonotope._trusted(Z.G[:, keep], Z.c)

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        d = CZData.of(Z)
        rows, consistent = _zero_rows_consistent(d.A, d.b)
        if not consistent and Z.is_empty():
            return EmptySet(Z.dim)
        d = d.keep_rows(rows)
        used = np.any(d.G != 0.0, axis=0) | np.any(d.A != 0.0, axis=0)
        d = d.keep_factors(np.flatnonzero(used))
        return Z if (d.ng, d.nc) == (Z.ng, Z.nc) else d.to_set()

    def _on_box(self, B: Box) -> Box:
        return B  # a box has no generators or constraints to drop


@dataclass(frozen=True)
class DropDependentConstraints(ReductionMethod):
    """Keep a maximal linearly independent set of constraint rows (`linalg.independent_rows`). Exact.

    The rank decision is relative (``RANK_TOL``); a dropped row whose right-hand side contradicts the
    kept ones gives `EmptySet` when `is_empty` agrees (see the module notes).
    """

    exact = True

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        return Z  # no constraints

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        if Z.nc == 0:
            return Z
        d = CZData.of(Z)
        basis = independent_rows(d.A, d.b)
        if not basis.consistent and Z.is_empty():
            return EmptySet(Z.dim)
        return Z if basis.keep.size == Z.nc else d.keep_rows(basis.keep).to_set()

    def _on_box(self, B: Box) -> Box:
        return B


def parallel_groups(L: np.ndarray) -> list[np.ndarray]:
    """Groups (of size ≥ 2) of non-zero columns of L that are parallel, up to ``PARALLEL_TOL``.

    Candidates come from the Gram matrix of the unit columns; each is confirmed on the columns
    themselves (‖u_i − s u_j‖∞ ≤ PARALLEL_TOL), which the Gram matrix cannot resolve below ~1e-8.
    """
    norms = np.linalg.norm(L, axis=0)
    nz = np.flatnonzero(norms > 0.0)
    if nz.size < 2:
        return []
    U = L[:, nz] / norms[nz]
    cos = U.T @ U
    taken = np.zeros(nz.size, dtype=bool)
    groups = []
    for i in range(nz.size):
        if taken[i]:
            continue
        cand = np.flatnonzero((np.abs(cos[i]) >= 1.0 - 1e-6) & ~taken)
        cand = cand[cand > i]
        if cand.size == 0:
            continue
        s = np.sign(cos[i, cand])
        close = np.abs(U[:, cand] - s * U[:, [i]]).max(axis=0) <= tol.PARALLEL_TOL
        members = cand[close]
        if members.size:
            taken[members] = True
            taken[i] = True
            groups.append(nz[np.concatenate([[i], members])])
    return groups


@dataclass(frozen=True)
class MergeParallelGenerators(ReductionMethod):
    """Merge parallel generators into one. Exact.

    For a zonotope, generators g_i ∥ g_j span the segment g_i ξ_i + g_j ξ_j = (g_i + s g_j) ξ with
    s = sign(g_iᵀ g_j). For a CZ the lifted columns [g_j; a_j] must be parallel (the factor enters the
    set and the constraints alike); merged factors with bounds h become one column Σ s_k h_k [g_k; a_k]
    with bound 1, and a group with a free factor (h = ∞) one free factor along the common direction.
    """

    exact = True

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        groups = parallel_groups(Z.G)
        if not groups:
            return Z
        G = Z.G.copy()
        drop = []
        for g in groups:
            s = np.sign(G[:, g[1:]].T @ G[:, g[0]])
            G[:, g[0]] = G[:, g[0]] + G[:, g[1:]] @ s
            drop.extend(g[1:])
        return Zonotope._trusted(np.delete(G, drop, axis=1), Z.c)

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        d = CZData.of(Z)
        L = np.vstack([d.G, d.A])
        groups = parallel_groups(L)
        if not groups:
            return Z
        h = d.h.copy()
        drop = []
        for g in groups:
            first = L[:, g[0]]
            if np.isinf(h[g]).any():
                L[:, g[0]] = first / np.linalg.norm(first)
                h[g[0]] = np.inf
            else:
                s = np.sign(L[:, g].T @ first)
                L[:, g[0]] = L[:, g] @ (s * h[g])
                h[g[0]] = 1.0
            drop.extend(g[1:])
        L = np.delete(L, drop, axis=1)
        out = CZData(L[:d.n], d.c, L[d.n:], d.b, np.delete(h, drop), d.sparse)
        return out.to_set()

    def _on_box(self, B: Box) -> Box:
        return B
