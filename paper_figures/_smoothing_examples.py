"""What the smoothing paper's figure scripts share: its settings, conventions and statistics.

The example systems themselves live in `setsmooth.papers.smoothing_examples` (one definition for figures,
tests, benchmarks and docs); this module names them as the figure scripts use them and adds the paper's
run sizes, the report's conventions (`REPORT_PREAMBLE`) and the statistics Figs. 3 and 6 share. All noises
are uniform on their ranges (paper footnote 3); x_0 is drawn uniformly from ⟦x_0⟧.
"""

from __future__ import annotations

import numpy as np

import setsmooth as ss
from setsmooth.papers.smoothing_examples import (SMOOTHING_31_X0, SMOOTHING_33_V, SMOOTHING_33_W,
                                                 SMOOTHING_33_X0, eta_33, eta_33_inverse,
                                                 measurement_interval_34, smoothing_example_31,
                                                 smoothing_example_31_x0, smoothing_example_33)

import _verdicts
from _outputs import row

PAPER = "smoothing"
PAPER_TITLE = f"Smoothing paper — {ss.references.cite('smoothing')}"  # authors, title, venue
T = 50                              # k ∈ [0, T] in Figs. 3–6
PAPER_RUNS = 5000                   # Monte Carlo size of Figs. 3, 5, 6
PAPER_RUNS_PER_PAIR = 100           # Fig. 4
PAPER_BEST_QR = (0.076, 0.036)      # Fig. 4
HULL_TOL = 1e-6                     # slack for comparisons of certified interval hulls

# -- linear example (31) ----------------------------------------------------------------------------
X0_LINEAR = SMOOTHING_31_X0
linear_system = smoothing_example_31
linear_x0 = smoothing_example_31_x0


def rts_prior() -> tuple[np.ndarray, np.ndarray]:
    """Mean and covariance of x_0 uniform on ⟦x_0⟧, given to the RTS smoother."""
    lo, hi = (np.asarray(v) for v in X0_LINEAR)
    return (lo + hi) / 2, np.diag((hi - lo) ** 2 / 12)


def linear_ranges(system: ss.LinearSystem, X0: ss.ConvexSet, ys: np.ndarray):
    """Posterior and smoothed ranges of example (31): Algorithm 1's filter and backward recursion (24),
    computed exactly with polygons (`classical_filter(form='polygon')`, then
    `optimal_smoother(method='recursion')` on them): each a `Polygon` containing the exact range and
    larger only by rounding, so its interval hull is certified without a solver. The same sets as the
    constrained-zonotope paths (hulls agree to ~1e-9, the solvers' accuracy), ~10× faster."""
    filtered = ss.classical_filter(system, X0, ys, form="polygon")
    return filtered, ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=filtered)


def hull_bounds(sets: list[ss.ConvexSet]) -> tuple[np.ndarray, np.ndarray]:
    """Certified interval hulls of ``sets`` as (lo, hi) arrays of shape (len(sets), n)."""
    hulls = [S.interval_hull(certified=True) for S in sets]
    return np.array([h.lo for h in hulls]), np.array([h.hi for h in hulls])


