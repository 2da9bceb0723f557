"""Interval hulls of constrained zonotopes that share one factor set, from one batch of solves.

The smoothed ranges of a data set (`setsmooth.optimal_smoother`, method 'trajectory') are
projections of one trajectory CZ: they share its factor set, and their hulls are LPs over one kept
program. `shared_interval_hulls` solves them direction by direction across the sets
(`setsmooth.solvers.shared_supports`), which starts every LP from the optimum of the same direction
one step earlier (docs/numerical_core.md: 24–27 → 8.4 pivots per LP for a 3-state smoother at
T = 600). The hulls are kept on the sets, as each set's own `interval_hull` keeps its answer, so a
set asked again later returns the same box.
"""

from __future__ import annotations

import numpy as np

from ..solvers.shared_supports import shared_supports
from .base import ConvexSet
from .constrained_zonotope import ConstrainedZonotope

__all__ = ["shared_interval_hulls"]


def shared_interval_hulls(sets: list[ConvexSet], certified: bool | None, *, progress: bool = False,
                          workers: int = 1) -> list[ConvexSet] | None:
    """``[S.interval_hull(certified=certified) for S in sets]`` for CZs over one factor set, or None
    when the sets are not such CZs (or their factor set is empty: each set's own hull decides).

    Parameters
    ----------
    sets : list of ConvexSet
    certified : bool or None
        As in `ConvexSet.interval_hull`.
    progress : bool
        A tqdm bar on standard error, one tick per LP (2n per set).
    workers : int
        Threads sharing the 2n chains of LPs (the hulls are the same for every count).
    """
    if len(sets) < 2 or any(type(S) is not ConstrainedZonotope for S in sets):
        return None
    if any(S._reference is not None or S.nc == 0 or S.dim != sets[0].dim for S in sets):
        return None  # views of other sets and closed forms answer on their own
    factors = sets[0].factors
    if any(S.factors is not factors for S in sets):
        return None
    key = ("auto", certified)
    if all(key in S.__dict__.get("_interval_hulls", {}) for S in sets):
        return [S.__dict__["_interval_hulls"][key] for S in sets]
    n = sets[0].dim
    eye = np.eye(n)
    from tqdm.auto import tqdm

    with tqdm(total=2 * n * len(sets), desc="interval hulls", unit="LP", disable=not progress,
              leave=False) as bar:
        supports = shared_supports([S._program for S in sets], np.vstack([eye, -eye]), certified,
                                   bar.update, workers)
    if supports is None or any(np.isneginf(v).any() or (u is not None and np.isneginf(u).any())
                               for v, u in supports):
        return None
    hulls = []
    for S, (values, bounds) in zip(sets, supports):
        # As a set's own path keeps them (`ConstrainedZonotope._interval_hulls_at_once`); the
        # solver's values of a certified=True call are not kept as the plain hull: its unsettled
        # attempts were taken as they are, which a plain call does not do.
        found = S._hulls_of_supports(values, bounds)
        if certified is True:
            del found[False]
        kept = S.__dict__.setdefault("_interval_hulls", {})
        for flag, hull in found.items():
            kept.setdefault(("auto", flag), hull)  # a hull asked before stays
        hulls.append(kept[key])
    return hulls
