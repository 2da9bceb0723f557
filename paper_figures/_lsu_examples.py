"""What the LSU paper's table and figure scripts share: the Section 4 experiment, run once and cached.

Tables 1–2 and Figs. 1–3 are views of one Monte Carlo experiment (11 noise levels × 4 filters ×
runs), so `experiment` runs it once per (runs, seed, horizon, maxima) and keeps the per-run metrics
in ``<out>/lsu_experiment_<key>.npz``; the other scripts of the same ``setsmooth figures`` call read
it back instead of recomputing.
"""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path

import numpy as np

import setsmooth as ss
from setsmooth import montecarlo
from setsmooth.filters.lsu import DEFAULT_MAX_CONSTRAINTS, DEFAULT_MAX_GENERATORS

import _blas
import _verdicts
from _outputs import DEFAULT_OUT

PAPER = "lsu"
PAPER_TITLE = ("LSU paper — Kuklišová Pavelková, *Bayesian State Estimation Using Constrained "
               "Zonotopes*")

# -- Section 4.1, as printed ------------------------------------------------------------------------
A = np.array([[1.0, -0.5, 0.2], [0.5, 0.1, 0.0], [0.3, 0.0, -0.1]])
B = np.array([[0.1], [0.6], [0.3]])
C = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.5]])
OMEGA = 1e-4 * np.ones(3)
K_VALUES = (4.0, 3.5, 3.0, 2.5, 2.0, 1.5, 1.0, 0.75, 0.5, 0.25, 0.0)
T = 600                                   # t̄, the length of the data sequences
# -- our choices (the paper states none of them) ----------------------------------------------------
X1_LO, X1_HI = -np.ones(3), np.ones(3)   # the prior box (5)
STEADY_FROM = 10                         # "steady" metrics skip t = 1..10 (the prior's transient)
PAPER_RUNS = "not stated"

#: The estimators compared: LSUCZ-1/2 and the centroid share one LSU-CZ run; LSUO, LSUP their own.
ESTIMATORS = ("LSUCZ-1", "LSUCZ-2", "LSUCZ-c", "LSUO", "LSUP", "LSUP-kept")
PAPER_ESTIMATORS = ("LSUCZ-1", "LSUCZ-2", "LSUO", "LSUP")
#: Our estimator behind each published column: the kept-shape LSUP reproduces the paper's LSUP (see
#: REPORT_PREAMBLE), so it stands for it in every comparison; the minimal-volume LSUP is shown beside.
PAPER_COLUMNS = ("LSUCZ-1", "LSUCZ-2", "LSUO", "LSUP-kept")
LABELS = {"LSUCZ-1": "LSUCZ-1 (Method 1)", "LSUCZ-2": "LSUCZ-2 (Method 2)",
          "LSUCZ-c": "LSUCZ centroid", "LSUO": "LSUO", "LSUP": "LSUP (min. volume)",
          "LSUP-kept": "LSUP (kept shape)"}
METRICS = ("rmse", "mae", "rmse_steady", "mae_steady", "error_std", "posterior_std")
FILTERS = ("LSU-CZ", "LSUO", "LSUP", "LSUP-kept")

#: Table 1 (RMSE·10³) and Table 2 (MAE·10³) as printed; None where the paper prints "< 10⁻³".
PUBLISHED_RMSE = {
    4.0: (None, None, None, None), 3.5: (6.0, 6.4, 1.5, 1.6), 3.0: (6.0, 6.5, 1.4, 2.5),
    2.5: (6.1, 6.6, 1.6, 2.6), 2.0: (6.4, 7.9, 3.0, 2.9), 1.5: (7.8, 12.9, 8.4, 6.9),
    1.0: (13.5, 27.5, 26.1, 21.2), 0.75: (21.5, 50.7, 45.1, 36.7), 0.5: (27.4, 63.2, 79.1, 57.8),
    0.25: (34.9, 96.1, 139.8, 100.1), 0.0: (50.3, 141.7, 250.8, 181.5)}