def inside(x: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Per k: whether the true state x_k lies in the box [lo_k, hi_k] (up to HULL_TOL)."""
    x = x.reshape(lo.shape)
    return np.all((lo - HULL_TOL <= x) & (x <= hi + HULL_TOL), axis=-1)



def shrinkage_rows(x: np.ndarray, f_lo: np.ndarray, f_hi: np.ndarray, s_lo: np.ndarray,
                   s_hi: np.ndarray, figure: str, what: str) -> tuple[list[dict], dict]:
    """Report rows and JSON statistics comparing smoothed with filtered ranges (Figs. 3b and 6).

    Bounds have shape (runs, T+1, n) (n = 1 may be omitted); diameters are ∞-norm widths. The
    statistics hold the mean diameters per k, the containment counts and the per-run ⊆ count.
    """
    if f_lo.ndim == 2:
        x, f_lo, f_hi, s_lo, s_hi = (a[..., None] for a in (x, f_lo, f_hi, s_lo, s_hi))
    filtered_diam = (f_hi - f_lo).max(axis=2)
    smoothed_diam = (s_hi - s_lo).max(axis=2)
    mean_f, mean_s = filtered_diam.mean(axis=0), smoothed_diam.mean(axis=0)
    ratio = mean_s / mean_f
    per_run_ok = smoothed_diam <= filtered_diam + HULL_TOL
    outside_f = int((~inside(x, f_lo, f_hi)).sum())
    outside_s = int((~inside(x, s_lo, s_hi)).sum())
    strictly_smaller = bool(np.all(mean_s[:-1] < mean_f[:-1]))
    rows = [
        row("mean smoothed diameter < mean filtered diameter at every k < T (equal at k = T)",
            f"yes ({figure})", f"{'yes' if strictly_smaller else 'no'} (ratio smoothed/filtered: "
                               f"min {ratio.min():.3f}, max over k<T {ratio[:-1].max():.3f})"),
        row(f"smoothed {what} <= filtered {what} in every run and k", "yes (theory: ⊆)",
            f"{int(per_run_ok.sum())}/{per_run_ok.size}"),
        row("average diameter over k ∈ [0, 50], filtered / smoothed", "not stated (plot only)",
            f"{mean_f.mean():.3f} / {mean_s.mean():.3f} (ratio {mean_s.mean() / mean_f.mean():.3f})"),
        row("true state outside the range (filtered, smoothed), of runs×(T+1)", "0 (guaranteed)",
            f"{outside_f}, {outside_s} of {per_run_ok.size}"),
    ]
    runs = filtered_diam.shape[0]
    gap = filtered_diam - smoothed_diam
    gap_se = gap.std(axis=0, ddof=1) / np.sqrt(runs) if runs > 1 else np.full(gap.shape[1], np.nan)
    error = f"{runs} runs; s.e. of the mean diameter gap up to {np.nanmax(gap_se[:-1]):.2g}" if runs > 1 \
        else "one run"
    checks = [
        _verdicts.claim("smoothed ranges smaller than filtered ranges at every k < T", strictly_smaller,
                        f"mean diameter ratio smoothed/filtered {ratio.min():.3f}–{ratio[:-1].max():.3f} "
                        f"for k < T; smoothed ⊆ filtered in {int(per_run_ok.sum())}/{per_run_ok.size}", error),
        _verdicts.claim("true state inside the filtered and smoothed ranges", outside_f == outside_s == 0,
                        f"{outside_f} and {outside_s} outside of {per_run_ok.size}", "none (a guarantee)"),
    ]
    stats = {"checks": checks, "mean_diameter_filtered": mean_f, "mean_diameter_smoothed": mean_s,
             "outside_filtered": outside_f, "outside_smoothed": outside_s,
             "smoothed_le_filtered": [int(per_run_ok.sum()), int(per_run_ok.size)]}
    return rows, stats

# -- nonlinear example (33)–(34) --------------------------------------------------------------------
X0_NONLINEAR = SMOOTHING_33_X0
W_NONLINEAR = SMOOTHING_33_W
V_NONLINEAR = SMOOTHING_33_V
eta = eta_33
eta_inverse = eta_33_inverse
measurement_interval = measurement_interval_34
nonlinear_system = smoothing_example_33


def describe_box(lo, hi) -> str:
    """'[-5, 5]²' for a cube, '[-5, 5] × [0, 1]' otherwise."""
    lo, hi = np.atleast_1d(lo), np.atleast_1d(hi)
    sides = [f"[{a:g}, {b:g}]" for a, b in zip(lo, hi)]
    if len(set(sides)) == 1 and len(sides) > 1:
        return sides[0] + {2: "²", 3: "³"}.get(len(sides), f"^{len(sides)}")
    return " × ".join(sides)


#: The conventions shared by the smoothing paper's figures, printed above their rows in REPORT.md.
REPORT_PREAMBLE = """\
Reproduction of the numerical section (IV-C) of the smoothing paper. Each section lists the published
value or qualitative claim beside ours; the plotted numbers are in `<name>.json`.

Conventions shared by these figures:
- Noises are uniform on their ranges (paper footnote 3). The paper does not state the initial range
  ⟦x_0⟧; we use {x0_linear} for the linear example (31) and {x0_nonlinear} for the nonlinear
  example (33)–(34) (`setsmooth.papers.smoothing_examples`), and draw x_0 uniformly from it.
- Posterior and smoothed ranges of (31) are those of Algorithm 1 (the optimal SMF and eq. (24)),
  computed exactly with polygons in closed form (`classical_filter(form="polygon")`, then
  `optimal_smoother(method="recursion")` on its posteriors: each polygon contains the exact range and
  exceeds it only by rounding). Diameters are ∞-norm diameters of certified interval hulls.
- MSE_k = mean over runs of ‖x̂_k − x_k‖₂²; Fig. 4 averages it over k ∈ [0, 50] too.
- Runs are seeded with `numpy.random.SeedSequence(seed).spawn(runs)`; identical for any worker count.
""".format(x0_linear=describe_box(*X0_LINEAR), x0_nonlinear=describe_box(*X0_NONLINEAR))
