"""The public extension points of `ConvexSet`, for users' own set representations.

* `ExtensionPoints.as_constrained_zonotope`: the set is exactly a constrained zonotope; every query,
  filter, smoother and trajectory set then takes the sparse CZ fast path.
* `ExtensionPoints.support_function` (and `ExtensionPoints.support_vectors`): a closed-form support
  function, used instead of a program wherever values (or maximizers) suffice.

They are ordinary overridable methods with documented contracts; the library's own representations
override the private hooks instead (``_support``, ``_as_constrained_zonotope``), and
``_as_constrained_zonotope`` stays the default of the public hook. `setsmooth.sets.base` dispatches to
them (`overrides` says whether a class overrides one) and checks what they return at the door.

The one required method, ``constraints(x)``, is checked too when a user's class defines it: every
program calls it (the generic path, membership, lazy sets, trajectory programs), so a constraint that
is not convex is named with the set's class at the first query rather than as CVXPY's ``DCPError``
from inside a solver call.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any

import cvxpy as cp
import numpy as np

from .._validation import as_directions

if TYPE_CHECKING:  # pragma: no cover
    from .constrained_zonotope import ConstrainedZonotope


class ExtensionPoints:
    """The public hooks a user representation may override (inherited by every `ConvexSet`)."""

    __slots__ = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        own = vars(cls).get("constraints")
        # The library's own representations are trusted (and tested); users' are checked.
        if own is not None and not cls.__module__.startswith("setsmooth."):
            cls.constraints = _convexity_checked(own)

    def as_constrained_zonotope(self) -> "ConstrainedZonotope | None":
        """Extension point: an exact constrained-zonotope form of this set, or None.

        Override it in a representation that is exactly a CZ Z(G, c, A, b, h) (smoothing paper
        Definition 2): every query (support, emptiness, membership, interval hull) then takes the
        sparse CZ fast path with certified values, and filters, smoothers and trajectory sets use
        the closed forms of smoothing (35)–(37) instead of CVXPY. It is called once per set (the
        result is kept), so it may build the matrices. Returning another set that is exactly a CZ
        (a `Zonotope`, a bounded `Box`) is accepted. The default returns the library's private
        hook ``_as_constrained_zonotope()`` (None for a set without an exact CZ form).

        Returns
        -------
        ConstrainedZonotope or None
            Must be the same set, of dimension ``dim``; None when there is no exact CZ form.

        Examples
        --------
        >>> import numpy as np, setsmooth as ss
        >>> class Cross(ss.ConvexSet):  # the ℓ1 ball of ℝ² = the zonotope of (1, 1) and (1, −1) halved
        ...     dim = 2
        ...     def constraints(self, x):
        ...         import cvxpy as cp
        ...         return [cp.norm1(x) <= 1]
        ...     def as_constrained_zonotope(self):
        ...         return ss.ConstrainedZonotope(0.5 * np.array([[1.0, 1.0], [1.0, -1.0]]), np.zeros(2))
        >>> round(Cross().support([1.0, 0.0]), 9)
        1.0
        """
        return self._as_constrained_zonotope()

    def support_function(self, D: np.ndarray) -> np.ndarray:
        """Extension point: the support values h_S(d) = sup_{x∈S} dᵀx of every row d of ``D``.

        Override it in a representation with a closed-form support function: `support`,
        `support_many`, `interval_hull`, `diameter`, containment tests and the lazy algebra (sums,
        linear maps, products of this set) then use it instead of a convex program. Override
        `support_vectors` too when the maximizers are known in closed form; otherwise they come
        from a program when a query needs them (`support_point`, `vertices_2d`, plotting). Called
        with a trusted float array of shape (k, dim); must return shape (k,) (``+inf`` along
        unbounded directions, ``-inf`` for an empty set). Certified queries (``certified=True``)
        use the CZ fast path when the set has one, never this override.

        The default (not overridden) computes the values by the set's own programs.

        Parameters
        ----------
        D : ndarray, shape (k, dim)
            Directions, one per row.

        Returns
        -------
        ndarray, shape (k,)
        """
        return self.support_many(D)

    def support_vectors(self, D: np.ndarray) -> np.ndarray:
        """Extension point: a maximizer of dᵀx over the set for every row d of ``D``, shape (k, dim).

        Override it together with `support_function` when the maximizers have a closed form. The
        default computes them (the set's program).
        """
        D = as_directions(D, self.dim)
        if overrides(self, "support_vectors"):  # called as super().support_vectors(D)
            return self._program_support(D)[1]
        return self._support_points(D, "auto", False)[1]

    def _program_support(self, D: np.ndarray):
        """(values, points) from a program: the CZ fast path, else the generic path."""
        cz = self._flat_cz
        return cz._support(D, False) if cz is not None else self._generic.support(D)


def _convexity_checked(constraints):
    """A user's ``constraints(self, x)`` that checks its result: CVXPY constraints, each convex (DCP)."""
    if getattr(constraints, "__isabstractmethod__", False):
        return constraints

    @functools.wraps(constraints)
    def checked(self, x):
        cons = list(constraints(self, x))
        what = f"{type(self).__name__}.constraints(x)"
        for c in cons:
            if not isinstance(c, cp.constraints.constraint.Constraint):
                raise TypeError(f"{what} must return CVXPY constraints, got a {type(c).__name__}: {c!r}")
            if not c.is_dcp():
                raise TypeError(f"{what} returned a constraint that is not convex under CVXPY's DCP "
                                f"rules: {c}. A ConvexSet is described by convex constraints: affine "
                                "equalities, convex ≤ concave (https://www.cvxpy.org/tutorial/dcp/)")
        return cons

    return checked


def overrides(S, name: str) -> bool:
    """Whether the class of ``S`` overrides the public extension point ``name``."""
    return getattr(type(S), name) is not getattr(ExtensionPoints, name)


def user_values(S, D: np.ndarray) -> np.ndarray:
    values = np.asarray(S.support_function(D), dtype=float).reshape(-1)
    if values.shape != (D.shape[0],) or np.isnan(values).any():
        raise ValueError(f"{type(S).__name__}.support_function must return {D.shape[0]} values "
                         f"(one per direction, no NaN), got shape {np.shape(values)}")
    return values


def user_points(S, D: np.ndarray) -> np.ndarray:
    points = np.array(S.support_vectors(D), dtype=float)
    if points.shape != D.shape:
        raise ValueError(f"{type(S).__name__}.support_vectors must return shape {D.shape} "
                         f"(one point per direction), got {points.shape}")
    return points


def checked_cz_form(S, cz: Any) -> "ConstrainedZonotope":
    """The CZ a user's `as_constrained_zonotope` returned, checked at the door."""
    from .base import ConvexSet
    from .constrained_zonotope import ConstrainedZonotope

    what = f"{type(S).__name__}.as_constrained_zonotope()"
    if isinstance(cz, ConvexSet) and not isinstance(cz, ConstrainedZonotope):
        inner = cz._flat_cz
        if inner is None:
            raise TypeError(f"{what} returned a {type(cz).__name__}, which is not exactly a "
                            "constrained zonotope; return a ConstrainedZonotope (or None)")
        cz = inner
    if not isinstance(cz, ConstrainedZonotope):
        raise TypeError(f"{what} must return a ConstrainedZonotope or None, got {type(cz).__name__}")
    if cz.dim != S.dim:
        raise ValueError(f"{what} returned a set of dimension {cz.dim}; the set has dim = {S.dim}")
    return cz
