"""The LSUO filter: uniform posteriors on orthotopic (box) supports (Pavelková & Jirsa 2018).

    data update:  𝕏_t       = □(𝕏_{t|t−1} ∩ {x : C x ∈ y_t − 𝕍})        the tightest box
    time update:  𝕏_{t+1|t} = □(A 𝕏_t + B u_t + 𝕎)

where □ is the interval hull: for box ∩ strip (a CZ with n + m generators and m constraints) the exact
hull of its enumerated vertices widened by their rounding slack (`sets.cz_vertices`, no LP; the certified
LP hull of `IntervalHull` if the enumeration were too large), for the zonotope of the time update the
library's `IntervalHull` reduction (closed form, rounded up). Every box contains the exact
set-membership posterior. The estimate is the box's centre (its centroid and Method 1 alike).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...sets.algebra import generalized_intersection, linear_map, minkowski_sum, translate
from ...sets.box import Box
from ...sets.constrained_zonotope import ConstrainedZonotope
from ...sets.empty import EmptySet
from ...sets.cz_vertices import cz_vertices, vertex_bounds
from ...sets.reduction import IntervalHull
from ..consistency import check_on_inconsistent, report_inconsistency
from ._strips import box_form, intersection_vertices
from .cz import empty_support
from .estimates import posterior_std
from .model import LSUModel
from .result import LSUResult

__all__ = ["lsuo_filter"]


def lsuo_filter(model: LSUModel, ys: Any, us: Any, *, std: bool = True,
                on_inconsistent: str = "warn") -> LSUResult:
    """Run LSUO (the orthotopic LSU filter) on one data sequence.

    Parameters
    ----------
    model : LSUModel
    ys : array_like, shape (t̄, m)
    us : array_like, shape (t̄, ℓ_u)
    std : bool
        Also return the posterior standard deviations (w/√12 per component).
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when a support is empty. Every support contains the exact set-membership
        posterior, so an empty one proves the data inconsistent with the model (a non-empty one does
        not prove them consistent; `setsmooth.filters.consistency`): 'warn' issues a
        `ModelInvalidationWarning` naming the first such index i (``ys[i]``), the measurement and its
        distance from the output set predicted from the support before it; 'raise' raises
        `ModelInvalidatedError`.

    Returns
    -------
    LSUResult
        Boxes ``supports[i]`` = 𝕏_{i+1} and ``estimates['center']``; `EmptySet` and NaN from the first
        empty support on.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> model = ss.LSUModel(A=[[0.9]], B=[[1.0]], C=[[1.0]], omega=[0.1], v=[0.2],
    ...                     x1_lo=[-1.0], x1_hi=[1.0])
    >>> us = np.zeros((10, 1))
    >>> xs, ys = model.simulate(us, np.random.default_rng(0))
    >>> result = ss.lsuo_filter(model, ys, us)
    >>> bool(np.all(np.abs(result.estimates["center"] - xs) <= 0.2 + 1e-12))
    True
    """
    if not isinstance(model, LSUModel):
        raise TypeError(f"model must be an LSUModel, got {type(model).__name__}")
    ys, us = model.check_data(ys, us)
    check_on_inconsistent(on_inconsistent)
    hull = IntervalHull()
    # 𝕎 in the zonotope form the sum takes it in, built once (a Box operand is converted at every step).
    W = model.W.to_zonotope()
    supports = []
    box = model.prior
    strips = model.strip_sets(ys)   # the CZ forms of model.strip(y), built at once
    for t, strip in enumerate(strips):
        if t > 0:
            box = hull.apply(minkowski_sum(translate(linear_map(model.A, supports[-1]), model.B @ us[t - 1]), W))
        post = _data_update(box, model.C, strip, hull)
        if isinstance(post, EmptySet) or post.is_empty():
            supports += [EmptySet(model.n) for _ in range(len(ys) - t)]
            break
        supports.append(post)
    if on_inconsistent != "ignore":
        report_inconsistency(empty_support(model, ys, us, supports, "LSUO"), on_inconsistent)
    return _box_result("LSUO", supports, model.n, std)


def tight_box(Q, hull: IntervalHull):
    """The tightest box around the small CZ Q: from its vertices, widened by their rounding slack
    (`sets.cz_vertices.vertex_bounds`; no LP), or by the certified LP hull when the enumeration is too
    large. `EmptySet` when Q is empty."""
    V = cz_vertices(Q) if isinstance(Q, ConstrainedZonotope) else None
    if V is None:
        return hull.apply(Q)
    if V.shape[0] == 0:
        return EmptySet(Q.dim)
    lo, hi = vertex_bounds(V, np.eye(Q.dim))
    return Box._trusted(lo, hi)


def _data_update(box: Box, C: np.ndarray, strip, hull: IntervalHull):
    """``tight_box(generalized_intersection(box, C, strip), hull)``, bit for bit, from the vertices
    of the intersection built without its rounding charges (`_strips`), which they do not read."""
    form = box_form(box)
    V = None if form is None else intersection_vertices(*form, C, strip)
    if V is None:
        return tight_box(generalized_intersection(box, C, strip), hull)
    if V.shape[0] == 0:
        return EmptySet(box.dim)
    lo, hi = vertex_bounds(V, np.eye(box.dim))
    return Box._trusted(lo, hi)


def _box_result(name: str, supports: list, n: int, std: bool) -> LSUResult:
    centers = np.array([np.full(n, np.nan) if isinstance(S, EmptySet) else S.midpoint() for S in supports])
    spread = np.array([posterior_std(S) for S in supports]) if std else None
    return LSUResult(name, supports, {"center": centers}, spread)
