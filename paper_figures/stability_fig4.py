"""Stability paper Fig. 4: the OIT-CZ SMF (Algorithm 3) on random observable and detectable systems.

Left: observable (A, C), n = 10, p = m ∈ {5, …, 10}, δ̄ = n − rank(C) + 3. Right: detectable, n = 10,
n_o = p = m ∈ {7, 8, 9}, δ̄ = 3, ε = 10⁻³. W = [−1, 1]^p, V = [−1, 1]^m, ⟦x_0⟧ = [−10, 10]ⁿ, the filter's
initial condition [−10, 10]ⁿ ⊕ {c} with c uniform in [−1, 1]ⁿ (the paper's text; ``offset="authors' code"``
or ``--offset "authors' code"`` draws c in [−10, 10]ⁿ as the authors' code does), k = 0..100. Top: ∞-norm
diameter of the certified interval hull of Z_k (2 × its largest half-width); bottom: the bound
max_i max(|x_i − lo_i|, |x_i − hi_i|) on the ∞-norm estimation gap, computed on the hull. Shading: min..max over all runs and all p; line: mean; dash-dotted: one run,
with stars where Line 5 reset the estimate. Line 5 can only fire for k < δ̄, so every run also
replays its first δ̄ steps with the other offset (same c up to the factor 10) to count the resets that
offset would have caused: with the paper's offset they are rare, which is why the paper's stars (drawn
from the authors' code) need not appear. Systems from `setsmooth.analysis.random_observable_system`
/ `random_detectable_system` (seeded; MATLAB's drss cannot be replayed, so the comparison is
statistical).
"""

from __future__ import annotations

import functools
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import setsmooth as ss
from setsmooth import analysis, montecarlo

import _blas
import _stability_examples as ex
import _verdicts as v
from _outputs import Stopwatch, cli, finish, row

NAME = "stability_fig4"
PAPER = ex.PAPER
DEFAULT_RUNS = 2           # per setting (paper: 1000)
PAPER_RUNS = 1000
N, T = 10, 100
OBSERVABLE_P = (5, 6, 7, 8, 9, 10)
DETECTABLE_NO = (7, 8, 9)
EPSILON = 1e-3
HULL_TOL = 1e-6
#: Half-width of the uniform offset c of the filter's initial condition [−10, 10]ⁿ ⊕ {c}.
OFFSETS = {"paper": 1.0, "authors' code": 10.0}
OFFSET_TEXT = {"paper": "c ~ U[−1, 1]^n (the paper's text)",
               "authors' code": "c ~ U[−10, 10]^n (the authors' code)"}


def trial(rng: np.random.Generator, kind: str, p: int, n: int = N, T: int = T, offset: str = "paper") -> dict:
    """One run: draw the system, simulate, filter; the hull diameters and gap bounds, k = 0..T;
    ``resets_by_offset``: the Line-5 resets under each offset of OFFSETS (the same c up to its scale);
    ``seconds`` timed with BLAS limited to one thread, ``blas_threads`` the count read back."""
    with _blas.limited(1):
        result = _run(rng, kind, p, n, T, offset)
        result["blas_threads"] = _blas.thread_counts(_blas.in_force())
    return result


