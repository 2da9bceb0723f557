"""The set-algebra hooks, declared once for every `ConvexSet` (which inherits them).

`setsmooth.sets.algebra` calls these methods directly on its operands. Each returns NotImplemented
when the representation has no closed form for the operand, and the algebra then widens (a CZ closed
form, else a lazy set). A representation overrides the ones it knows a closed form for.

The naming convention makes the hooks checkable: every hook is named ``_closed_<operation>``, and a
class whose private name starts with ``closed`` but is not declared here, or is a near-miss of a
declared hook (a typo), is refused when it is defined — a misspelt hook fails loudly instead of
silently falling back to a slow lazy set.
"""

from __future__ import annotations

import difflib
from typing import Any

import numpy as np

#: Similarity (difflib ratio) from which an undeclared name counts as a misspelt hook.
_NEAR_MISS = 0.9


class AlgebraHooks:
    """The closed forms a set representation may know; all default to NotImplemented."""

    __slots__ = ()

    def _closed_linear_map(self, M) -> Any:
        """Hook: {M s : s ∈ self} for a trusted (k, dim) matrix M (dense or sparse), or NotImplemented."""
        return NotImplemented

    def _closed_translate(self, v: np.ndarray) -> Any:
        """Hook: self + v for a trusted vector v, or NotImplemented."""
        return NotImplemented

    def _closed_sum(self, other) -> Any:
        """Hook: self ⊕ other (tried in both orders: the sum commutes), or NotImplemented."""
        return NotImplemented

    def _closed_intersection(self, other) -> Any:
        """Hook: self ∩ other (tried in both orders), or NotImplemented."""
        return NotImplemented

    def _closed_generalized_intersection(self, R, Y) -> Any:
        """Hook: {s ∈ self : R s ∈ Y}, or NotImplemented (then Y's reflected hook is tried)."""
        return NotImplemented

    def _closed_reflected_generalized_intersection(self, S, R) -> Any:
        """Hook: {s ∈ S : R s ∈ self}, the closed form the operand Y = self knows, or NotImplemented."""
        return NotImplemented

    def _closed_product(self, other) -> Any:
        """Hook: self × other (in this order), or NotImplemented (then other's reflected hook is tried)."""
        return NotImplemented

    def _closed_reflected_product(self, S) -> Any:
        """Hook: S × self, the closed form the right operand knows, or NotImplemented."""
        return NotImplemented

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name in vars(cls):
            if name not in ALGEBRA_HOOKS and looks_like_a_hook(name):
                raise TypeError(f"{cls.__name__}.{name} looks like a set-algebra hook but is not one of "
                                f"the hooks declared on ConvexSet: {sorted(ALGEBRA_HOOKS)}")


#: The declared hook names.
ALGEBRA_HOOKS = frozenset(name for name in vars(AlgebraHooks) if name.startswith("_closed_"))


def looks_like_a_hook(name: str) -> bool:
    """Whether ``name`` is a ``closed…`` name or a near-miss of a declared hook (a typo).

    Examples
    --------
    >>> looks_like_a_hook("_closed_intersecton"), looks_like_a_hook("_minkowski_sum")
    (True, False)
    """
    if name.lstrip("_").startswith("closed"):
        return True
    return any(difflib.SequenceMatcher(None, name, hook).ratio() >= _NEAR_MISS for hook in ALGEBRA_HOOKS)
