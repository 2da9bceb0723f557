"""Stability paper Table 1: time per step of the OIT-CZ SMF and of CORA-style reduced CZ filters.

n = p = m ∈ {10, 20, 30}, random observable systems (`analysis.random_observable_system`), W = [−1, 1]^p,
V = [−1, 1]^m, ⟦x_0⟧ = ⟦x̂_0⟧ = [−10, 10]ⁿ, OIT-CZ with δ̄ = 3 (window prior ℝⁿ); the baselines are the
classical filter with CORA's pipelines ``ss.CORA_GIRARD`` / ``ss.CORA_COMBASTEL`` (rescale 'iter',
reduceConstraints to nc = 1, reduce at DOF order 1) after every update. All three run on the same
trajectories in one process. Times are CPU seconds of this process per step (the machine is shared):
"step only" is the filter's own work (the paper's timing, hull LPs outside), "step + hull" adds the
certified interval hull a user needs for a box. Radius: largest half-width of the certified interval
hull, averaged over k and runs (the paper's "∞-norm diameters" are these radii, see the notes).
Paper size: 100 runs × 101 steps (``--runs 100``); the default is 1 run × 11 steps.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy loads OpenBLAS (see the notes below)

import functools  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth import analysis, montecarlo  # noqa: E402

import _stability_examples as ex  # noqa: E402
from _outputs import Stopwatch, cli, finish, row  # noqa: E402

NAME = "stability_table1"
PAPER = ex.PAPER
DEFAULT_RUNS = 1
PAPER_RUNS = 100
DIMENSIONS = (10, 20, 30)
DELTA_BAR = 3
PAPER_STEPS, DEFAULT_STEPS = 100, 10       # T: k = 0..T
FILTERS = ("girard", "combastel", "oit")
PUBLISHED_TIME = {"girard": (0.5822, 3.8103, 11.9702), "combastel": (0.5809, 3.8014, 11.9546),
                  "oit": (0.0004, 0.0006, 0.0011)}
PUBLISHED_RADIUS = {"girard": (14.89, 29.31, 37.23), "combastel": (14.89, 29.14, 37.23),
                    "oit": (3.69, 4.76, 5.09)}


def measure(rng: np.random.Generator, n: int, T: int) -> dict:
    """One run at dimension n: per-step CPU seconds (step only, hull) and mean hull radius of each filter."""
    drawn = analysis.random_observable_system(rng, n, n, n)
    system = drawn.linear_system()
    X0 = ss.Box(-10.0 * np.ones(n), 10.0 * np.ones(n))
    xs, ys = ss.simulate(system, X0, T, rng)
    out = {}
    for name, reduce in (("girard", ss.CORA_GIRARD), ("combastel", ss.CORA_COMBASTEL)):
        t0 = time.process_time()
        posteriors = ss.classical_filter(system, X0, ys, reduce=reduce)
        t1 = time.process_time()
        hulls = [Z.interval_hull(certified=True) for Z in posteriors]
        t2 = time.process_time()
        lo, hi = np.array([h.lo for h in hulls]), np.array([h.hi for h in hulls])
        out[name] = _summary((t1 - t0) / (T + 1), (t2 - t1) / (T + 1), lo, hi, xs)
    res = ss.oit_cz_filter(system, X0, ys, delta_bar=DELTA_BAR, decomposition=drawn.decomposition, hulls=True)
    out["oit"] = _summary(res.step_seconds.mean(), res.hull_seconds.mean(), *res.hulls, xs)
    out["oit"]["step_steady"] = float(np.median(res.step_seconds[DELTA_BAR:]))
    return out


def _summary(step: float, hull: float, lo: np.ndarray, hi: np.ndarray, xs: np.ndarray) -> dict:
    inside = np.all((lo - 1e-6 <= xs) & (xs <= hi + 1e-6), axis=1)
    return {"step": float(step), "hull": float(hull), "radius": float(((hi - lo) / 2).max(axis=1).mean()),
            "outside": int((~inside).sum())}


def trial(rng: np.random.Generator, T: int, dimensions=DIMENSIONS) -> dict:
    return {n: measure(rng, n, T) for n in dimensions}


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, *, dimensions=DIMENSIONS, steps: int | None = None) -> dict:
    """The table; ``dimensions`` (a sub-tuple of DIMENSIONS) and ``steps`` shrink it for tests."""
    clock = Stopwatch()
    T = steps if steps is not None else (PAPER_STEPS if runs >= PAPER_RUNS else DEFAULT_STEPS)
    # Serial in one process: the three filters are timed side by side on the same trajectories.
    results = montecarlo.run(functools.partial(trial, T=T, dimensions=dimensions), runs, seed,
                             executor="serial", progress=progress)
    table = {f: {key: [float(np.mean([r[n][f][key] for r in results])) for n in dimensions]
                 for key in ("step", "hull", "radius", "outside")} for f in FILTERS}
    table["oit"]["step_steady"] = [float(np.median([r[n]["oit"]["step_steady"] for r in results]))
                                   for n in dimensions]
    rows = _rows(table, dimensions)
    fig = _plot(table, dimensions)
    data = {
        "figure": "Stability paper Table 1",
        "rows": rows,
        "settings": {"runs": runs, "seed": seed, "T": T, "n = p = m": dimensions, "delta_bar": DELTA_BAR,
                     "x0 and initial condition": "[−10, 10]^n",
                     "baselines": "classical_filter(reduce=ss.CORA_GIRARD | ss.CORA_COMBASTEL): rescale 'iter', "
                                  "reduceConstraints nc = 1, DOF order 1",
                     "time": "CPU seconds per step (time.process_time), one process, BLAS single-threaded",
                     "radius": "largest half-width of the certified interval hull, mean over k = 0..T and runs"},
        "published": {"runs": PAPER_RUNS, "steps": PAPER_STEPS + 1, "time": PUBLISHED_TIME,
                      "radius": PUBLISHED_RADIUS, "machine": "MATLAB 2019b, Intel Core i7 laptop"},
        "table": table,
        "notes": ["The paper's OIT-CZ time excludes the interval hull (2n LPs per step); so does 'step only'. "
                  "The OIT-CZ step itself is the window's right-hand side b (its G and A are built once).",
                  "The baselines' reduced sets have nc ≤ 1, so their hulls are cheap; the OIT-CZ window has "
                  "(δ̄+1)m constraints and n + δ̄p + (δ̄+1)m factors, and its 2n hull LPs are the cost.",
                  "With multithreaded OpenBLAS on this shared 2-core machine the baselines' dense solves "
                  "ran ~20× slower (n = 30); the scripts pin BLAS to one thread."],
    }
    return finish(out, NAME, PAPER, fig, data, clock)


def _rows(table: dict, dimensions) -> list[dict]:
    rows = []
    for i, n in enumerate(dimensions):
        p = DIMENSIONS.index(n)  # the published column
        g, c, o = (table[f] for f in FILTERS)
        rows += [
            row(f"n = {n}: step only, girard / combastel / OIT-CZ (s)",
                " / ".join(f"{PUBLISHED_TIME[f][p]:g}" for f in FILTERS),
                f"{g['step'][i]:.3g} / {c['step'][i]:.3g} / {o['step'][i]:.2g} (steady k ≥ δ̄: "
                f"{o['step_steady'][i]:.2g})"),
            row(f"n = {n}: speed-up of the OIT-CZ step over girard (step only)",
                f"{PUBLISHED_TIME['girard'][p] / PUBLISHED_TIME['oit'][p]:.0f}×",
                f"{g['step'][i] / o['step'][i]:.0f}× (steady: {g['step'][i] / o['step_steady'][i]:.0f}×)"),
            row(f"n = {n}: step + hull, girard / combastel / OIT-CZ (s)", "not reported",
                f"{g['step'][i] + g['hull'][i]:.3g} / {c['step'][i] + c['hull'][i]:.3g} / "
                f"{o['step'][i] + o['hull'][i]:.3g} (girard/OIT = "
                f"{(g['step'][i] + g['hull'][i]) / (o['step'][i] + o['hull'][i]):.2g}×)"),
            row(f"n = {n}: hull radius, girard / combastel / OIT-CZ",
                " / ".join(f"{PUBLISHED_RADIUS[f][p]:g}" for f in FILTERS),
                f"{g['radius'][i]:.3g} / {c['radius'][i]:.3g} / {o['radius'][i]:.3g} "
                f"(girard/OIT = {g['radius'][i] / o['radius'][i]:.2g}×; paper "
                f"{PUBLISHED_RADIUS['girard'][p] / PUBLISHED_RADIUS['oit'][p]:.2g}×)"),
            row(f"n = {n}: true state outside the hull (steps, girard / combastel / OIT-CZ)", "0",
                " / ".join(f"{table[f]['outside'][i]:g}" for f in FILTERS)),
        ]
    return rows


def _plot(table: dict, dimensions):
    fig, (ax_t, ax_r) = plt.subplots(1, 2, figsize=(11, 4.2))
    x = np.arange(len(dimensions))
    cols = [DIMENSIONS.index(n) for n in dimensions]
    styles = {"girard": ("tab:red", "o"), "combastel": ("tab:orange", "s"), "oit": ("tab:blue", "*")}
    for f in FILTERS:
        color, marker = styles[f]
        ax_t.plot(x, table[f]["step"], marker=marker, color=color, label=f"{f}: step only")
        ax_t.plot(x, np.add(table[f]["step"], table[f]["hull"]), marker=marker, color=color, linestyle="--",
                  label=f"{f}: step + hull")
        ax_t.plot(x, np.asarray(PUBLISHED_TIME[f])[cols], marker=marker, color=color, linestyle=":", alpha=0.6,
                  label=f"{f}: paper")
        ax_r.plot(x, table[f]["radius"], marker=marker, color=color, label=f"{f}")
        ax_r.plot(x, np.asarray(PUBLISHED_RADIUS[f])[cols], marker=marker, color=color, linestyle=":", alpha=0.6,
                  label=f"{f}: paper")
    for ax in (ax_t, ax_r):
        ax.set_xticks(x, [f"n = {n}" for n in dimensions])
        ax.grid(alpha=0.3)
    ax_t.set(yscale="log", ylabel="seconds per step", title="time per step")
    ax_r.set(ylabel="mean interval-hull radius", title="accuracy (∞-radius)")
    ax_t.legend(fontsize=7, ncol=1)
    ax_r.legend(fontsize=7)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