def _run(rng, kind, p, n, T, offset) -> dict:
    if kind == "observable":
        drawn = analysis.random_observable_system(rng, n, p, p)
        delta_bar = n - int(np.linalg.matrix_rank(drawn.C)) + 3
    else:
        drawn = analysis.random_detectable_system(rng, n, p, p, p)
        delta_bar = 3
    system = drawn.linear_system()
    true_x0 = ss.Box(-10 * np.ones(n), 10 * np.ones(n))
    xs, ys = ss.simulate(system, true_x0, T, rng)
    c = rng.uniform(-1.0, 1.0, n)    # U[−s, s]ⁿ is s·U[−1, 1]ⁿ: one draw serves every offset

    def filtered(name, data, hulls):
        X0 = ss.Box(OFFSETS[name] * c - 10.0, OFFSETS[name] * c + 10.0)
        return ss.oit_cz_filter(system, X0, data, delta_bar=delta_bar, epsilon=EPSILON,
                                decomposition=drawn.decomposition, hulls=hulls)

    res = filtered(offset, ys, True)
    # Line 5 acts only for k < δ̄: the first δ̄ measurements decide the other offsets' resets.
    resets = {name: list((res if name == offset else filtered(name, ys[:delta_bar], False)).resets)
              for name in OFFSETS}
    lo, hi = res.lo, res.hi   # the certified hulls of hulls=True, timed apart
    inside = np.all((lo - HULL_TOL <= xs) & (xs <= hi + HULL_TOL), axis=1)
    return {"diameter": (hi - lo).max(axis=1), "gap": np.maximum(np.abs(xs - lo), np.abs(xs - hi)).max(axis=1),
            "resets": list(res.resets), "resets_by_offset": resets, "inside": inside, "delta_bar": delta_bar,
            "seconds": float(res.step_seconds.sum() + res.hull_seconds.sum()),
            "max_state": float(np.abs(xs).max())}


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, *, n: int = N, T: int = T, observable_p=OBSERVABLE_P,
         detectable_no=DETECTABLE_NO, offset: str = "paper") -> dict:
    """The figure; ``offset`` picks c's range (OFFSETS); ``n``, ``T``, ``observable_p``, ``detectable_no``
    shrink it for tests."""
    if offset not in OFFSETS:
        raise ValueError(f"offset must be one of {', '.join(map(repr, OFFSETS))}, got {offset!r}")
    clock = Stopwatch()
    settings = [("observable", p) for p in observable_p] + [("detectable", n_o) for n_o in detectable_no]
    own = executor is None and runs * len(settings) > 1
    pool = ProcessPoolExecutor(workers or 2) if own else executor
    try:
        results = {s: montecarlo.run(functools.partial(trial, kind=s[0], p=s[1], n=n, T=T, offset=offset), runs,
                                     seed * 100 + i, executor=pool, progress=progress, workers=workers)
                   for i, s in enumerate(settings)}
    finally:
        if own:
            pool.shutdown()
    panels = {kind: _panel([r for (k, _), rs in results.items() if k == kind for r in rs])
              for kind in ("observable", "detectable")}
    highlight = {kind: results[(kind, observable_p[0] if kind == "observable" else detectable_no[0])][0]
                 for kind in panels}
    fig = _plot(panels, highlight, runs, T, offset)
    rows = _rows(panels, results, T, offset)
    data = {
        "figure": "Stability paper Fig. 4",
        "rows": rows,
        "checks": _checks(panels, results, highlight, runs, T, offset),
        "settings": {"runs": runs, "seed": seed, "n": n, "T": T, "observable_p_m": observable_p,
                     "detectable_n_o_p_m": detectable_no, "epsilon": EPSILON,
                     "delta_bar": "observable n − rank(C) + 3 = 13 − p; detectable 3",
                     "initial_condition": f"[−10, 10]^n ⊕ {{c}}, {OFFSET_TEXT[offset]}",
                     "offset": offset,
                     "BLAS threads in force while timing (read back)":
                         sorted({t for rs in results.values() for r in rs for t in r["blas_threads"]}),
                     "diameter": "∞-norm diameter of the certified interval hull (2 × largest half-width)",
                     "gap": "max_i max(|x_i − lo_i|, |x_i − hi_i|) on the interval hull"},
        "published": {"runs": PAPER_RUNS, "claim": "OIT-CZ SMF stable and uniformly bounded (Theorem 4)"},
        "k": np.arange(T + 1),
        **{f"{kind}_{key}": value for kind, panel in panels.items() for key, value in panel.items()},
        "highlight": {kind: {"diameter": h["diameter"], "gap": h["gap"], "resets": h["resets"]}
                      for kind, h in highlight.items()},
    }
    return finish(out, NAME, PAPER, fig, data, clock)


def _checks(panels: dict, results: dict, highlight: dict, runs: int, T: int, offset: str) -> list[dict]:
    """Theorem 4's claims as the figure shows them, and the stars of the highlighted run."""
    error = f"{runs} runs per setting: extremes over runs, no standard error"
    checks = []
    for kind in ("observable", "detectable"):
        rs = [r for (k, _), group in results.items() if k == kind for r in group]
        later = slice(min(20, T), T + 1)
        largest = float(panels[kind]["diameter_max"][later].max())
        start = (lambda r: r["delta_bar"]) if kind == "observable" else (lambda r: 2 * r["delta_bar"] + 10)
        outside = sum(int((~r["inside"][start(r):]).sum()) for r in rs)
        checks += [v.claim(f"{kind}: uniformly bounded estimates", np.isfinite(largest),
                           f"largest ∞-diameter for k ∈ [{later.start}, {T}]: {largest:.3g}", error),
                   v.claim(f"{kind}: true state inside the estimate", outside == 0,
                           f"{outside} steps outside the hull", error)]
    stars = {kind: bool(h["resets"]) for kind, h in highlight.items()}
    reset_runs = {name: sum(bool(r["resets_by_offset"][name]) for rs in results.values() for r in rs)
                  for name in OFFSETS}
    total = sum(len(rs) for rs in results.values())
    checks.append(v.claim(
        "Line-5 reset stars in the highlighted runs", any(stars.values()),
        f"offset {offset}: highlighted runs reset: "
        + ", ".join(f"{k} {'yes' if s else 'no'}" for k, s in stars.items()) + "; runs with a reset: " + ", ".join(f"{name} offset {n} of {total}" for name, n in reset_runs.items()),
        error))
    return checks


