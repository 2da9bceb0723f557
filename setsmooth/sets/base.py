"""`ConvexSet`: a set is anything that can state "x is in me" as CVXPY constraints.

Every query is derived here once, through the generic CVXPY path of `setsmooth.solvers`.

Extension points for users (public, documented, stable): `ConvexSet.as_constrained_zonotope` (the set
is exactly a constrained zonotope: every query and estimator then takes the CZ fast path) and
`ConvexSet.support_function` / `ConvexSet.support_vectors` (a closed-form support function). The
library's own representations override private hooks (``_support``, ``_is_empty``, ``_contains``,
``_as_constrained_zonotope`` ...) where they know a closed form or a faster program; the private
``_as_constrained_zonotope`` stays the default of the public hook, so both spellings work.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from functools import cached_property
from typing import TYPE_CHECKING, Any, Sequence

import cvxpy as cp
import numpy as np

from .._validation import as_directions, as_matrix, as_vector
from ..solvers import GenericProgram
from ..solvers.closest import closest_point, fast_norm
from ..solvers.instances import cached_instance
from .extension import ExtensionPoints, checked_cz_form, overrides, user_points, user_values
from .hooks import AlgebraHooks
from .relations import SetRelations
from .vertices_2d import plot_set, polygon_area, vertices_2d
from .vertices_3d import plot_set_3d

if TYPE_CHECKING:  # pragma: no cover
    from .box import Box
    from .constrained_zonotope import ConstrainedZonotope

#: The solver paths a query can take: the closed form or fast path ('auto'), or CVXPY ('generic').
_PATHS = ("auto", "generic")


class ConvexSet(AlgebraHooks, ExtensionPoints, SetRelations, ABC):
    """A closed convex subset of ℝⁿ described by CVXPY constraints.

    Subclasses implement `constraints` and set ``dim``; every other query has a default here, and
    the set-algebra hooks (``_closed_*``) are declared with NotImplemented defaults in `AlgebraHooks`.
    Sets are immutable: operations return new sets and cache solver data on themselves.

    Attributes
    ----------
    dim : int
        Dimension n of the ambient space.
    """

    dim: int

    #: Makes ``ndarray @ S`` and ``ndarray + S`` defer to the set's reflected operators.
    __array_ufunc__ = None

    # -- the one required method ---------------------------------------------------------------------
    @abstractmethod
    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        """CVXPY constraints stating ``x ∈ self`` for an affine expression ``x`` of shape (dim,)."""

    # -- support functions ---------------------------------------------------------------------------
    def support(self, d: Any, *, path: str = "auto", certified: bool = False) -> float:
        """Support function h_S(d) = sup_{x∈S} dᵀx.

        Parameters
        ----------
        d : array_like, shape (dim,)
            Direction.
        path : {'auto', 'generic'}
            The solver path: 'auto' uses the representation's closed form or fast path; 'generic' forces the CVXPY path.
        certified : bool
            Return a value proven to be ≥ the exact support (weak duality), whatever the solver's
            accuracy. Available for sets that flatten to a constrained zonotope.

        Returns
        -------
        float
            ``+inf`` along unbounded directions, ``-inf`` for an empty set.
        """
        d = as_vector(d, "d", self.dim)
        return float(self.support_many(d[None, :], path=path, certified=certified)[0])

    def support_many(self, D: Any, *, path: str = "auto", certified: bool = False) -> np.ndarray:
        """Support values for every row of ``D`` (shape (k, dim)); see `support`."""
        D = as_directions(D, self.dim)
        return self._support_values(D, self._check_path(path), certified)

    def support_point(self, d: Any, *, path: str = "auto") -> np.ndarray:
        """A maximizer of dᵀx over the set (NaN entries when the support is infinite)."""
        d = as_vector(d, "d", self.dim)
        return self._support_points(d[None, :], self._check_path(path), False)[1][0]

    def _support_points(self, D: np.ndarray, path: str, certified: bool):
        """Values and points, trusted arguments. Dispatches to the fast hook unless told otherwise."""
        if path == "generic":
            if certified:
                raise ValueError("certified=True needs the constrained-zonotope fast path; "
                                 "path='generic' cannot certify its values")
            return self._generic.support(D)
        return self._support(D, certified)

    def _support_values(self, D: np.ndarray, path: str, certified: bool) -> np.ndarray:
        """Values only, trusted arguments: a user's closed form (`support_function`) without
        solving for maximizers; otherwise the values of `_support_points`."""
        if path == "auto" and not certified and overrides(self, "support_function"):
            return user_values(self, D)
        return self._support_points(D, path, certified)[0]

    def _support(self, D: np.ndarray, certified: bool):
        """Hook: (values, points). Default: the user's closed form (`support_function`,
        `support_vectors`) when given, else the CZ fast path when the set flattens to a CZ, else
        the generic path."""
        cz = self._flat_cz
        if not certified and overrides(self, "support_function"):
            values = user_values(self, D)
            if overrides(self, "support_vectors"):
                points = user_points(self, D)
            else:  # maximizers from a program; the values stay the closed form's
                points = self._program_support(D)[1]
            points[~np.isfinite(values)] = np.nan
            return values, points
        if cz is not None:
            return cz._support(D, certified)
        if certified:
            raise ValueError(f"certified support values are not available for {type(self).__name__}:"
                             " it does not flatten to a constrained zonotope")
        return self._generic.support(D)

    @property
    def _generic(self) -> GenericProgram:
        """This thread's compiled CVXPY program of the set (`solvers.instances`): never stored on
        the set, so that sets stay picklable and threads never share a solver."""
        return cached_instance(self, "generic", lambda: GenericProgram(self))

    @cached_property
    def _flat_cz(self) -> "ConstrainedZonotope | None":
        cz = self.as_constrained_zonotope()
        if cz is None or cz is self:
            return cz
        return checked_cz_form(self, cz)

    def _as_constrained_zonotope(self) -> "ConstrainedZonotope | None":
        """Hook: an exact CZ representation of this set, or None when there is none."""
        return None

    def to_constrained_zonotope(self) -> "ConstrainedZonotope":
        """The exact constrained-zonotope form of this set.

        Raises
        ------
        TypeError
            When the set has no exact CZ form (ellipsoids, H-polytopes, lazy sets of those).
        """
        cz = self._flat_cz
        if cz is None:
            raise TypeError(f"{type(self).__name__} has no exact constrained-zonotope form")
        return cz

    # -- emptiness and membership --------------------------------------------------------------------
    def is_empty(self, *, path: str = "auto") -> bool:
        """Whether the set has no point (a feasibility program)."""
        if self._check_path(path) == "generic":
            return self._generic.is_empty()
        return self._is_empty()

    def _is_empty(self) -> bool:
        cz = self._flat_cz
        return cz._is_empty() if cz is not None else self._generic.is_empty()

    # -- derived geometry ----------------------------------------------------------------------------
    def interval_hull(self, *, path: str = "auto",
                      certified: bool | None = None) -> "Box | ConvexSet":
        """The tightest box containing the set (2·dim support values, one stacked program).

        Parameters
        ----------
        path : {'auto', 'generic'}
        certified : bool or None
            None (default): certified where available, that is when the set flattens to a
            constrained zonotope and ``path='auto'``: the box's faces are weak-duality bounds that
            hold in floating point, so the box encloses every point of the set whatever the solver's
            accuracy (falling back to the solver's values only where no sound bound exists: free
            factors that are neither determined by bounded ones nor cancelled exactly). True:
            certified or raise. False: the solver's values (accurate to its tolerance, not
            enclosing).

        Returns
        -------
        Box
            With possibly infinite ``lo``/``hi``; an `EmptySet` when the set is empty. Computed once
            per (path, certified) and kept on the set (sets are immutable; `diameter` and `center`
            reuse it). The kept hull is an immutable Box, so the set stays picklable.
        """
        key = (self._check_path(path), certified)
        hulls = self.__dict__.setdefault("_interval_hulls", {})
        hull = hulls.get(key)
        if hull is None and key[0] == "auto" and certified is not True:
            # One set of solves gives the solver's values and their certified bounds: keep both.
            for flag, shared in (self._interval_hulls_at_once() or {}).items():
                hulls.setdefault(("auto", flag), shared)
            hull = hulls.get(key)
        if hull is None:
            hull = hulls[key] = self._interval_hull(*key)
            if key == ("auto", True):
                hulls.setdefault(("auto", None), hull)  # certified where available: it is
        return hull

    def _interval_hulls_at_once(self) -> "dict | None":
        """Hook: the fast path's interval hulls for several values of ``certified`` (keys False,
        None and, where a sound bound exists, True) from one set of solves, or None. Default: the
        CZ form's, when the support function is the CZ's (no closed form of the set's own)."""
        if type(self)._support is not ConvexSet._support or overrides(self, "support_function"):
            return None
        cz = self._flat_cz
        return cz._interval_hulls_at_once() if cz is not None and cz is not self else None

    @staticmethod
    def _box_of_supports(values: np.ndarray, dim: int) -> "Box | ConvexSet":
        """The box of support values along (e_1..e_n, −e_1..−e_n); the empty set for −inf."""
        from .box import Box
        from .empty import EmptySet

        hi, lo = values[:dim], -values[dim:]
        if np.isneginf(hi).any():
            return EmptySet(dim)
        return Box._trusted(lo, np.maximum(hi, lo))

    def _interval_hull(self, path: str, certified: bool) -> "Box | ConvexSet":
        if certified is None and (self._check_path(path) != "auto" or self._flat_cz is None):
            certified = False
        eye = np.eye(self.dim)
        values = self.support_many(np.vstack([eye, -eye]), path=path, certified=certified)
        return self._box_of_supports(values, self.dim)

    def diameter(self, *, path: str = "auto", certified: bool | None = None) -> float:
        """∞-norm diameter sup_{s,s'∈S} ‖s − s'‖∞: the widest edge of the interval hull.

        ``certified`` as in `interval_hull` (certified where available by default). Returns
        ``-inf`` for the empty set (the supremum over no pairs) and ``inf`` when unbounded.
        """
        hull = self.interval_hull(path=path, certified=certified)
        if hull.is_empty():
            return -np.inf
        return float(np.max(hull.hi - hull.lo))

    def center(self, method: str = "interval_hull", reference: Any = None,
               norm: float | str = 2) -> np.ndarray:
        """A point estimate of the set.

        Parameters
        ----------
        method : {'interval_hull', 'chebyshev', 'closest'}
            'interval_hull': centre of the interval hull, which is also the ∞-norm Chebyshev centre
            (the point minimizing the worst-case ∞-norm error over the set).
            'chebyshev': centre of the largest inscribed Euclidean ball (sets with an H-representation,
            ellipsoids, and sets that flatten to a constrained zonotope: see
            `ConstrainedZonotope.chebyshev_ball`, exact in 2-D and for zonotopes, an inner ball
            otherwise).
            'closest': the member closest to ``reference`` in the given ``norm`` (LSU paper,
            Method 2): one Clarabel program on the factor set when the set flattens to a
            constrained zonotope and ``norm`` is 1, 2 or inf (`solvers.closest`), the generic CVXPY
            path otherwise.
        reference : array_like, shape (dim,), optional
            Needed by 'closest'.
        norm : {2, 1, inf, 'inf'} or any p-norm CVXPY accepts
            Norm of 'closest'.

        Returns
        -------
        ndarray, shape (dim,)
            NaN entries when the set is empty.
        """
        if method == "interval_hull":
            hull = self.interval_hull()
            if hull.is_empty():
                return np.full(self.dim, np.nan)
            return hull.midpoint()
        if method == "chebyshev":
            return self._chebyshev_center()
        if method == "closest":
            if reference is None:
                raise ValueError("center(method='closest') needs a reference point")
            ref = as_vector(reference, "reference", self.dim)
            point = self._closest_point(ref, norm)
            return np.full(self.dim, np.nan) if point is None else point
        raise ValueError(f"method must be 'interval_hull', 'chebyshev' or 'closest', got {method!r}")

    def _closest_point(self, reference: np.ndarray, norm) -> np.ndarray | None:
        """A member closest to ``reference`` (None when empty): the fast path when the set
        flattens to a CZ and ``norm`` is 1, 2 or ∞, the generic path otherwise."""
        cz, p = self._flat_cz, fast_norm(norm)
        if cz is None or p is None:
            return self._generic.closest_point(reference, norm)
        return closest_point(cz.G, cz.c, cz.A, cz.b, cz.h, reference, p)

    def _chebyshev_center(self) -> np.ndarray:
        cz = self._flat_cz
        if cz is not None:
            return cz.chebyshev_ball().center
        raise NotImplementedError(
            f"the inscribed-ball Chebyshev centre needs an H-representation or a constrained-zonotope "
            f"form; {type(self).__name__} has neither (use center('interval_hull'), the ∞-norm "
            "Chebyshev centre)")

    def vertices_2d(self) -> np.ndarray:
        """Vertices of a bounded 2-D set in counter-clockwise order (see `setsmooth.sets.vertices_2d`)."""
        return vertices_2d(self)

    def area(self) -> float:
        """Area of a bounded 2-D set (shoelace formula on `vertices_2d`)."""
        return polygon_area(self.vertices_2d())

    def plot(self, ax=None, dims: Sequence[int] = (0, 1), **kwargs):
        """Draw the projection onto ``dims`` and return the matplotlib artist.

        Two ``dims``: a `matplotlib.patches.Polygon` on a 2-D axes (`vertices_2d.plot_set`). Three
        ``dims``: a `Poly3DCollection` of the exact polytope (curved sets: refined to the
        vertex tolerance) on a 3-D axes (`vertices_3d.plot_set_3d`; ``ax`` from
        ``fig.add_subplot(projection='3d')``). Keyword arguments go to the artist.
        """
        if len(tuple(dims)) == 3:
            return plot_set_3d(self, ax=ax, dims=dims, **kwargs)
        return plot_set(self, ax=ax, dims=dims, **kwargs)

    def sample(self, rng: np.random.Generator, size: int = 1, *, method: str = "auto") -> np.ndarray:
        """Points drawn uniformly from a bounded set, shape (size, dim).

        ``method='auto'`` samples exactly from the simplices of the vertex hull when the set flattens
        to a small low-dimensional CZ, and by hit-and-run otherwise (closed-form chords for an
        H-polytope, one program per move for other sets, re-solved along the walk where the set has a
        constrained-zonotope form); 'exact', 'hit_and_run' and 'rejection'
        force one (`setsmooth.sets.sampling.uniform_sample`). Representations with a direct sampler
        (boxes, ellipsoids) override it.
        """
        from .sampling import uniform_sample

        return uniform_sample(self, rng, size, method)

    # -- algebra (see setsmooth.sets.algebra for the widening rules) ---------------------------------
    def __matmul__(self, other):
        return NotImplemented

    def __rmatmul__(self, M):
        from .algebra import linear_map

        return linear_map(as_matrix(M, "M", cols=self.dim, allow_sparse=True), self)

    def __add__(self, other):
        from .algebra import minkowski_sum, translate

        if isinstance(other, ConvexSet):
            _same_dim(self, other, "Minkowski sum")
            return minkowski_sum(self, other)
        return translate(self, as_vector(other, "translation vector", self.dim))

    __radd__ = __add__

    def __sub__(self, other):
        """``S - T`` is the Minkowski sum S ⊕ (−T) = {s − t : s ∈ S, t ∈ T}, and ``S - v`` a
        translation; it is NOT the Pontryagin difference {x : x + T ⊆ S}, which is
        `pontryagin_difference` (S ⊕ (−T) grows, S ⊖ T shrinks)."""
        if isinstance(other, ConvexSet):
            return self + (-np.eye(other.dim)) @ other
        return self + (-as_vector(other, "translation vector", self.dim))

    def __neg__(self):
        return (-np.eye(self.dim)) @ self

    def __and__(self, other):
        from .algebra import intersection

        if not isinstance(other, ConvexSet):
            return NotImplemented
        _same_dim(self, other, "intersection")
        return intersection(self, other)

    def __mul__(self, other):
        from .algebra import cartesian_product

        if not isinstance(other, ConvexSet):
            return NotImplemented
        return cartesian_product(self, other)

    def intersect_preimage(self, R: Any, Y: "ConvexSet") -> "ConvexSet":
        """Generalized intersection {s ∈ S : R s ∈ Y} (smoothing paper (37)).

        Parameters
        ----------
        R : array_like, shape (Y.dim, self.dim)
        Y : ConvexSet
        """
        from .algebra import generalized_intersection

        if not isinstance(Y, ConvexSet):
            raise TypeError(f"Y must be a ConvexSet, got {type(Y).__name__}")
        R = as_matrix(R, "R", rows=Y.dim, cols=self.dim, allow_sparse=True)
        return generalized_intersection(self, R, Y)

    def preimage(self, M: Any) -> "ConvexSet":
        """{x : M x ∈ S} for ``M`` of shape (dim, n); M may be singular or non-square."""
        from .reals import Reals

        M = as_matrix(M, "M", rows=self.dim, allow_sparse=True)
        return Reals(M.shape[1]).intersect_preimage(M, self)

    def project(self, dims: Sequence[int]) -> "ConvexSet":
        """Coordinate projection onto ``dims`` (in the given order)."""
        idx = _as_dims(dims, self.dim)
        return self._project(idx)

    def _project(self, idx: np.ndarray) -> "ConvexSet":
        return np.eye(self.dim)[idx] @ self

    def _check_path(self, path: str) -> str:
        if path not in _PATHS:
            raise ValueError(f"path must be one of {_PATHS}, got {path!r}")
        return path

    def __repr__(self) -> str:
        return f"{type(self).__name__}(dim={self.dim})"

    # -- pickling (process pools, Dask) ----------------------------------------------------------------
    #: Caches derived from the representation (cached properties): rebuilt on demand after
    #: unpickling rather than shipped. Solver instances are never on a set at all (they live in the
    #: per-thread cache of `solvers.instances`), so no query can make a set unpicklable.
    #: ``_polygon_form`` is a 2-D polytope's `Polygon` (`polygon`), kept by the polygon algebra.
    _DERIVED = ("_flat_cz", "_program", "_polygon_form", "_vertices")

    def __getstate__(self) -> dict:
        return {name: value for name, value in self.__dict__.items() if name not in self._DERIVED}

    def __setstate__(self, state: dict) -> None:
        # Pickle restores arrays writeable; a set's arrays stay read-only (sets are immutable).
        for value in state.values():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
        self.__dict__.update(state)


def _same_dim(a: ConvexSet, b: ConvexSet, what: str) -> None:
    if a.dim != b.dim:
        raise ValueError(f"{what} needs operands of equal dimension, got {a.dim} and {b.dim}")


def _as_dims(dims: Sequence[int], n: int) -> np.ndarray:
    raw = np.asarray(dims).reshape(-1)
    # np.asarray(..., dtype=int) would truncate 0.7 to 0 and read True as 1: refuse both.
    if raw.size and (raw.dtype == bool or not np.issubdtype(raw.dtype, np.integer)):
        raise TypeError(f"dims must be a sequence of integers, got {dims!r}")
    idx = raw.astype(int)
    if idx.size == 0 or (idx < 0).any() or (idx >= n).any():
        raise ValueError(f"dims must be non-empty indices in [0, {n}), got {list(idx)}")
    return idx