PUBLISHED_MAE = {
    4.0: (None, None, None, None), 3.5: (0.5, 0.7, 0.1, 0.1), 3.0: (0.6, 1.0, 0.3, 0.4),
    2.5: (0.9, 1.8, 0.7, 0.7), 2.0: (1.9, 3.8, 2.0, 1.9), 1.5: (3.9, 8.8, 5.9, 4.8),
    1.0: (8.4, 20.4, 18.7, 15.0), 0.75: (13.4, 35.2, 32.2, 25.1), 0.5: (17.8, 47.8, 56.9, 39.0),
    0.25: (23.6, 72.2, 99.6, 65.9), 0.0: (28.7, 102.6, 178.0, 120.0)}


def model(K: float) -> ss.LSUModel:
    """The Section 4 model with v = 10^−K·1 and our prior box."""
    return ss.LSUModel(A, B, C, OMEGA, 10.0 ** -K * np.ones(2), X1_LO, X1_HI)


def metrics(estimate: np.ndarray, x: np.ndarray, std: np.ndarray) -> np.ndarray:
    """The METRICS of one estimate sequence (t̄, n) against the truth: over t and components,
    RMSE = √mean e², MAE = mean |e|, the same from t = STEADY_FROM + 1 on, the standard deviation of
    e, and the mean posterior standard deviation (`posterior_std` of the supports)."""
    e = estimate - x
    s = e[STEADY_FROM:]
    return np.array([np.sqrt(np.mean(e ** 2)), np.mean(np.abs(e)), np.sqrt(np.mean(s ** 2)),
                     np.mean(np.abs(s)), np.std(e), np.mean(std)])


def trial(rng: np.random.Generator, K_values=K_VALUES, horizon: int = T,
          max_generators: int = DEFAULT_MAX_GENERATORS,
          max_constraints: int = DEFAULT_MAX_CONSTRAINTS) -> dict:
    """One run at every K: the same inputs and the same standard uniform draws (common random
    numbers: v_t = 10^−K·v̄_t), so differences between noise levels are not sampling noise.

    Returns ``metrics`` (len(K), len(ESTIMATORS), len(METRICS)), ``seconds`` (len(K), len(FILTERS)),
    ``outside`` (len(K), len(FILTERS)): steps at which the true state is outside the support's interval
    hull (must be 0), and ``blas_threads``: the most BLAS threads any library reported while it timed
    (limited to one first, `_blas.limited`).
    """
    with _blas.limited(1):
        result = _timed_trial(rng, K_values, horizon, max_generators, max_constraints)
        result["blas_threads"] = max(_blas.thread_counts(_blas.in_force()), default=0)
    return result


def _timed_trial(rng, K_values, horizon, max_generators, max_constraints) -> dict:
    us = rng.standard_normal((horizon, 1))
    seed = int(rng.integers(2 ** 63))
    out = np.empty((len(K_values), len(ESTIMATORS), len(METRICS)))
    seconds = np.empty((len(K_values), len(FILTERS)))
    outside = np.zeros((len(K_values), len(FILTERS)), dtype=int)
    for i, K in enumerate(K_values):
        m = model(K)
        xs, ys = m.simulate(us, np.random.default_rng(seed))
        clock = time.perf_counter()
        cz = ss.lsu_cz_filter(m, ys, us, max_generators=max_generators, max_constraints=max_constraints)
        seconds[i, 0] = time.perf_counter() - clock
        clock = time.perf_counter()
        box = ss.lsuo_filter(m, ys, us)
        seconds[i, 1] = time.perf_counter() - clock
        clock = time.perf_counter()
        par = ss.lsup_filter(m, ys, us)
        seconds[i, 2] = time.perf_counter() - clock
        clock = time.perf_counter()
        kept = ss.lsup_filter(m, ys, us, construction="kept_shape")
        seconds[i, 3] = time.perf_counter() - clock
        for j, (result, key) in enumerate(((cz, "interval_hull"), (cz, "closest"), (cz, "centroid"),
                                           (box, "center"), (par, "center"), (kept, "center"))):
            out[i, j] = metrics(result.estimates[key], xs, result.std)
        outside[i] = [_outside_hulls(r, xs) for r in (cz, box, par, kept)]
    return {"metrics": out, "seconds": seconds, "outside": outside}


