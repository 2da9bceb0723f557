"""Membership, containment and differences as `ConvexSet` methods (inherited by every set).

The work is done in `setsmooth.sets.membership` (scale-relative margins), `setsmooth.sets.containment`
(S ⊆ T) and `setsmooth.sets.difference` (S ⊖ T); these methods validate and dispatch.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import as_vector, real_number

if TYPE_CHECKING:  # pragma: no cover
    from .base import ConvexSet


class SetRelations:
    """`contains`, ``p in S``, `is_subset` (``S <= T``) and `pontryagin_difference`."""

    __slots__ = ()

    def contains(self, point: Any, tol: float | None = None, *, path: str = "auto") -> bool:
        """Whether ``point`` lies in the set, up to a margin.

        Parameters
        ----------
        point : array_like, shape (dim,)
        tol : float, optional
            Absolute ∞-norm margin: True when some member lies within ``tol`` of ``point``. By
            default the margin is relative to the set's own scale, per coordinate
            (`setsmooth.sets.membership.default_margins`): ``MEMBERSHIP_TOL`` times the width of
            the set's interval hull in that coordinate, plus ``MAGNITUDE_TOL`` times the
            coordinates' magnitude (the rounding the set algebra accumulates). A box of width 1e-9
            thus holds no point a thousandth of its width away, and a set measured in km along one
            axis and in µm along another is judged in both units. Coordinates along which the set
            is unbounded have no own scale; they keep ``MEMBERSHIP_TOL · max(1, |p_i|)``.
            The programs are solved in coordinates normalized by the margins, so the solver's
            accuracy is relative to the set's size; a set whose CVXPY constraints carry auxiliary
            variables at a large position (lazy sums and intersections of sets far from the
            origin) is resolved only to ``SOLVER_TOL`` times that position.
        path : {'auto', 'generic'}

        Returns
        -------
        bool

        Examples
        --------
        >>> import setsmooth as ss
        >>> tiny = ss.Box([0.0], [1e-9])
        >>> tiny.contains([0.5e-9]), tiny.contains([50e-9]), [50e-9] in tiny
        (True, False, False)
        """
        from .membership import default_margins, settled_without_hull

        p = as_vector(point, "point", self.dim)
        path = self._check_path(path)
        if tol is None and path == "auto":
            verdict = settled_without_hull(self, p)
            if verdict is not None:
                return verdict
        margin = self._margin(p, tol) if tol is not None else default_margins(self, p, path)
        if margin is None:  # the set is empty
            return False
        if path == "generic":
            from .membership import generic_contains

            return generic_contains(self, p, margin)
        return self._contains(p, margin)

    def __contains__(self, point: Any) -> bool:
        """``point in S``: `contains` with the default, scale-relative margin."""
        from .base import ConvexSet

        if isinstance(point, ConvexSet):
            raise TypeError("`in` tests membership of a point; for sets use S.is_subset(T) or S <= T")
        return self.contains(point)

    def _contains(self, p: np.ndarray, margin: "float | np.ndarray") -> bool:
        """Hook: membership with an ∞-norm margin, a float or one per coordinate (shape (dim,))."""
        from .membership import generic_contains

        cz = self._flat_cz
        return cz._contains(p, margin) if cz is not None else generic_contains(self, p, margin)

    @staticmethod
    def _margin(p: np.ndarray, given: float) -> float:
        value = real_number(given, "tol")
        if not np.isfinite(value) or value < 0:
            raise ValueError(f"tol must be a finite non-negative number, got {given}")
        return value

    def is_subset(self, other: "ConvexSet", tol: float | None = None):
        """Whether this set is contained in ``other``: see `setsmooth.sets.containment.is_subset`.

        Returns a `Containment` (truthy when containment is established), which says whether the
        test was exact or only sufficient.
        """
        from .containment import is_subset

        return is_subset(self, other, tol=tol)

    def __le__(self, other):
        from .base import ConvexSet

        if not isinstance(other, ConvexSet):
            return NotImplemented
        return self.is_subset(other)

    def __ge__(self, other):
        from .base import ConvexSet

        if not isinstance(other, ConvexSet):
            return NotImplemented
        return other.is_subset(self)

    def pontryagin_difference(self, other: "ConvexSet", method: str = "exact") -> "ConvexSet":
        """{x : x + other ⊆ self}: see `setsmooth.sets.difference.pontryagin_difference`.

        Not the same as ``self - other``, which is the Minkowski sum self ⊕ (−other).
        """
        from .difference import pontryagin_difference

        return pontryagin_difference(self, other, method=method)
