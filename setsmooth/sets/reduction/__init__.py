"""Order reduction: methods are values, applied by one function, `reduce(S, method_or_methods)`.

Exact (the set is unchanged, up to rounding): `DropZeros`, `DropDependentConstraints`,
`MergeParallelGenerators`, `Rescale` ('iter' | 'exact', Scott et al. 2016 §4.1).
Outer approximations (the result contains the set, in floating point too): `EliminateConstraints`
(Scott §4.2), `Girard`, `Combastel` (for CZs through the lifted zonotope, Scott §4.3), `IntervalHull`.

A method that has no implementation for a set's type raises `NotImplementedError` naming both; no
method falls back to another. The empty set is returned unchanged; a method that finds a set empty
returns `EmptySet`. Free factors (h = ∞) are handled exactly or refused with a `ValueError`; no finite
bound is ever invented for them.

Floating point: every computed *bound* (propagated factor ranges, the factor radii of rescaling, box
radii of `Girard`/`Combastel`, interval hulls) is rounded outward with a rigorous rounding-error bound
(γ_k of Higham), and merged bounds are rounded up, so those steps lose nothing in floating point. The
affine re-parametrizations are not: the re-centring c + G m, b − A m of rescaling (`rescale_data`)
and the substitution (27)/(29) of an eliminated factor (`eliminate_factor`) are rounded to nearest,
so their result is the intended set only up to the roundoff of those operations on the data (a CZ's
equality constraints cannot carry a rounding margin). "Outer" is therefore rigorous in floating point
for `Girard`, `Combastel` and `IntervalHull` with respect to the data they receive, and holds up to
that roundoff for `EliminateConstraints` and the pipelines.

`CORA_GIRARD` and `CORA_COMBASTEL` are the pipelines of CORA's reduced constrained-zonotope observer,
the baselines of the stability paper's Table 1: ``rescale(·, 'iter')`` → ``reduceConstraints(·, 1)`` →
``reduce(·, 'girard' | 'combastel', 1)`` at degrees-of-freedom order 1.

References
----------
J. K. Scott, D. M. Raimondo, G. R. Marseglia, R. D. Braatz, "Constrained zonotopes: A new tool for
set-based estimation and fault detection", Automatica 69 (2016). A. Girard, "Reachability of uncertain
linear systems using zonotopes", HSCC 2005. C. Combastel, "A state bounding observer based on
zonotopes", ECC 2003.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Union

from ..base import ConvexSet
from ._base import ReductionMethod
from .constraints import EliminateConstraints
from .exact import DropDependentConstraints, DropZeros, MergeParallelGenerators
from .generators import Combastel, Girard, IntervalHull
from .propagation import FactorBounds, propagate
from .rescale import Rescale, rescale_data

__all__ = ["reduce", "ReductionMethod", "DropZeros", "DropDependentConstraints",
           "MergeParallelGenerators", "Rescale", "EliminateConstraints", "Girard", "Combastel",
           "IntervalHull", "CORA_GIRARD", "CORA_COMBASTEL", "as_methods", "apply_methods",
           "MethodOrMethods", "FactorBounds", "propagate", "rescale_data"]

#: One reduction method or a non-empty sequence of them, applied in order.
MethodOrMethods = Union[ReductionMethod, Sequence[ReductionMethod]]

#: CORA's reduced CZ observer with Girard's method (stability paper Table 1).
CORA_GIRARD = (Rescale("iter"), EliminateConstraints(1), Girard(1))

#: CORA's reduced CZ observer with Combastel's method (stability paper Table 1).
CORA_COMBASTEL = (Rescale("iter"), EliminateConstraints(1), Combastel(1))


def as_methods(method_or_methods: MethodOrMethods, name: str = "method") -> tuple[ReductionMethod, ...]:
    """Validate one method or a sequence of methods; return them as a tuple.

    Parameters
    ----------
    method_or_methods : ReductionMethod or sequence of ReductionMethod
        What the user passed.
    name : str
        The argument's name in the user's call, used in the error message (e.g. ``"reduce"``).

    Returns
    -------
    tuple of ReductionMethod
        The methods, in order.

    Raises
    ------
    TypeError
        If ``method_or_methods`` is neither a `ReductionMethod` nor a non-empty sequence of them (a
        string is refused).

    Examples
    --------
    >>> import setsmooth as ss
    >>> from setsmooth.sets.reduction import as_methods
    >>> as_methods(ss.Girard(1))
    (Girard(order=1),)
    >>> len(as_methods(ss.CORA_GIRARD))
    3
    """
    if isinstance(method_or_methods, ReductionMethod):
        return (method_or_methods,)
    if isinstance(method_or_methods, Sequence) and not isinstance(method_or_methods, str):
        methods = tuple(method_or_methods)
        bad = [m for m in methods if not isinstance(m, ReductionMethod)]
        if not methods or bad:
            raise TypeError(f"{name} must be a reduction method (e.g. ss.Girard(1)) or a non-empty "
                            f"sequence of them, got {method_or_methods!r}")
        return methods
    raise TypeError(f"{name} must be a reduction method (e.g. ss.Girard(1)) or a sequence of them, "
                    f"got {method_or_methods!r}")


def reduce(S: ConvexSet, method_or_methods: MethodOrMethods) -> ConvexSet:
    """Apply one reduction method, or a sequence of them in order, to a set.

    Parameters
    ----------
    S : ConvexSet
        A `Zonotope`, `ConstrainedZonotope`, `Box` or `EmptySet`.
    method_or_methods : ReductionMethod or sequence of ReductionMethod
        One method, or a non-empty sequence applied in order, e.g. ``ss.Girard(1)``,
        ``(ss.Rescale('iter'), ss.EliminateConstraints(1), ss.Girard(1))``, ``ss.CORA_GIRARD``. Every
        method is applied, a ``Rescale('iter')`` right before an `EliminateConstraints` too (see
        `apply_methods`).

    Returns
    -------
    ConvexSet
        The same set (exact methods) or a superset (outer ones); `EmptySet` when a method proves the
        set empty.

    Raises
    ------
    TypeError
        If ``S`` is not a ConvexSet or a method is not a `ReductionMethod`.
    NotImplementedError
        If a method has no implementation for the type of set it receives.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[0.5])
    >>> R = ss.reduce(Z, ss.CORA_GIRARD)
    >>> R.support([1.0, 1.0]) >= Z.support([1.0, 1.0]) - 1e-9
    True
    """
    methods = as_methods(method_or_methods, "method_or_methods")
    if not isinstance(S, ConvexSet):
        raise TypeError(f"S must be a ConvexSet, got {type(S).__name__}")
    return apply_methods(S, methods)


def apply_methods(S: ConvexSet, methods: tuple[ReductionMethod, ...]) -> ConvexSet:
    """`reduce` with trusted arguments (validated by the caller, e.g. once before a filter's loop).

    Every method is applied, in order. (A ``Rescale('iter')`` before `EliminateConstraints` is not
    redundant: on the rescaled data the factors' propagated ranges lie inside their bounds, so the
    elimination is exact where it would otherwise have to stop at ``max_constraints``.)

    Parameters
    ----------
    S : ConvexSet
        A `Zonotope`, `ConstrainedZonotope`, `Box` or `EmptySet`.
    methods : tuple of ReductionMethod
        As returned by `as_methods`.

    Returns
    -------
    ConvexSet
        As `reduce`.

    Raises
    ------
    NotImplementedError
        If a method has no implementation for the type of set it receives.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> from setsmooth.sets.reduction import apply_methods
    >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[0.5])
    >>> apply_methods(Z, ss.CORA_COMBASTEL).nc <= 1
    True
    """
    for method in methods:
        S = method.apply(S)
    return S
