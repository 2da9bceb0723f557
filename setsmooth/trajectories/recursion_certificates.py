"""Certified hulls of the recursion's sets, certified against the model data.

Algorithm 1's recursion (stability (20)–(21), smoothing (24)) forms products of the model matrices in
floating point: the k-th set's generators are A_{k−1}⋯A_0 G rounded. The set algebra charges that
rounding (`setsmooth.sets.rounding`), but a rigorous charge of a product's rounding, carried through
the following maps, grows like ‖|A|‖^k (the wrapping effect of interval arithmetic): on a stable 6-state
system the pad of the filter's 20th set was 7e-3, where the rounding itself stays near 1e-13. A
certificate of the stored CZ would then be sound and useless.

The same exact sets are projections of the trajectory set (smoothing paper Theorem 1 and Corollary 1;
stability (7)), whose rows are the model data themselves, each rounded once and charged once
(`setsmooth.trajectories`), with no product of A's anywhere. So the recursion's estimators attach to
each of their sets a `DataReference`, and the set's support values (plain and certified), hulls,
emptiness and membership are those of the matching projection, posed on the data: one program decides
every query of the set, so its plain hull lies inside its certified one. The recursion's own CZ (its
rows repeated once per step that carries them, its generators products of A's) stays the set's
representation for further set algebra, but is not the program its questions are asked of: on a
thin smoothed set (reliability case 069, every state pinned by the data) its plain hull was 1e-4 of
the data scale wide where the set is a point, outside its own certified hull, and its hulls cost 2.8x
the projection's (docs/numerical_core.md). The trajectory CZ of one data set is built once, on the
first query, and shared by the sets: a bound valid for the stored CZ can sit inside the exact set's,
a bound against the data cannot.
"""

from __future__ import annotations

import threading

import numpy as np

from ..sets.constrained_zonotope import ConstrainedZonotope
from .posterior_views import posterior_views, smoothed_ranges_from_trajectories
from .sparse_cz import trajectory_set

__all__ = ["DataReference", "certified_against_data"]


class _SharedReferences:
    """The projections of one data set's trajectory CZ, built on first use (thread-safe)."""

    def __init__(self, system, X0, ys: np.ndarray, kind: str):
        self.system, self.X0, self.ys, self.kind = system, X0, ys, kind
        self._sets: list | None = None
        self._lock = threading.Lock()

    def set_at(self, k: int) -> ConstrainedZonotope:
        with self._lock:
            if self._sets is None:
                if self.kind == "filtered":
                    self._sets = posterior_views(self.system, self.X0, self.ys)
                else:
                    self._sets = smoothed_ranges_from_trajectories(
                        trajectory_set(self.system, self.X0, self.ys), self.system.n)
            return self._sets[k]

    def __getstate__(self) -> dict:  # the lock does not pickle; the built sets are rebuilt
        return {"system": self.system, "X0": self.X0, "ys": self.ys, "kind": self.kind}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._sets = None
        self._lock = threading.Lock()


class DataReference:
    """⟦x_k | y_{0:j}⟧ as a projection of the data's trajectory CZ: the set a recursion CZ is
    certified against (``get()``)."""

    def __init__(self, shared: _SharedReferences, k: int):
        self._shared, self.k = shared, int(k)

    def get(self) -> ConstrainedZonotope:
        return self._shared.set_at(self.k)


def certified_against_data(sets: list, system, X0, ys: np.ndarray, kind: str) -> list:
    """``sets`` with every constrained zonotope among them replaced by the same CZ certified against
    the data (a `DataReference` to its trajectory projection); other sets are returned as they are.

    Parameters
    ----------
    sets : list of ConvexSet
        The exact estimates ⟦x_k | y_{0:k}⟧ (``kind='filtered'``) or ⟦x_k | y_{0:T}⟧ (``'smoothed'``)
        for k = 0..T, computed from ``system``, ``X0`` and ``ys`` (not outer bounds: the reference
        is the exact set).
    kind : {'filtered', 'smoothed'}
    """
    if kind not in ("filtered", "smoothed"):
        raise ValueError(f"kind must be 'filtered' or 'smoothed', got {kind!r}")
    if any(S._flat_cz is None for S in (X0, system.W, system.V)):
        return list(sets)  # no trajectory CZ to certify against
    shared = _SharedReferences(system, X0, ys, kind)
    out = []
    for k, S in enumerate(sets):
        if type(S) is ConstrainedZonotope:
            S = S._with_reference(DataReference(shared, k))
        out.append(S)
    return out
