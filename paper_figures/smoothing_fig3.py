"""Smoothing paper Fig. 3: optimal SMF vs optimal SMS on the linear example (31).

(a) interval hulls of the posterior ranges ⟦x_k | y_{0:k}⟧ (green) and the smoothed ranges
    ⟦x_k | y_{0:T}⟧ (red) for k ∈ [0, 10] in the (x1, x2) plane, with the true trajectory dashed (run 0);
(b) their ∞-norm diameters averaged over the Monte Carlo runs, k ∈ [0, 50].

Posteriors (the optimal SMF) and smoothed ranges are Algorithm 1's sets: its filter and backward
recursion (24) computed exactly with polygons in closed form (`classical_filter(form="polygon")`,
`optimal_smoother(method="recursion")`; every set of (31) is a planar polygon), each containing the
exact range and larger only by rounding. Diameters are those of certified interval hulls (no solver:
the polygons' support values are rounded upward).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import setsmooth as ss
from setsmooth import montecarlo

import _smoothing_examples as ex
from _outputs import DEFAULT_OUT, Stopwatch, cli, finish, row

NAME = "smoothing_fig3"
PAPER = ex.PAPER
DEFAULT_RUNS = 300
K_PLANE = 10          # Fig. 3(a) shows k ∈ [0, 10]
#: The per-run true states and smoothed hulls, kept for Fig. 5: its runs are the same seeded data sets
#: (same seed, same `montecarlo` streams) and its SMS estimate is the centre of the same certified hull,
#: so it reads them instead of smoothing every data set a second time (half of `--runs 5000`'s cost).
RUNS_FILE = f"{NAME}_runs.npz"


def trial(rng: np.random.Generator) -> dict:
    """One run: true states and the interval hulls of posterior and smoothed ranges, k = 0..T."""
    system, X0 = ex.linear_system(), ex.linear_x0()
    xs, ys = ss.simulate(system, X0, ex.T, rng)
    filtered, smoothed = ex.linear_ranges(system, X0, ys)
    filtered_lo, filtered_hi = ex.hull_bounds(filtered)
    smoothed_lo, smoothed_hi = ex.hull_bounds(smoothed)
    return {"x": xs, "filtered_lo": filtered_lo, "filtered_hi": filtered_hi,
            "smoothed_lo": smoothed_lo, "smoothed_hi": smoothed_hi}


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None) -> dict:
    clock = Stopwatch()
    results = montecarlo.run(trial, runs, seed, executor=executor, progress=progress, workers=workers)

    def stack(key):
        return np.array([r[key] for r in results])

    x = stack("x")
    f_lo, f_hi, s_lo, s_hi = (stack(k) for k in ("filtered_lo", "filtered_hi", "smoothed_lo", "smoothed_hi"))
    save_runs(Path(out) if out is not None else DEFAULT_OUT, runs, seed, x, s_lo, s_hi)
    k = np.arange(ex.T + 1)
    rows, stats = ex.shrinkage_rows(x, f_lo, f_hi, s_lo, s_hi, "Fig. 3b", "hull diameter")
    mean_f, mean_s = stats["mean_diameter_filtered"], stats["mean_diameter_smoothed"]
    rows.insert(3, row("steady part k ∈ [10, 40], filtered / smoothed", "not stated (plot only)",
                          f"{mean_f[10:41].mean():.3f} / {mean_s[10:41].mean():.3f}"))
    fig = _plot(k, x[0], f_lo[0], f_hi[0], s_lo[0], s_hi[0], mean_f, mean_s, runs)
    data = {
        "figure": "Smoothing paper Fig. 3",
        "rows": rows,
        "settings": {"runs": runs, "seed": seed, "T": ex.T, "x0_set": ex.X0_LINEAR,
                     "noise": "uniform on ⟦w⟧ = [-1, 1], ⟦v⟧ = [-1, 1]^2",
                     "filter": "classical_filter(form='polygon') (optimal SMF, exact polygons)",
                     "smoother": "optimal_smoother(method='recursion') on the polygon posteriors: the "
                                 "sets of Algorithm 1 / (24), exact polygons",
                     "diameter": "∞-norm diameter of the certified interval hull",
                     "fig3a_run": 0, "fig3a_k": [0, K_PLANE]},
        "published": {"runs": ex.PAPER_RUNS, "claim": "smoothed ranges are smaller than posterior ranges"},
        "k": k, **stats,
        "fig3a": {"x": x[0, :K_PLANE + 1], "filtered_lo": f_lo[0, :K_PLANE + 1],
                  "filtered_hi": f_hi[0, :K_PLANE + 1], "smoothed_lo": s_lo[0, :K_PLANE + 1],
                  "smoothed_hi": s_hi[0, :K_PLANE + 1]}
    }
    return finish(out, NAME, PAPER, fig, data, clock)


def save_runs(out: Path, runs: int, seed: int, x, smoothed_lo, smoothed_hi) -> None:
    """Write `RUNS_FILE`: the settings that identify the data sets, their true states and smoothed hulls."""
    out.mkdir(parents=True, exist_ok=True)
    np.savez(out / RUNS_FILE, runs=runs, seed=seed, T=ex.T, x0_set=np.asarray(ex.X0_LINEAR, dtype=float),
             x=x, smoothed_lo=smoothed_lo, smoothed_hi=smoothed_hi)


def load_runs(out: Path, runs: int, seed: int) -> dict | None:
    """The saved runs of `save_runs` when they were made with these settings, else None."""
    path = out / RUNS_FILE
    if not path.exists():
        return None
    with np.load(path) as saved:
        if (int(saved["runs"]) != runs or int(saved["seed"]) != seed or int(saved["T"]) != ex.T
                or not np.array_equal(saved["x0_set"], np.asarray(ex.X0_LINEAR, dtype=float))):
            return None
        return {key: saved[key] for key in ("x", "smoothed_lo", "smoothed_hi")}


def _plot(k, x, f_lo, f_hi, s_lo, s_hi, mean_f, mean_s, runs):
    from matplotlib.patches import Rectangle

    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1, 1.15]})
    for j in range(K_PLANE + 1):
        # Green under red and wider, so that a hull the smoother leaves unchanged still shows both.
        for lo, hi, color, width in ((f_lo[j], f_hi[j], "tab:green", 2.4), (s_lo[j], s_hi[j], "tab:red", 1.2)):
            ax_a.add_patch(Rectangle(lo, *(hi - lo), fill=False, edgecolor=color, linewidth=width))
    ax_a.plot(x[:K_PLANE + 1, 0], x[:K_PLANE + 1, 1], "k--", marker=".", markersize=7, linewidth=1.2,
              zorder=3)
    for j in range(K_PLANE + 1):
        ax_a.annotate(str(j), x[j], textcoords="offset points", xytext=(4, 4), fontsize=8, zorder=4)
    ax_a.plot([], [], color="tab:green", linewidth=2.4, label=r"hull of $[\![x_k \mid y_{0:k}]\!]$ (SMF)")
    ax_a.plot([], [], color="tab:red", label=r"hull of $[\![x_k \mid y_{0:T}]\!]$ (SMS)")
    ax_a.plot([], [], "k--", marker=".", label="true state $x_k$ (labels: $k$)")
    ax_a.autoscale_view()
    ax_a.set_aspect("equal", adjustable="datalim")
    ax_a.set(xlabel="$x_1$", ylabel="$x_2$", title=f"(a) interval hulls, $k \\in [0, {K_PLANE}]$ (run 0)")
    ax_a.legend(loc="best", fontsize=8)
    ax_a.grid(alpha=0.3)

    ax_b.plot(k, mean_f, color="tab:green", marker="o", markersize=5, mfc="none",
              label=r"$[\![x_k \mid y_{0:k}]\!]$ optimal SMF")
    ax_b.plot(k, mean_s, color="tab:red", marker="*", markersize=7, label=r"$[\![x_k \mid y_{0:T}]\!]$ optimal SMS")
    ax_b.set(xlabel="$k$", ylabel=r"average $\infty$-norm diameter",
             title=f"(b) average diameters over {runs} runs", xlim=(-1, k[-1] + 1))
    ax_b.legend()
    ax_b.grid(alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
