"""The reduction-method protocol: a method is a frozen value with one hook per set type it handles.

`ReductionMethod.apply` dispatches on the set's type to the hooks ``_on_zonotope``,
``_on_constrained_zonotope`` and ``_on_box``; the empty set goes through unchanged. A hook a method
does not define raises `NotImplementedError` naming the method and the type: no method ever falls back
silently to another one.

The helpers below hold the data of a constrained zonotope as dense arrays while a method works on it,
and the rounding bounds that keep outer approximations outer in floating point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ...floating import gamma
from ..base import ConvexSet
from ..box import Box
from ..constrained_zonotope import ConstrainedZonotope
from ..empty import EmptySet
from ..zonotope import Zonotope


class ReductionMethod:
    """Base of every order-reduction method (a frozen dataclass in each subclass).

    ``exact`` says whether the method returns the same set (up to rounding) or an outer
    approximation. Subclasses override the hooks of the types they handle.
    """

    exact: bool = False

    def apply(self, S: ConvexSet) -> ConvexSet:
        """Apply the method to ``S`` (trusted: ``S`` is a ConvexSet)."""
        if isinstance(S, EmptySet):
            return S
        # ConstrainedZonotope first: the order of the checks decides nothing today (no subclassing
        # between these types) but states which representation wins if that ever changes.
        # A set that carries its algebra's rounding charges (`setsmooth.sets.rounding`) is reduced
        # with them written as generators, so that the methods see data meaning what they say.
        if isinstance(S, ConstrainedZonotope):
            return self._on_constrained_zonotope(S.materialized())
        if isinstance(S, Zonotope):
            return self._on_zonotope(S.materialized())
        if isinstance(S, Box):
            return self._on_box(S)
        raise self._unsupported(S)

    def _on_zonotope(self, Z: Zonotope) -> ConvexSet:
        raise self._unsupported(Z)

    def _on_constrained_zonotope(self, Z: ConstrainedZonotope) -> ConvexSet:
        raise self._unsupported(Z)

    def _on_box(self, B: Box) -> ConvexSet:
        raise self._unsupported(B)

    def _unsupported(self, S: ConvexSet) -> NotImplementedError:
        return NotImplementedError(f"{self!r} has no implementation for {type(S).__name__}; "
                                   "order reduction handles Zonotope, ConstrainedZonotope, Box and "
                                   "EmptySet (convert the set first, e.g. to_constrained_zonotope())")


@dataclass
class CZData:
    """Dense working copy of Z(G, c, A, b, h); ``sparse`` remembers the input's storage."""

    G: np.ndarray
    c: np.ndarray
    A: np.ndarray
    b: np.ndarray
    h: np.ndarray
    sparse: bool

    @classmethod
    def of(cls, Z: ConstrainedZonotope) -> "CZData":
        sparse = sp.issparse(Z.G) or sp.issparse(Z.A)
        G = Z.G.toarray() if sp.issparse(Z.G) else np.array(Z.G)
        A = Z.A.toarray() if sp.issparse(Z.A) else np.array(Z.A)
        return cls(G, np.array(Z.c), A, np.array(Z.b), np.array(Z.h), sparse)

    @property
    def n(self) -> int:
        return self.G.shape[0]

    @property
    def ng(self) -> int:
        return self.G.shape[1]

    @property
    def nc(self) -> int:
        return self.A.shape[0]

    def keep_factors(self, idx) -> "CZData":
        return CZData(self.G[:, idx], self.c, self.A[:, idx], self.b, self.h[idx], self.sparse)

    def keep_rows(self, idx) -> "CZData":
        return CZData(self.G, self.c, self.A[idx], self.b[idx], self.h, self.sparse)

    def to_set(self) -> ConstrainedZonotope:
        G, A = self.G, self.A
        if self.sparse:
            G, A = sp.csc_matrix(G), sp.csc_matrix(A)
        return ConstrainedZonotope._trusted(G, self.c, A, self.b, self.h)


def round_up(x: np.ndarray) -> np.ndarray:
    """The next float above each entry: covers one correctly rounded operation."""
    return np.nextafter(x, np.inf)


def round_down(x: np.ndarray) -> np.ndarray:
    """The next float below each entry."""
    return np.nextafter(x, -np.inf)


def abs_sum_upper(M: np.ndarray, axis: int = 1) -> np.ndarray:
    """An upper bound, rigorous in floating point, on Σ|M_ij| along ``axis`` (γ_k of the k terms)."""
    k = M.shape[axis]
    s = np.abs(M).sum(axis=axis)
    # An exactly zero sum (every term zero) stays zero: no rounding happened.
    return np.where(s == 0.0, 0.0, round_up(s * (1.0 + 2.0 * gamma(k + 1))))


def scaled_abs_upper(M: np.ndarray, h: np.ndarray) -> np.ndarray:
    """|M_ij|·h_j rounded up, entry by entry (exact where h_j = 1 or the product is 0; 0·∞ = 0)."""
    with np.errstate(invalid="ignore"):
        P = np.abs(M) * h
    P = np.where(M == 0.0, 0.0, P)  # a free factor (h = ∞) the row does not see
    return np.where((h == 1.0) | (P == 0.0), P, round_up(P))


def certified_margin(terms: int, scale) -> np.ndarray:
    """Widening of a certified (weak-duality) support value for its own floating-point evaluation.

    The certificate is a dot product of ``terms`` terms of magnitude ``scale`` at most (data and dual
    values); 8·γ_terms·scale bounds its rounding with a margin for the products forming the terms.
    Used by `Rescale('exact')` and `IntervalHull`.
    """
    return 8.0 * gamma(terms) * np.asarray(scale, dtype=float)
