"""Exact reductions: the set is unchanged, only its representation gets smaller.

* `DropZeros`: factors with a zero generator and a zero constraint column, and zero constraint rows;
* `DropDependentConstraints`: linearly dependent constraint rows (rank-revealing, `linalg.independent_rows`);
* `MergeParallelGenerators`: parallel generators of a zonotope, parallel lifted columns [g; a] of a CZ
  (columns parallel only up to ``PARALLEL_TOL`` keep their leftover in a box: a superset, never less).

An inconsistent constraint (a zero row with b ≠ 0, or a dependent row whose right-hand side disagrees)
means the set is empty, and the result is `EmptySet` once the emptiness program (`is_empty`, the
library's tolerance policy) agrees. Otherwise the disagreement is rounding left in the data by the set
algebra (a posterior that is a single point, from extreme noise realizations, comes out a hair
inconsistent) and the row is dropped like a dependent one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ... import tolerances as tol
from ...floating import gamma
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..cz_vertices import row_basis
from ..empty import EmptySet
from ..zonotope import Zonotope
from ._base import CZData, ReductionMethod, abs_sum_upper, round_up


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
        if not (sp.issparse(Z.G) or sp.issparse(Z.A)):
            # Nothing to drop (the usual case, twice per step of a reduced filter): the set itself,
            # as below, without the working copy.
            used = np.any(Z.G != 0.0, axis=0) | np.any(Z.A != 0.0, axis=0)
            if used.all() and np.any(Z.A != 0.0, axis=1).all():
                return Z
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
        basis = row_basis(d.A, d.b)   # linalg.independent_rows' answer, without its QR when clear
        if not basis.consistent and Z.is_empty():
            return EmptySet(Z.dim)
        return Z if basis.keep.size == Z.nc else d.keep_rows(basis.keep).to_set()

    def _on_box(self, B: Box) -> Box:
        return B


def parallel_groups(L: np.ndarray) -> list[np.ndarray]:
    """Candidate groups (of size ≥ 2) of non-zero columns of L parallel up to ``PARALLEL_TOL``.

    Candidates come from the Gram matrix of the unit columns (|cos| ≥ 1 − ``PARALLEL_COS_TOL``); each
    is confirmed on the columns themselves (‖u_i − s u_j‖∞ ≤ PARALLEL_TOL), which the Gram matrix
    cannot resolve below ~1e-8. Candidates are not assumed exactly parallel: `merge_group` keeps
    whatever is left over.
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
        cand = np.flatnonzero((np.abs(cos[i]) >= 1.0 - tol.PARALLEL_COS_TOL) & ~taken)
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


def merge_group(L: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, float, np.ndarray] | None:
    """Merge the columns L_k (bounds h_k) of one candidate group along v = L_0; None if not worth it.

    Each column splits as L_k = t_k v + e_k with t_k = vᵀL_k / vᵀv (any t_k would do: the split is an
    identity) and e_k ⟂ v. Then Σ_k L_k h_k ξ_k ⊆ v·[−H, H] ⊕ Σ_k h_k e_k ξ_k with H = Σ|t_k| h_k:
    the merged factor keeps the column v itself with bound H (rounded up), and the leftover is boxed,
    diag(Σ_k h_k |e_k|) rounded up, on the rows where it exceeds rounding level (``gamma`` of the
    computation: there it is the rounding of v's multiples, the contract of an exact method). So the
    result contains the set, and is the set when the columns are exactly parallel. A group is merged
    only when it shrinks (1 + boxed rows < group size); a group with a free factor (h = ∞) only when
    no leftover needs a box (one free factor along v then spans the group's line).

    Returns
    -------
    (v, H, box) : the kept column, its bound (∞ for a free group) and the box columns (rows × k'),
    or None when the group is better left as it is.
    """
    v = L[:, 0]
    t = (v @ L) / (v @ v)
    E = L - np.outer(v, t)
    rounding = gamma(2 * L.shape[0] + 4) * np.abs(L).max(axis=0)
    E = np.where(np.abs(E) <= rounding, 0.0, E)  # rounding of t_k v, not a leftover
    free = np.isinf(h)
    if free.any():
        return (v, np.inf, np.zeros((L.shape[0], 0))) if not E.any() else None
    H = float(abs_sum_upper((np.abs(t) * h)[None, :])[0])
    radius = abs_sum_upper(np.where(E == 0.0, 0.0, round_up(np.abs(E) * h)))
    rows = np.flatnonzero(radius > 0.0)
    if 1 + rows.size >= L.shape[1]:
        return None
    box = np.zeros((L.shape[0], rows.size))
    box[rows, np.arange(rows.size)] = radius[rows]
    return v, H, box


@dataclass(frozen=True)
class MergeParallelGenerators(ReductionMethod):
    """Merge parallel generators into one. Exact for exactly parallel columns, outer otherwise.

    For a zonotope, generators g_i ∥ g_j span the segment g_i ξ_i + g_j ξ_j = (g_i + s g_j) ξ with
    s = sign(g_iᵀ g_j). For a CZ the lifted columns [g_j; a_j] must be parallel (the factor enters the
    set and the constraints alike). Columns only nearly parallel (within ``PARALLEL_TOL``) are merged
    along the first one and their orthogonal leftovers boxed into extra generators (`merge_group`),
    so the result always contains the set; a group is merged only when that makes it smaller.
    ``exact`` stays True: the set grows only by the boxed leftover, at most ``PARALLEL_TOL`` relative
    to the merged columns, and not at all for exactly parallel ones.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> ss.reduce(ss.Zonotope([[1.0, -2.0, 0.0], [1.0, -2.0, 1.0]], [0.0, 0.0]),
    ...           ss.MergeParallelGenerators()).ng
    2
    """

    exact = True

    def _on_zonotope(self, Z: Zonotope) -> Zonotope:
        out = self._merge(Z.G, np.ones(Z.ng))
        if out is None:
            return Z
        L, h = out
        # A zonotope has no bounds: the merged bound scales its column (one rounding per entry).
        return Zonotope._trusted(L * h, Z.c)

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope):
        d = CZData.of(Z)
        out = self._merge(np.vstack([d.G, d.A]), d.h)
        if out is None:
            return Z
        L, h = out
        return CZData(L[:d.n], d.c, L[d.n:], d.b, h, d.sparse).to_set()

    @staticmethod
    def _merge(L: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """Lifted columns and bounds after merging every group worth it; None if none is."""
        merged, drop = [], []
        for g in parallel_groups(L):
            out = merge_group(L[:, g], h[g])
            if out is not None:
                merged.append(out)
                drop.extend(g)
        if not merged:
            return None
        keep = np.setdiff1d(np.arange(L.shape[1]), drop)
        cols = [L[:, keep]] + [np.hstack([v[:, None], box]) for v, _, box in merged]
        bounds = [h[keep]] + [np.concatenate([[H], np.ones(box.shape[1])]) for _, H, box in merged]
        return np.hstack(cols), np.concatenate(bounds)

    def _on_box(self, B: Box) -> Box:
        return B
