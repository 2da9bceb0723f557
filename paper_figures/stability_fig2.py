"""Stability paper Fig. 2: four designers on the observable example (25), the OIT and its bound (16).

Panels: the exact posterior sets of the truth (from ⟦x_0⟧ = [1, 3]²) and of Alice [0, 4]², Bob [−4, 4]²,
David [−2, 2]² (Algorithm 1) and Carol [−1, 1]² (Algorithm 2) at k ∈ {0, …, 6, 10}, with the OIT
(δ = 2) from k = 2; then the 2-norm diameters with the bound (16) minimized over δ, and the
estimation gaps — exact Hausdorff distance and the authors' vertex surrogate — for k ∈ [0, 50].
The trajectory is the authors' (seed 24629, replayed bit for bit); ``--runs N`` adds N − 1 fresh
trajectories, summarized in the report.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import setsmooth as ss
from setsmooth import analysis, montecarlo

import _stability_examples as ex
import _verdicts as v
from _outputs import Stopwatch, cli, finish, row

NAME = "stability_fig2"
PAPER = ex.PAPER
DEFAULT_RUNS = 1
PANEL_K = (0, 1, 2, 3, 4, 5, 6, 10)
OIT_DELTA = 2
COLORS = {"true": "black", "Alice": "tab:orange", "Bob": "tab:olive", "Carol": "tab:purple",
          "David": "tab:cyan", "OIT": "tab:red"}


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, horizon: int = ex.T) -> dict:
    """``horizon`` < 50 truncates the authors' trajectory (the tests' small version)."""
    clock = Stopwatch()
    horizon = ex.check_horizon(horizon, PANEL_K)
    example = ex.EXAMPLE_25
    system = example.system()
    xs, ys = (a[:horizon + 1] for a in ex.authors_data(example))
    T = horizon
    sets = ex.designer_estimates(example, ys)
    sets["OIT"] = [None] * OIT_DELTA + [ss.observation_information_tower(system, ys, k, OIT_DELTA)
                                         for k in range(OIT_DELTA, T + 1)]
    polys = {name: ex.polygons(S) if name != "OIT" else
             [np.zeros((0, 2))] * OIT_DELTA + ex.polygons(S[OIT_DELTA:]) for name, S in sets.items()}
    true_polys = polys["true"]
    curves = {name: ex.curves(true_polys, polys[name]) for name in list(ex.DESIGNERS) + ["OIT"]}
    true_diam = np.array([analysis.diameter(P, 2) for P in true_polys])
    bound = analysis.minimize_oit_diameter_bound(system.A_at(0), system.E_at(0), system.C_at(0), system.W, system.V)
    oit_bound = analysis.oit_diameter_bound(system.A_at(0), system.E_at(0), system.C_at(0), system.W, system.V, OIT_DELTA)

    extra = montecarlo.run(partial(ex.fresh_run, "25", horizon), runs - 1, seed, executor=executor, progress=progress,
                           workers=workers) if runs > 1 else []
    rows, checks = _rows(example, xs, sets, polys, curves, true_diam, bound, oit_bound)
    extra_rows, extra_stats = ex.fresh_run_rows(extra, "Fig. 2")
    rows += extra_rows
    fig = _plot(polys, curves, true_diam, bound, xs)
    k = np.arange(T + 1)
    data = {
        "figure": "Stability paper Fig. 2",
        "rows": rows,
        "checks": checks,
        "settings": {"runs": runs, "seed": seed, "example": "(25)", "authors_seed": example.seed,
                     "T": T, "true_x0": ex.TRUE_X0, "designers": ex.DESIGNERS, "panel_k": PANEL_K,
                     "oit_delta": OIT_DELTA, "carol": "Algorithm 2, k_* = 1, θ̄ = ∞ (P = I)",
                     "diameter": "2-norm, largest vertex distance; 0 for an empty estimate",
                     "gap": "exact 2-norm Hausdorff distance to the true posterior; vertex surrogate beside it",
                     "gap_zero_tol": ex.GAP_TOL},
        "published": {"runs": 1, "david_empty_from": 2, "gaps_zero_from": 6},
        "k": k, "x": xs, "y": ys, "true_diameter": true_diam,
        "bound_16": {"delta": bound.delta, "value": bound.value, "values_from_mu_minus_1": bound.values,
                     "oit_delta_2": oit_bound},
        **{name: {key: c[key] for key in ("empty", "diameter", "gap", "gap_surrogate")}
           for name, c in curves.items()},
        "panels": {str(kk): {name: polys[name][kk] for name in polys} for kk in PANEL_K},
        "fresh_runs": extra_stats,
        "notes": ["Carol's switching time and θ̄ = ∞ follow the paper's Algorithm 2; the authors' script "
                  "switches at μ_o − 1 = 1 with a box of half-width 1000, the same set here.",
                  "The OIT row compares ∩_{i=k−2}^{k} O_{k,i} (an exact CZ) with the true posterior."],
    }
    return finish(out, NAME, PAPER, fig, data, clock)


def _contains(outer: np.ndarray, inner: np.ndarray) -> bool:
    """Polygon containment: every vertex of ``inner`` within 1e-7 of ``outer``."""
    return all(analysis.point_polygon_distance(v, outer) <= 1e-7 for v in inner)


def _rows(example, xs, sets, polys, curves, true_diam, bound, oit_bound) -> tuple[list[dict], list[dict]]:
    A, C = example.A, example.C
    verdicts = {name: analysis.check_stability_criterion(A, C, ex.box(ex.DESIGNERS[name]), ex.box(ex.TRUE_X0))
                for name in ex.DESIGNERS}
    david_empty = ex.first_empty(curves["David"]["empty"])
    vanish = {name: ex.gaps_vanish_from(curves[name]["gap"]) for name in ("Alice", "Bob", "Carol")}
    vanish_s = {name: ex.gaps_vanish_from(curves[name]["gap_surrogate"]) for name in ("Alice", "Bob", "Carol")}
    p1 = {name: polys[name][1] for name in polys}
    chain = (_contains(p1["Carol"], p1["Bob"]) and _contains(p1["Bob"], p1["Alice"])
             and _contains(p1["Alice"], p1["true"]))
    strict = all(analysis.hausdorff_distance(a, b) > ex.GAP_TOL
                 for a, b in ((p1["Carol"], p1["Bob"]), (p1["Bob"], p1["Alice"]), (p1["Alice"], p1["true"])))
    gaps6 = {name: curves[name]["gap"][6] for name in ("Alice", "Bob", "Carol", "OIT")}
    oit_gap = curves["OIT"]["gap"]
    T = len(xs) - 1
    oit_equal = [k for k in range(OIT_DELTA, T + 1) if oit_gap[k] <= ex.GAP_TOL]
    inside = {n: ex.inside_from(sets[n], xs) for n in ("true", "Alice", "Bob", "Carol")}
    later = slice(bound.delta, None)
    max_diam = {name: float(np.max(curves[name]["diameter"][later])) for name in ("Alice", "Bob", "Carol")}
    ratio = [curves[n]["gap_surrogate"][k] / curves[n]["gap"][k] for n in ("Alice", "Bob", "Carol")
             for k in range(T + 1) if curves[n]["gap"][k] > ex.GAP_TOL]
    one_run = "none: the authors' own trajectory (one run, replayed bit for bit)"
    david_inside = _contains(p1["true"], p1["David"])
    checks = [
        v.claim("David's estimate empty at k = 2", david_empty == 2, f"ours: first empty at k = {david_empty}",
                one_run),
        v.claim("gaps of Alice, Bob, Carol are 0 from k = 6 on",
                all(k is not None and k <= 6 for k in vanish.values()),
                "exact gap ≤ 1e-6 from k = " + ", ".join(f"{n} {k}" for n, k in vanish.items()), one_run),
        v.claim("k = 1: Carol ⊃ Bob ⊃ Alice ⊃ true posterior ⊃ David", chain and david_inside,
                f"nested chain {'yes' if chain else 'no'}, David inside {'yes' if david_inside else 'no'}", one_run),
        v.claim("diameters for k ≥ δ below the bound (16)",
                max(max_diam.values()) <= bound.value and np.max(true_diam[later]) <= bound.value,
                f"largest {max(max(max_diam.values()), np.max(true_diam[later])):.3f} vs bound {bound.value:.3f}",
                one_run),
        v.claim("Theorem 2: Alice, Bob stable, David not",
                verdicts["Alice"].holds and verdicts["Bob"].holds and not verdicts["David"].holds,
                ", ".join(f"{n} {'yes' if r.holds else 'no'}" for n, r in verdicts.items()), "none (a criterion)"),
    ]
    return [
        row("David's estimate becomes empty at k", "2", str(david_empty)),
        row("Alice, Bob, Carol: estimation gap 0 from k (exact Hausdorff ≤ 1e-6)", "0 for k ≥ 6",
            ", ".join(f"{n} {vanish[n]}" for n in vanish)),
        row("... with the authors' vertex surrogate", "(their curve)", ", ".join(f"{n} {vanish_s[n]}" for n in vanish_s)),
        row("k = 1: Carol ⊃ Bob ⊃ Alice ⊃ true posterior", "yes (Fig. 2b)",
            f"{'yes' if chain else 'no'}{' (strict)' if strict else ''}"),
        row("k = 1: David's estimate inside the true posterior", "yes (Fig. 2b)",
            "yes" if _contains(p1["true"], p1["David"]) else "no"),
        row("k = 6: gap to the true posterior of Alice, Bob, Carol and of the OIT (δ = 2)",
            "all 0: the posteriors equal the true set and the OIT", ", ".join(f"{n} {v:.2e}" for n, v in gaps6.items())),
        row("OIT (δ = 2) equals the true posterior (gap ≤ 1e-6) at k", "k = 6 (the time shown)",
            f"{len(oit_equal)} of {T + 1 - OIT_DELTA} times k ∈ [2, {T}], first {oit_equal[:6]}; "
            f"largest gap {np.nanmax(oit_gap[OIT_DELTA:]):.3f}" if oit_equal else "never"),
        row("bound (16) minimized over δ ≥ μ − 1 (d_w = d_v = 2)", "horizontal line (value not printed)",
            f"{bound.value:.4f} at δ = {bound.delta}; (16) at δ = 2: {oit_bound:.4f}"),
        row(f"largest 2-norm diameter for k ≥ {bound.delta}: true / Alice / Bob / Carol", "below the line",
            f"{np.max(true_diam[later]):.3f} / " + " / ".join(f"{max_diam[n]:.3f}" for n in max_diam)),
        row("largest OIT (δ = 2) diameter, k ≥ 2", "≤ (16)",
            f"{np.max(curves['OIT']['diameter'][OIT_DELTA:]):.3f} ≤ {oit_bound:.3f}"),
        row("Theorem 2 holds (Alice, Bob, Carol's box, David)", "Alice, Bob yes; David no (condition (i))",
            ", ".join(f"{n} {'yes' if v.holds else 'no'}" for n, v in verdicts.items())),
        row("true state inside the estimate for every k from (true posterior, Alice, Bob, Carol)",
            "0 for the true posterior, Alice, Bob (Proposition 4); Carol: from k_* = 1 (observable)",
            ", ".join(f"{n} {v}" for n, v in inside.items())),
        row("vertex surrogate / exact gap where the gap > 0", "(surrogate is an upper bound)",
            f"min {min(ratio):.3f}, max {max(ratio):.3f}" if ratio else "no positive gap"),
    ], checks


def _plot(polys, curves, true_diam, bound, xs):
    fig = plt.figure(figsize=(15, 10.5))
    grid = fig.add_gridspec(3, 4, height_ratios=[1, 1, 1.1])
    for idx, kk in enumerate(PANEL_K):
        ax = fig.add_subplot(grid[idx // 4, idx % 4])
        if kk == 0:
            for name, lo_hi in ex.DESIGNERS.items():
                ex.draw_polygon(ax, ss.Box(*lo_hi).vertices_2d(), COLORS[name], linestyle=":", linewidth=1)
            ex.draw_polygon(ax, ss.Box(*ex.TRUE_X0).vertices_2d(), "black", linestyle=":", linewidth=1)
        for name in ("OIT", "Carol", "Bob", "Alice", "David", "true"):
            style = {"linewidth": 3.0, "alpha": 0.35} if name == "OIT" else {"linewidth": 1.4}
            ex.draw_polygon(ax, polys[name][kk], COLORS[name], label=name if idx == 0 else None, **style)
        ax.plot(*xs[kk], "k*", markersize=7)
        empty = [n for n in ex.DESIGNERS if len(polys[n][kk]) == 0]
        ax.set_title(f"k = {kk}" + (f" ({', '.join(empty)}: ∅)" if empty else ""), fontsize=10)
        ax.grid(alpha=0.3)
        ax.set_aspect("equal", adjustable="datalim")
    fig.axes[0].plot([], [], color=COLORS["OIT"], linewidth=3.0, alpha=0.35, label=f"OIT (δ = {OIT_DELTA})")
    fig.axes[0].plot([], [], "k*", label="true state")
    fig.axes[0].legend(fontsize=7, loc="best")
    k = np.arange(len(xs))
    ax_d = fig.add_subplot(grid[2, :2])
    ax_d.plot(k, true_diam, color="black", marker="s", markersize=3, label="true")
    for name in ex.DESIGNERS:
        ax_d.plot(k, curves[name]["diameter"], color=COLORS[name], marker="o", markersize=3, label=name)
    ax_d.axhline(bound.value, color="tab:red", linestyle="--", label=f"bound (16), δ = {bound.delta}")
    ax_d.set(xlabel="k", ylabel="2-norm diameter", title="diameters (0 when empty)")
    ax_d.legend(fontsize=8, ncol=3)
    ax_d.grid(alpha=0.3)
    ax_g = fig.add_subplot(grid[2, 2:])
    for name in ("Alice", "Bob", "Carol"):
        gap = np.where(curves[name]["gap"] > ex.GAP_TOL, curves[name]["gap"], np.nan)
        sur = np.where(curves[name]["gap_surrogate"] > ex.GAP_TOL, curves[name]["gap_surrogate"], np.nan)
        ax_g.semilogy(k, gap, color=COLORS[name], marker="o", markersize=3, label=f"{name} (exact)")
        ax_g.semilogy(k, sur, color=COLORS[name], linestyle=":", label=f"{name} (vertex surrogate)")
    ax_g.set(xlabel="k", ylabel="estimation gap (2-norm)", title=f"estimation gaps (≤ {ex.GAP_TOL:g} counted as 0, not drawn)", xlim=(-0.5, 12))
    ax_g.legend(fontsize=7, ncol=2)
    ax_g.grid(alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