def _outside_hulls(result, xs: np.ndarray) -> int:
    """Steps whose true state lies outside the support (boxes, parallelotopes: exactly; CZs: their
    interval hull from the vertices, the exact containment being tested in tests/filters)."""
    count = 0
    for S, x in zip(result.supports, xs):
        if isinstance(S, ss.Box):
            count += not np.all((S.lo <= x) & (x <= S.hi))
        elif isinstance(S, ss.Zonotope):
            count += not np.all(np.abs(np.linalg.solve(S.G, x - S.c)) <= 1.0 + 1e-9)
        else:
            from setsmooth.sets.cz_vertices import cz_vertices

            V = cz_vertices(S)
            count += V is None or V.shape[0] == 0 or not np.all((V.min(0) - 1e-9 <= x) & (x <= V.max(0) + 1e-9))
    return int(count)


def experiment(runs: int, seed: int, out: Path | None = None, workers: int | None = None,
               progress: bool = True, executor=None, K_values=K_VALUES, horizon: int = T,
               max_generators: int = DEFAULT_MAX_GENERATORS,
               max_constraints: int = DEFAULT_MAX_CONSTRAINTS) -> dict:
    """The Monte Carlo of Section 4 (``trial`` × runs), cached in ``out`` by its settings.

    Returns ``metrics`` (runs, K, estimators, METRICS), ``seconds`` (runs, K, filters), ``outside``
    (runs, K, filters), the settings, and ``wall_time_s`` of the computation (0 when read back).
    """
    settings = {"runs": runs, "seed": seed, "K": list(K_values), "T": horizon,
                "max_generators": max_generators, "max_constraints": max_constraints,
                "prior": [X1_LO.tolist(), X1_HI.tolist()], "steady_from": STEADY_FROM}
    key = hashlib.sha1(json.dumps(settings, sort_keys=True).encode()).hexdigest()[:12]
    path = (Path(out) if out is not None else DEFAULT_OUT) / f"lsu_experiment_{key}.npz"
    if path.exists():
        with np.load(path) as cached:
            # A cache written before the threads were recorded reads as 0 threads: unknown.
            return {**{k: cached[k] for k in ("metrics", "seconds", "outside")},
                    "blas_threads": cached["blas_threads"] if "blas_threads" in cached else np.zeros(runs, int),
                    "settings": settings, "cached": True}
    from functools import partial

    clock = time.perf_counter()
    # One Monte Carlo per noise level, all with the same seed: run r draws its inputs and noises first,
    # so at every K it sees the same ones, and these are the runs of `trial` over all K cut into tasks
    # of one K each (same numbers; the tasks spread over the workers and the progress moves per K).
    per_K = [montecarlo.run(partial(trial, K_values=(K,), horizon=horizon, max_generators=max_generators,
                                    max_constraints=max_constraints),
                            runs, seed, executor=executor, progress=progress, workers=workers)
             for K in K_values]
    data = {k: np.concatenate([np.array([r[k] for r in results]) for results in per_K], axis=1)
            for k in ("metrics", "seconds", "outside")}
    data["blas_threads"] = np.array([[r["blas_threads"] for r in results] for results in per_K]).max(axis=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **data)
    return {**data, "settings": settings, "cached": False, "wall_time_s": time.perf_counter() - clock}


