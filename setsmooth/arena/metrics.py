"""What the arena measures of one estimator on one run: soundness and tightness, from interval hulls.

Soundness has two tests. The truth: every true state x_k must lie in the estimator's own hull at k
(up to `TRUTH_ATOL` at the state's scale). The exact range: where an exact estimator of the same kind
is the reference, the estimator's hull must contain the reference's hull, coordinate by coordinate,
up to `CONTAINMENT_RTOL` of the reference's width plus `CONTAINMENT_ATOL` at the bound's scale. The
second test catches an estimator that cuts off a sliver of the range the truth happened not to visit
(one that shrinks the exact sets by 1 % loses the truth in a few steps out of a hundred, but fails
containment at every step).

Tightness: the mean radius (half-width of the hull, averaged over steps and coordinates) and the
hull-volume ratio to the reference, the geometric mean over steps of ∏_i width_i / ∏_i width_ref,i
(1 for the reference itself, ≥ 1 for a sound estimator). On 2-D problems also the Hausdorff gap, the
distance of the sets themselves to the exact ones (`hausdorff_gap`), which sees what a hull hides: a
set whose hull is the exact hull's can still be larger than the exact set.
"""

from __future__ import annotations

import numpy as np

from ..analysis.hausdorff import hausdorff_distance

__all__ = ["TRUTH_ATOL", "CONTAINMENT_RTOL", "CONTAINMENT_ATOL", "truth_outside", "containment_gap",
           "contains_reference", "mean_radius", "volume_ratio", "hausdorff_gap"]

#: A true state counts as inside a hull when it is at most this far outside, times max(1, |x_k,i|):
#: certified hulls are outer already, so this only absorbs the rounding of the simulated states.
TRUTH_ATOL = 1e-9
#: Hull containment holds up to this fraction of the reference hull's width ...
CONTAINMENT_RTOL = 1e-6
#: ... plus this, times max(1, |bound|): two solvers' certified bounds of one set differ by rounding.
CONTAINMENT_ATOL = 1e-9


def truth_outside(lo: np.ndarray, hi: np.ndarray, xs: np.ndarray) -> int:
    """Number of steps k whose true state x_k lies outside the hull [lo_k, hi_k] (an empty set counts)."""
    slack = TRUTH_ATOL * np.maximum(1.0, np.abs(xs))
    inside = (xs >= lo - slack) & (xs <= hi + slack)    # False where the hull is NaN (empty)
    return int(np.count_nonzero(~inside.all(axis=1)))


def _shortfall(lo, hi, ref_lo, ref_hi) -> tuple[np.ndarray, np.ndarray]:
    """How far the hull falls short of the reference hull on each side, and the allowed slack."""
    short = np.maximum(lo - ref_lo, ref_hi - hi)
    short = np.where(np.isnan(lo) | np.isnan(hi), np.inf, short)   # empty where the reference is not
    width = ref_hi - ref_lo
    scale = np.maximum(1.0, np.maximum(np.abs(ref_lo), np.abs(ref_hi)))
    slack = CONTAINMENT_RTOL * width + CONTAINMENT_ATOL * scale
    known = ~(np.isnan(ref_lo) | np.isnan(ref_hi))
    return np.where(known, short, -np.inf), np.where(known, slack, np.inf)


def containment_gap(lo, hi, ref_lo, ref_hi) -> float:
    """Largest shortfall of the hull against the reference hull, as a fraction of the reference's width.

    ≤ 0 when every hull contains the reference's; +inf when a hull is empty where the reference's is not.
    """
    short, _ = _shortfall(lo, hi, ref_lo, ref_hi)
    width = np.where(ref_hi - ref_lo > 0, ref_hi - ref_lo, np.inf)
    with np.errstate(invalid="ignore"):
        relative = np.where(np.isinf(short), short, short / width)
    return float(np.max(relative)) if relative.size else 0.0


def contains_reference(lo, hi, ref_lo, ref_hi) -> bool:
    """Whether every hull contains the reference hull at its step, up to the stated tolerances."""
    short, slack = _shortfall(lo, hi, ref_lo, ref_hi)
    return bool(np.all(short <= slack))


def mean_radius(lo, hi) -> float:
    """Half-width of the hulls, averaged over steps and coordinates (empty steps left out)."""
    radius = (hi - lo) / 2.0
    return float(np.nanmean(radius)) if not np.isnan(radius).all() else np.nan


def volume_ratio(lo, hi, ref_lo, ref_hi) -> float:
    """Geometric mean over steps of the hull volume (product of widths) over the reference's.

    Steps where either hull is empty or the reference is flat are left out; NaN when none is left.
    """
    width, ref_width = hi - lo, ref_hi - ref_lo
    usable = np.all(np.isfinite(ref_width) & (ref_width > 0) & ~np.isnan(width), axis=1)
    if not usable.any():
        return np.nan
    with np.errstate(divide="ignore"):
        logs = np.sum(np.log(width[usable]) - np.log(ref_width[usable]), axis=1)
    return float(np.exp(np.mean(logs)))


def hausdorff_gap(S, exact) -> float:
    """d_H(S, exact) in the 2-norm (stability paper (10)) of a 2-D set and the exact one at one step.

    Exact for polygons up to the solver's accuracy, not certified: `analysis.hausdorff_distance`
    measures each vertex's distance to the other polygon in closed form, and the vertices are the
    support points `vertices_2d` finds (a curved set's polygon is refined to the vertex tolerance).
    ``inf`` when exactly one of the sets is empty.
    """
    return hausdorff_distance(S, exact, 2)
