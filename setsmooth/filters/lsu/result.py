"""What an LSU filter returns: the supports of the approximate posteriors and their estimates."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...results import SetEstimates, Tubes
from ...sets.base import ConvexSet

__all__ = ["LSUResult"]


@dataclass(frozen=True, eq=False)
class LSUResult(Tubes):
    """Supports 𝕏_t of the uniform approximate posteriors f(x_t | d(t)), t = 1..t̄, and estimates.

    It behaves as the list of supports (``len``, indexing, iteration) and follows the `Estimates`
    protocol like `classical_filter`'s result: ``lo``/``hi`` are the supports' interval hulls (computed
    on first use), ``contains_trajectory`` tests exact membership in the supports, ``first_empty`` is
    the first empty support (the data contradict the model), ``plot_tubes`` labels the tube with the
    filter's name.

    Attributes
    ----------
    filter : str
        'LSU-CZ', 'LSUO' or 'LSUP'.
    supports : SetEstimates of ConvexSet
        ``supports[i]`` is 𝕏_{i+1}, an outer approximation of the exact set-membership posterior
        (``outer=True``).
    estimates : dict of str to ndarray, shape (t̄, n)
        Point estimates by name: 'interval_hull' (Method 1), 'closest' (Method 2), 'centroid' for
        LSU-CZ; 'center' (the centre of the box or parallelotope, also its centroid) for LSUO/LSUP.
    std : ndarray, shape (t̄, n), or None
        Standard deviations of x_t under the uniform density on 𝕏_t (`posterior_std`).
    settings : dict
        What the filter was run with (complexity maxima, reduction), for the record.
    """

    filter: str
    supports: list[ConvexSet]
    estimates: dict[str, np.ndarray]
    std: np.ndarray | None = None
    settings: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.supports, SetEstimates):
            object.__setattr__(self, "supports", SetEstimates(self.supports, kind=self.filter, outer=True))

    @property
    def kind(self) -> str:
        return self.filter

    @property
    def lo(self) -> np.ndarray:
        """Lower edges of the supports' interval hulls, shape (t̄, n); NaN rows where empty."""
        return self.supports.lo

    @property
    def hi(self) -> np.ndarray:
        """Upper edges of the supports' interval hulls, shape (t̄, n); NaN rows where empty."""
        return self.supports.hi

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray:
        """Whether each x_{i+1} = ``xs[i]`` lies in 𝕏_{i+1} (exact membership)."""
        return self.supports.contains_trajectory(xs, tol)

    def __len__(self) -> int:
        return len(self.supports)

    def __getitem__(self, i):
        return self.supports[i]

    def __iter__(self):
        return iter(self.supports)