def mean_se(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean over runs (axis 0) and its standard error (0 for a single run)."""
    n = values.shape[0]
    se = values.std(axis=0, ddof=1) / np.sqrt(n) if n > 1 else np.zeros(values.shape[1:])
    return values.mean(axis=0), se


def fmt(mean: float, se: float) -> str:
    return f"{mean:.3g} ± {se:.2g}"


def common_settings(exp: dict) -> dict:
    s = exp["settings"]
    return {"runs": s["runs"], "seed": s["seed"], "T": s["T"], "K": s["K"],
            "model": "A, B, C of Section 4.1; ω = 1e−4·1; v = 10^−K·1; u_t ~ N(0, 1)",
            "prior box (ours)": "x_1 ~ U([−1, 1]³)",
            "LSU-CZ maxima (ours)": f"n_g = {s['max_generators']}, n_c = {s['max_constraints']}; "
                                    "reduction Rescale('iter') → EliminateConstraints(n_c) → "
                                    "Girard((n_g − n_c)/n)",
            "experiment computed": "read from cache" if exp["cached"] else "in this script",
            "BLAS threads in force while timing (read back, per run)":
                sorted({int(t) for t in exp["blas_threads"] if t}) or "unknown (cache without the record)"}


#: The conventions shared by the LSU paper's tables and figures, printed above their rows.
REPORT_PREAMBLE = """\
Reproduction of Section 4 of the LSU paper: the model (4)–(6) with A, B, C as printed, ω = 1e−4·1,
v = 10^−K·1 for the 11 printed K, u_t ~ N(0, 1), t̄ = 600; LSUCZ-1/2 (Algorithm 1 with Method 1/2),
LSUO, LSUP (two constructions), and the centroid of the LSU-CZ support (ours). One Monte Carlo serves Tables 1–2 and
Figs. 1–3 (`_lsu_examples.experiment`, cached per settings).

What the paper does not state, and what we chose:
- Runs: the paper does not say how many; ours are in each section (paper size: `--runs 100`). Numbers
  are mean ± standard error over runs. Each run draws u and the standard uniform noises once and
  scales v by 10^−K at every K (common random numbers).
- Prior box (5): x_1 ~ U([−1, 1]³). RMSE = √(mean over t = 1..600 and the 3 components of e²), MAE =
  mean |e|, per run, e = x̂_t − x_t. Because the prior is wide, the first few steps dominate the
  full-horizon errors at small noise; we also give "steady" errors over t = 11..600.
- STD (Fig. 3): the standard deviation of x_t under the uniform density on the support (the
  posterior spread of the approximation, averaged over t and components). It is the same for
  LSUCZ-1 and LSUCZ-2 (one support), as the paper's Fig. 3 suggests. The standard deviation of the
  estimation error is in the JSON (`error_std`).
- LSU-CZ complexity maxima n_g = 9 generators, n_c = 2 constraints, reduced by the library's
  Rescale('iter') → EliminateConstraints(n_c) → Girard((n_g − n_c)/n) (`lsu_complexity` shows the
  errors for other maxima). Method 2 is the ∞-norm closest point (one LP).
- LSUP (min. volume): Vicino–Zappa minimal-volume parallelotope after the data update (both strips
  at once), minimal-volume generator selection after the time update. LSUP (kept shape): the
  predicted edges AT kept, one strip at a time — this variant reproduces the paper's LSUP column
  where it is not dominated by the prior (K ≤ 1.5), so we take it to be the paper's construction
  (`setsmooth.filters.lsu.parallelotope`).
"""


def curve_figure(exp: dict, metric: str, published: dict | None, ylabel: str, title: str):
    """Mean ± s.e. of one metric against K for every estimator (ours solid, the paper's dashed); a
    second panel with the steady part (t ≥ STEADY_FROM + 1) when the metric has one."""
    import matplotlib.pyplot as plt

    K = np.array(exp["settings"]["K"])
    panels = [(metric, "t = 1..600")]
    if metric + "_steady" in METRICS:
        panels.append((metric + "_steady", f"steady part, t = {STEADY_FROM + 1}..600"))
    fig, axes = plt.subplots(1, len(panels), figsize=(7.5 * len(panels), 5), squeeze=False)
    colors = dict(zip(ESTIMATORS, ("tab:blue", "tab:orange", "tab:purple", "tab:green", "tab:red",
                                   "tab:brown")))
    for ax, (name_metric, part) in zip(axes[0], panels):
        mean, se = mean_se(exp["metrics"][..., METRICS.index(name_metric)])
        for j, name in enumerate(ESTIMATORS):
            ax.errorbar(K, mean[:, j] * 1e3, yerr=se[:, j] * 1e3, color=colors[name], marker="o", ms=4,
                        capsize=2, label=f"{LABELS[name]} (ours)")
            if published is not None and name in PAPER_COLUMNS:
                k = PAPER_COLUMNS.index(name)
                pk = [x for x in K if published.get(x) and published[x][k] is not None]
                ax.plot(pk, [published[x][k] for x in pk], color=colors[name], ls="--", marker="x",
                        label=f"{PAPER_ESTIMATORS[k]} (paper, t = 1..600)")
        ax.set_yscale("log")
        ax.invert_xaxis()
        ax.set(xlabel="K  (v = 10^−K)", ylabel=ylabel, title=f"{title}: {part}")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def ordering(values: np.ndarray, names=PAPER_ESTIMATORS, se: np.ndarray | None = None) -> str:
    """Estimators sorted by a metric, best first: 'LSUCZ-1 < LSUP < ...'; with standard errors ``se``,
    neighbours closer than two standard errors of their difference are a tie: 'LSUO ≈ LSUP'."""
    order = np.argsort(values)
    text = names[order[0]]
    for a, b in zip(order[:-1], order[1:]):
        tie = se is not None and values[b] - values[a] <= 2 * np.hypot(se[a], se[b])
        text += (" ≈ " if tie else " < ") + names[b]
    return text


def consistent(values: np.ndarray, se: np.ndarray, paper) -> bool:
    """Whether ``values`` (± ``se``) keep every pairwise order of ``paper``, a reversal within two standard
    errors of the difference counting as a tie."""
    paper = np.asarray(paper, dtype=float)
    return all(values[a] - values[b] <= 2 * np.hypot(se[a], se[b])
               for a in range(len(paper)) for b in range(len(paper)) if paper[a] < paper[b])


def error_curve_main(name: str, metric: str, label: str, published: dict, figure: int, table: int,
                     runs: int, seed: int, out: Path | None, workers: int | None, progress: bool,
                     executor, **experiment_options) -> dict:
    """Figs. 1 and 2: one error metric against K for every filter, the paper's table values dashed.

    ``metric`` is ``'rmse'`` or ``'mae'``; ``published`` the paper's table of it (Table ``table``).
    """
    from _outputs import Stopwatch, finish, row

    clock = Stopwatch()
    exp = experiment(runs, seed, out, workers, progress, executor, **experiment_options)
    K = exp["settings"]["K"]
    mean, se = mean_se(exp["metrics"][..., METRICS.index(metric)] * 1e3)
    columns = [ESTIMATORS.index(e) for e in PAPER_COLUMNS]
    rows = []
    for i, k in enumerate(K):
        pub = published.get(k)
        rows.append(row(f"{label}·10³ at K = {k:g}, best → worst (≈: within 2 s.e.; LSUP: kept shape)",
                        ordering(np.array(pub, dtype=float)) if pub and None not in pub else "all < 1e-3",
                        ordering(mean[i, columns], se=se[i, columns])
                        + f" (centroid {mean[i, ESTIMATORS.index('LSUCZ-c')]:.3g} vs LSUCZ-1 {mean[i, 0]:.3g}; "
                        f"LSUP min. volume {mean[i, ESTIMATORS.index('LSUP')]:.3g}; LSUP kept shape "
                        f"{mean[i, ESTIMATORS.index('LSUP-kept')]:.3g} vs paper LSUP "
                        f"{pub[3] if pub and pub[3] is not None else '< 1e-3'})"))
    # The paper's ordering at high noise (K ≤ 1), where its columns are steady-state numbers.
    high = [i for i, k in enumerate(K) if k <= 1.0 and published.get(k) and None not in published[k]]
    same = [consistent(mean[i, columns], se[i, columns], published[K[i]]) for i in high]
    checks = [_verdicts.claim(
        f"{label} ordering of LSUCZ-1 / LSUCZ-2 / LSUO / LSUP at K ≤ 1 as in Table {table} (up to ties "
        "within 2 s.e.)", all(same),
        f"consistent at {sum(same)} of {len(high)} noise levels"
        + "".join(f"; at K = {K[i]:g} ours {ordering(mean[i, columns], se=se[i, columns])}, paper "
                  f"{ordering(np.array(published[K[i]], dtype=float))}" for i, ok in zip(high, same) if not ok),
        f"s.e. over {exp['settings']['runs']} runs up to {se[high][:, columns].max():.2g} (·10³)"
        if high else None)]
    title = f"Fig. {figure}: {label} of the state estimates ({exp['settings']['runs']} runs)"
    fig = curve_figure(exp, metric, published, f"{label}·10³", title)
    data = {"figure": f"LSU paper Fig. {figure}", "rows": rows, "checks": checks,
            "settings": common_settings(exp),
            "published": {"runs": PAPER_RUNS, "values": published, "table": table},
            "K": K, "estimators": ESTIMATORS, "mean": mean, "se": se}
    return finish(out, name, PAPER, fig, data, clock)
