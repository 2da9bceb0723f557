"""What an LSU filter returns: the supports of the approximate posteriors and their estimates."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...sets.base import ConvexSet

__all__ = ["LSUResult"]


@dataclass(frozen=True, eq=False)
class LSUResult:
    """Supports 𝕏_t of the uniform approximate posteriors f(x_t | d(t)), t = 1..t̄, and estimates.

    It behaves as the list of supports (``len``, indexing, iteration), like `classical_filter`'s result.

    Attributes
    ----------
    filter : str
        'LSU-CZ', 'LSUO' or 'LSUP'.
    supports : list of ConvexSet
        ``supports[i]`` is 𝕏_{i+1}, an outer approximation of the exact set-membership posterior.
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

    def __len__(self) -> int:
        return len(self.supports)

    def __getitem__(self, i):
        return self.supports[i]

    def __iter__(self):
        return iter(self.supports)
