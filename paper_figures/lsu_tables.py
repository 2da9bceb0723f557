"""LSU paper Tables 1–2: RMSE and MAE (×10⁻³) of LSUCZ-1, LSUCZ-2, LSUO, LSUP against K, ours beside the paper's.

The experiment (`_lsu_examples.experiment`) is shared with `lsu_fig1`..`lsu_fig3`. Each row gives, per
K, the published values and ours (mean over runs; full horizon t = 1..600, then the steady part
t = 11..600), with the LSU-CZ centroid in brackets; the JSON holds the standard errors.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import _lsu_examples as ex
import _verdicts
from _outputs import Stopwatch, cli, finish, row

NAME = "lsu_tables"
PAPER = ex.PAPER
DEFAULT_RUNS = 3
AFTER = ("lsu_fig3",)     # the shared experiment: see lsu_fig2.AFTER


def table_rows(exp: dict, metric: str, published: dict, label: str) -> tuple[list[dict], dict]:
    """One report row per K: paper LSUCZ-1 / LSUCZ-2 / LSUO / LSUP beside ours (·10³; LSUP: kept shape)."""
    K = exp["settings"]["K"]
    m = exp["metrics"]
    mean, se = ex.mean_se(m[..., ex.METRICS.index(metric)] * 1e3)
    steady, steady_se = ex.mean_se(m[..., ex.METRICS.index(metric + "_steady")] * 1e3)
    paper_idx = [ex.ESTIMATORS.index(e) for e in ex.PAPER_COLUMNS]
    centroid, volume = ex.ESTIMATORS.index("LSUCZ-c"), ex.ESTIMATORS.index("LSUP")
    rows = []
    for i, k in enumerate(K):
        pub = published.get(k)
        paper = " / ".join("< 1e-3" if v is None else f"{v:g}" for v in pub) if pub else "—"
        ours = (" / ".join(f"{mean[i, j]:.3g}" for j in paper_idx)
                + f" (centroid {mean[i, centroid]:.3g}, LSUP min. volume {mean[i, volume]:.3g})"
                + "; steady " + " / ".join(f"{steady[i, j]:.3g}" for j in paper_idx)
                + f" ({steady[i, centroid]:.3g}, {steady[i, volume]:.3g})")
        if pub and None in pub:
            ours += (" — the paper prints '< 10⁻³' (below its table's resolution); ours are of the same "
                     "order, set by the prior's transient")
        rows.append(row(f"{label}, K = {k:g}: LSUCZ-1 / LSUCZ-2 / LSUO / LSUP (kept shape)", paper, ours))
    data = {"K": K, "estimators": ex.ESTIMATORS, "mean": mean, "se": se, "steady_mean": steady,
            "steady_se": steady_se}
    return rows, data


#: Where the published columns are compared number by number: the noise levels whose errors the steady
#: part dominates (at lower noise our prior's transient does, see NOTES).
HIGH_NOISE = (1.0, 0.75, 0.5, 0.25, 0.0)


def table_checks(table: dict, published: dict, label: str, runs: int) -> list[dict]:
    """Per published column, ours at HIGH_NOISE against the paper's; the shape is the column's growth
    with the noise."""
    K = [k for k in HIGH_NOISE if k in list(table["K"])]
    rows = [list(table["K"]).index(k) for k in K]
    checks = []
    if not K:
        return checks
    for j, (column, ours) in enumerate(zip(ex.PAPER_ESTIMATORS, ex.PAPER_COLUMNS)):
        e = ex.ESTIMATORS.index(ours)
        mean = [float(table["mean"][i, e]) for i in rows]
        checks.append(_verdicts.value(
            f"{label} {column}{' (ours: kept shape)' if ours != column else ''}, K = "
            + " / ".join(f"{k:g}" for k in K), mean, [published[k][j] for k in K],
            [float(table["se"][i, e]) for i in rows], shape="the error grows with the noise",
            shape_holds=bool(np.all(np.diff(mean) > 0)), error=f"s.e. over {runs} runs: "
            + ", ".join(f"{table['se'][i, e]:.2g}" for i in rows)))
    return checks


def ordering_rows(exp: dict) -> list[dict]:
    """The paper's qualitative claims about the ordering of the methods, checked on our numbers."""
    K = np.array(exp["settings"]["K"])
    rmse, rmse_se = ex.mean_se(exp["metrics"][..., ex.METRICS.index("rmse")])
    steady, steady_se = ex.mean_se(exp["metrics"][..., ex.METRICS.index("rmse_steady")])
    idx = [ex.ESTIMATORS.index(e) for e in ex.PAPER_COLUMNS]
    low, high = (K >= 2.5) & (K < 4), K <= 1.0
    rows = []
    for what, values, errors in (("full horizon", rmse, rmse_se), ("steady t ≥ 11", steady, steady_se)):
        v, s = values[:, idx], errors[:, idx]
        # "Better" only by more than two standard errors of the difference; closer is a tie.
        box_best = np.minimum(v[low, 2], v[low, 3])
        box_se = np.where(v[low, 2] <= v[low, 3], s[low, 2], s[low, 3])
        cz_best = np.minimum(v[low, 0], v[low, 1])
        cz_se = np.where(v[low, 0] <= v[low, 1], s[low, 0], s[low, 1])
        margin = 2 * np.hypot(box_se, cz_se)
        verdict = ("yes" if np.all(box_best < cz_best - margin) else
                   "tie (within 2 s.e.)" if np.all(np.abs(box_best - cz_best) <= margin) else "no")
        cz1_best = bool(np.all(np.argmin(v[high], axis=1) == 0))
        lsuo_worst = bool(np.all(np.argmax(v[high], axis=1) == 2))
        at3, at0 = list(K).index(3.0), list(K).index(0.0)
        rows += [row(f"RMSE, low noise K ∈ [2.5, 3.5]: LSUO or LSUP better than both LSUCZ ({what}; LSUP kept "
                     "shape)", "yes", f"{verdict}; at K = 3: {ex.ordering(v[at3], se=s[at3])} (≈: within 2 s.e.)"),
                 row(f"RMSE, high noise K ≤ 1: LSUCZ-1 best, LSUO worst ({what}; LSUP kept shape)", "yes",
                     f"LSUCZ-1 best: {'yes' if cz1_best else 'no'}, LSUO worst: {'yes' if lsuo_worst else 'no'};"
                     f" at K = 0: {ex.ordering(v[at0], se=s[at0])}")]
    return rows


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None, **experiment) -> dict:
    clock = Stopwatch()
    exp = ex.experiment(runs, seed, out, workers, progress, executor, **experiment)
    rows1, table1 = table_rows(exp, "rmse", ex.PUBLISHED_RMSE, "Table 1 RMSE·10³")
    rows2, table2 = table_rows(exp, "mae", ex.PUBLISHED_MAE, "Table 2 MAE·10³")
    rows = rows1 + rows2 + ordering_rows(exp)
    outside = exp["outside"].sum(axis=(0, 1))
    rows.append(row("true state outside the support (LSU-CZ hull / LSUO / LSUP / LSUP kept), all runs, K, t",
                    "—",
                    " / ".join(str(int(o)) for o in outside)))
    seconds = exp["seconds"].mean(axis=(0, 1))
    rows.append(row(f"seconds per run of t̄ = {exp['settings']['T']} steps "
                    "(LSU-CZ with 3 estimates / LSUO / LSUP / LSUP kept)",
                    "not stated", " / ".join(f"{s:.2f}" for s in seconds)))
    fig = _plot(table1, table2)
    runs = exp["settings"]["runs"]
    checks = (table_checks(table1, ex.PUBLISHED_RMSE, "Table 1 RMSE·10³", runs)
              + table_checks(table2, ex.PUBLISHED_MAE, "Table 2 MAE·10³", runs))
    data = {"figure": "LSU paper Tables 1–2", "rows": rows, "checks": checks,
            "settings": ex.common_settings(exp),
            "published": {"runs": ex.PAPER_RUNS, "table1_rmse": ex.PUBLISHED_RMSE,
                          "table2_mae": ex.PUBLISHED_MAE},
            "table1": table1, "table2": table2, "outside": outside, "seconds_per_run": seconds,
            "notes": NOTES}
    return finish(out, NAME, PAPER, fig, data, clock)