def _panel(rs: list[dict]) -> dict:
    diam = np.array([r["diameter"] for r in rs])
    gap = np.array([r["gap"] for r in rs])
    return {"diameter_min": diam.min(axis=0), "diameter_max": diam.max(axis=0), "diameter_mean": diam.mean(axis=0),
            "gap_min": gap.min(axis=0), "gap_max": gap.max(axis=0), "gap_mean": gap.mean(axis=0)}


def _rows(panels: dict, results: dict, T: int, offset: str) -> list[dict]:
    rows = [row("offset c of the initial condition [−10, 10]ⁿ ⊕ {c} that produced this figure",
                "text: c ~ U[−1, 1]ⁿ; the authors' code: c ~ U[−10, 10]ⁿ", OFFSET_TEXT[offset])]
    for kind in ("observable", "detectable"):
        rs = [r for (k, _), group in results.items() if k == kind for r in group]
        d = panels[kind]
        later = slice(min(20, T), T + 1)
        outside = sum(int((~r["inside"][r["delta_bar"]:]).sum()) for r in rs) if kind == "observable" else \
            sum(int((~r["inside"][2 * r["delta_bar"] + 10:]).sum()) for r in rs)
        when = "k ≥ δ̄" if kind == "observable" else "k ≥ 2δ̄ + 10"
        rows += [
            row(f"{kind}: uniformly bounded — largest ∞-diameter over k ∈ [{later.start}, {T}], all runs",
                "bounded (plot only)", f"{d['diameter_max'][later].max():.3g}"),
            row(f"{kind}: mean ∞-diameter at k = {later.start} / {T}", "plot only",
                f"{d['diameter_mean'][later.start]:.3g} / {d['diameter_mean'][T]:.3g}"),
            row(f"{kind}: mean / largest gap bound for k ∈ [{later.start}, {T}]", "bounded (plot only)",
                f"{d['gap_mean'][later].mean():.3g} / {d['gap_max'][later].max():.3g}"),
            row(f"{kind}: true state outside the hull for {when} (steps, all runs)", "0 (Theorem 4)", outside),
            row(f"{kind}: runs with a Line-5 reset / resets per run, per offset (this figure: {offset})",
                "stars in the highlighted run (drawn with the authors' code's offset)",
                "; ".join(f"{name}: {sum(bool(r['resets_by_offset'][name]) for r in rs)} of {len(rs)} / "
                          f"{np.mean([len(r['resets_by_offset'][name]) for r in rs]):.2f}" for name in OFFSETS)),
            row(f"{kind}: filter + hulls per run (s)", "not stated", f"{np.median([r['seconds'] for r in rs]):.2f}"),
        ]
    return rows


def _plot(panels: dict, highlight: dict, runs: int, T: int, offset: str):
    k = np.arange(T + 1)
    fig, axes = plt.subplots(2, 2, figsize=(12, 7.5), sharex=True)
    titles = {"observable": f"observable, p = m ∈ {{5..10}}, {runs} runs each",
              "detectable": f"detectable, n_o = p = m ∈ {{7, 8, 9}}, {runs} runs each"}
    for col, kind in enumerate(("observable", "detectable")):
        d, h = panels[kind], highlight[kind]
        for row_i, key, label in ((0, "diameter", r"$d_\infty(\overline{\mathrm{IH}}(\mathcal{Z}_k))$"),
                                  (1, "gap", r"gap bound on $\overline{\mathrm{IH}}(\mathcal{Z}_k)$")):
            ax = axes[row_i, col]
            ax.fill_between(k, d[f"{key}_min"], d[f"{key}_max"], color="tab:blue", alpha=0.25, label="min–max")
            ax.plot(k, d[f"{key}_mean"], color="tab:blue", label="mean")
            ax.plot(k, h[key], color="gold", linestyle="-.",
                    label="one run" + ("" if h["resets"] else " (no Line-5 reset)"))
            if h["resets"]:
                ax.plot(h["resets"], np.asarray(h[key])[h["resets"]], "*", color="purple", markersize=10,
                        label="Line 5 reset")
            ax.set_yscale("log")
            ax.set(ylabel=label)
            ax.grid(alpha=0.3)
            if row_i == 0:
                ax.set_title(titles[kind])
            else:
                ax.set_xlabel("$k$")
            ax.legend(fontsize=8)
    fig.suptitle(f"initial condition [−10, 10]ⁿ ⊕ {{c}}, {OFFSET_TEXT[offset]}", fontsize=10)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0],
        offset={"choices": tuple(OFFSETS), "default": "paper", "help": "range of the offset c (default: paper)"})
