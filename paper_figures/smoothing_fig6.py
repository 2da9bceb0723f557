"""Smoothing paper Fig. 6: optimal SMF vs optimal SMS (Algorithm 2) on the nonlinear example (33)–(34).

    x_{k+1} = ∛x_k + x_k + w_k,  y_k = 2x_k + v_k,  ⟦w_k⟧ = [−1, 1],  ⟦v_k⟧ = [1, 3],  ⟦x_0⟧ = [−5, 5].

Posteriors [a_k, b_k] from `interval_filter` (the optimal SMF, Lemma 3), smoothed ranges from
`interval_smoother` (Proposition 2, Algorithm 2) with η⁻¹ in closed form (Cardano). Their lengths
(the ∞-norm diameters) are averaged over the Monte Carlo runs for k ∈ [0, 50].
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import setsmooth as ss
from setsmooth import montecarlo
from setsmooth.filters.interval import interval_filter
from setsmooth.smoothers.nonlinear import interval_smoother

import _smoothing_examples as ex
from _outputs import Stopwatch, cli, finish, row

NAME = "smoothing_fig6"
PAPER = ex.PAPER
DEFAULT_RUNS = ex.PAPER_RUNS


#: The system (33)–(34) and ⟦x_0⟧, built once: sets are immutable, and building them took a tenth of a run.
SYSTEM = ex.nonlinear_system()
X0 = ss.Box([ex.X0_NONLINEAR[0]], [ex.X0_NONLINEAR[1]])


def trial(rng: np.random.Generator) -> dict:
    """One run: true states, posterior and smoothed intervals for k = 0..T."""
    xs, ys = ss.simulate(SYSTEM, X0, ex.T, rng)
    filtered = interval_filter(ex.eta, ex.W_NONLINEAR, ex.X0_NONLINEAR, ys[:, 0], ex.measurement_interval)
    smoothed = interval_smoother(ex.eta, ex.W_NONLINEAR, filtered, eta_inverse=ex.eta_inverse)
    return {"x": xs[:, 0], "filtered_lo": filtered.lo, "filtered_hi": filtered.hi,
            "smoothed_lo": smoothed.lo, "smoothed_hi": smoothed.hi}


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None) -> dict:
    clock = Stopwatch()
    results = montecarlo.run(trial, runs, seed, executor=executor, progress=progress, workers=workers)

    def stack(key):
        return np.array([r[key] for r in results])

    x = stack("x")
    f_lo, f_hi, s_lo, s_hi = (stack(k) for k in ("filtered_lo", "filtered_hi", "smoothed_lo", "smoothed_hi"))
    empty = int(np.isnan(f_hi - f_lo).any(axis=1).sum() + np.isnan(s_hi - s_lo).any(axis=1).sum())
    k = np.arange(ex.T + 1)
    rows, stats = ex.shrinkage_rows(x, f_lo, f_hi, s_lo, s_hi, "Fig. 6", "interval length")
    rows.append(row("runs with an empty range", "0", f"{empty}"))
    data = {
        "figure": "Smoothing paper Fig. 6",
        "rows": rows,
        "settings": {"runs": runs, "seed": seed, "T": ex.T, "x0_set": ex.X0_NONLINEAR,
                     "w_set": ex.W_NONLINEAR, "v_set": ex.V_NONLINEAR,
                     "noise": "uniform on ⟦w⟧ = [-1, 1], ⟦v⟧ = [1, 3]",
                     "filter": "interval_filter (optimal SMF, Lemma 3)",
                     "smoother": "interval_smoother (Proposition 2 / Algorithm 2), closed-form eta inverse",
                     "diameter": "interval length"},
        "published": {"runs": ex.PAPER_RUNS, "claim": "smoothed ranges are smaller than posterior ranges"},
        "k": k, **stats
    }
    fig = _plot(k, stats["mean_diameter_filtered"], stats["mean_diameter_smoothed"], runs)
    return finish(out, NAME, PAPER, fig, data, clock)


def _plot(k, mean_f, mean_s, runs):
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    ax.plot(k, mean_f, color="tab:green", marker="o", markersize=5, mfc="none",
            label=r"$[\![x_k \mid y_{0:k}]\!]$ optimal SMF")
    ax.plot(k, mean_s, color="tab:red", marker="*", markersize=7,
            label=r"$[\![x_k \mid y_{0:T}]\!]$ optimal SMS (Algorithm 2)")
    ax.set(xlabel="$k$", ylabel="average diameter (interval length)",
           title=f"Nonlinear example (33)–(34): average diameters over {runs} runs", xlim=(-1, k[-1] + 1))
    ax.legend(loc="center right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