NOTES = [
    "Prior and transient: the paper does not give its prior box; with ours ([−1, 1]³) the first steps "
    "dominate the full-horizon errors at K ≥ 2.5 (all filters within ~10% of each other), so "
    "the paper's low-noise numbers (LSUO 1.4–1.6, LSUCZ-1 ~6) cannot be compared digit by digit; its "
    "flat low-noise rows suggest a transient there too, from a narrower prior.",
    "LSUO is within ~20% of the paper (ours lower) where the steady part dominates (K ≤ 1): the box "
    "filter is fully specified by the model.",
    "LSUP: the paper's column is reproduced (within ~5% at K ≤ 1) by the simple "
    "construction that keeps the predicted edges A·T and applies Vicino–Zappa one strip at a time "
    "(`lsup_filter(construction='kept_shape')`, 'LSUP kept shape' in brackets). Choosing the "
    "minimal-volume parallelotope among all generator and face choices (our default LSUP) gives "
    "errors 10–1000× smaller at high noise: the kept shape degenerates under the shear of A.",
    "Ordering: at low noise the paper finds LSUO/LSUP slightly better than LSU-CZ; we find LSU-CZ at "
    "least as good in the steady part at every K from 3.5 to 0.25, because its support keeps (within n_g, n_c) "
    "the constraints of past outputs that a box or parallelotope discards, and with ω = 1e−4 the state "
    "is nearly deterministic given u, so those constraints are worth much. At high noise the paper "
    "finds LSUCZ-1 best; we find it better than LSUO and the paper's LSUP (kept shape), but our "
    "minimal-volume LSUP is better still at K = 0 with the default maxima (9, 2); `lsu_complexity` "
    "shows LSU-CZ narrowing that gap with exact rescaling, at 2× the cost.",
    "LSU-CZ against the paper: the paper does not state its maxima. With our default (9, 2) the steady "
    "LSUCZ-1 error is about 0.1·10⁻³ at every K, far below the paper's, so our full-horizon LSU-CZ numbers "
    "are mostly our prior's transient (their ratios to the paper are in the verdict table); "
    "`lsu_complexity` sweeps the maxima from (3, 0) to (9, 2) and names the budget closest to the "
    "paper's LSUCZ-1 column (a smaller one, whose steady error is of the paper's size). The K = 4 row: "
    "the paper prints '< 10⁻³' for every filter, below its table's resolution; ours there are set by "
    "the prior's transient (see the first note).",
    "LSUCZ-2 (∞-norm closest point to the zonotope centre, one LP) is close to LSUCZ-1 here, unlike "
    "in the paper (141.7 vs 50.3 at K = 0); the paper's 'two LPs' are not stated. The centroid "
    "(posterior mean of the uniform approximation) is the best LSU-CZ estimate at high noise.",
]


def _plot(table1: dict, table2: dict):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
    for ax, table, published, title in ((axes[0], table1, ex.PUBLISHED_RMSE, "Table 1: RMSE·10³"),
                                        (axes[1], table2, ex.PUBLISHED_MAE, "Table 2: MAE·10³")):
        for k_i, k in enumerate(table["K"]):
            pub = published.get(k)
            if not pub:
                continue
            for j, (name, ours) in enumerate(zip(ex.PAPER_ESTIMATORS, ex.PAPER_COLUMNS)):
                if pub[j] is None:
                    continue
                e = ex.ESTIMATORS.index(ours)
                ax.scatter(pub[j], table["mean"][k_i, e], marker="o", s=18,
                           color=f"C{j}", label=ex.LABELS[ours] if k_i == 1 else None)
                ax.scatter(pub[j], table["steady_mean"][k_i, e], marker="x", s=18, color=f"C{j}")
        lims = [1e-3, 1e3]
        ax.plot(lims, lims, "k:", lw=1)
        ax.set(xscale="log", yscale="log", xlabel="paper", ylabel="ours (o: t = 1..600, x: t = 11..600)",
               title=title)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
