"""The two examples of the smoothing paper §IV-C, and what the figure scripts share.

Linear example (31): Φ = [[sin 1, cos 1], [−cos 1, sin 1]], Γ = [0.5, 1]ᵀ, Ξ = [[0.5, 0.5], [1, 0.3]],
Ψ = I, ⟦w_k⟧ = [−1, 1], ⟦v_k⟧ = [−1, 1]², over k ∈ [0, 50] (Figs. 3–5).

Nonlinear example (33)–(34): x_{k+1} = ∛x_k + x_k + w_k, y_k = 2x_k + v_k, ⟦w_k⟧ = [−1, 1],
⟦v_k⟧ = [1, 3] (Fig. 6).

The paper does not state ⟦x_0⟧ for either example. We take ⟦x_0⟧ = [−5, 5]² for (31) and [−5, 5] for
(33): wider than what one measurement tells (Ξ⁻¹⟦v⟧ has widths 4.6 × 8.6 for (31); (34) pins x_k to an
interval of width 1), so the first posteriors are shaped by the data rather than by the prior, and
x_0 is drawn uniformly from the same set. All noises are uniform on their ranges (paper footnote 3).
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import numpy as np

import setsmooth as ss

T = 50                              # k ∈ [0, T] in Figs. 3–6
PAPER_RUNS = 5000                   # Monte Carlo size of Figs. 3, 5, 6
PAPER_RUNS_PER_PAIR = 100           # Fig. 4
PAPER_BEST_QR = (0.076, 0.036)      # Fig. 4
DEFAULT_OUT = Path(__file__).resolve().parent / "out"
HULL_TOL = 1e-6                     # slack for comparisons of certified interval hulls

# -- linear example (31) ----------------------------------------------------------------------------
X0_LINEAR = ((-5.0, -5.0), (5.0, 5.0))


def linear_system() -> ss.LinearSystem:
    """Smoothing paper example (31)."""
    s1, c1 = np.sin(1.0), np.cos(1.0)
    return ss.LinearSystem([[s1, c1], [-c1, s1]], [[0.5], [1.0]], [[0.5, 0.5], [1.0, 0.3]], np.eye(2),
                           W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0, -1.0], [1.0, 1.0]))


def linear_x0() -> ss.Box:
    return ss.Box(*X0_LINEAR)


def rts_prior() -> tuple[np.ndarray, np.ndarray]:
    """Mean and covariance of x_0 uniform on ⟦x_0⟧, given to the RTS smoother."""
    lo, hi = (np.asarray(v) for v in X0_LINEAR)
    return (lo + hi) / 2, np.diag((hi - lo) ** 2 / 12)


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
    stats = {"mean_diameter_filtered": mean_f, "mean_diameter_smoothed": mean_s,
             "outside_filtered": outside_f, "outside_smoothed": outside_s,
             "smoothed_le_filtered": [int(per_run_ok.sum()), int(per_run_ok.size)]}
    return rows, stats

# -- nonlinear example (33)–(34) --------------------------------------------------------------------
X0_NONLINEAR = (-5.0, 5.0)
W_NONLINEAR = (-1.0, 1.0)
V_NONLINEAR = (1.0, 3.0)


def eta(x):
    """η(x) = ∛x + x of (33): continuous, strictly increasing, onto ℝ."""
    return np.cbrt(x) + x


def eta_inverse(z):
    """η⁻¹ in closed form: t = ∛x solves t³ + t − z = 0 (Cardano, one real root, u·v = −1/3)."""
    z = float(z)
    s = np.sqrt(z * z / 4 + 1 / 27)
    u = np.cbrt(abs(z) / 2 + s)          # the larger Cardano term; no cancellation for either sign
    t = np.copysign(u - 1 / (3 * u), z)
    return t ** 3


def nonlinear_step(k, x, w):
    return eta(x) + w


def nonlinear_measure(k, x, v):
    return 2 * x + v


def nonlinear_system() -> ss.NonlinearSystem:
    """Smoothing paper example (33)–(34)."""
    return ss.NonlinearSystem(nonlinear_step, nonlinear_measure, ss.Box([W_NONLINEAR[0]], [W_NONLINEAR[1]]),
                              ss.Box([V_NONLINEAR[0]], [V_NONLINEAR[1]]), n=1)


def measurement_interval(k, y):
    """{x : y = 2x + v, v ∈ [1, 3]} = [(y − 3)/2, (y − 1)/2] (34)."""
    y = float(np.asarray(y).reshape(-1)[0])
    return (y - V_NONLINEAR[1]) / 2, (y - V_NONLINEAR[0]) / 2


def describe_box(lo, hi) -> str:
    """'[-5, 5]²' for a cube, '[-5, 5] × [0, 1]' otherwise."""
    lo, hi = np.atleast_1d(lo), np.atleast_1d(hi)
    sides = [f"[{a:g}, {b:g}]" for a, b in zip(lo, hi)]
    if len(set(sides)) == 1 and len(sides) > 1:
        return sides[0] + {2: "²", 3: "³"}.get(len(sides), f"^{len(sides)}")
    return " × ".join(sides)


# -- outputs ----------------------------------------------------------------------------------------
class Stopwatch:
    """Wall time, and CPU time of this process plus its finished worker processes (Unix)."""

    def __init__(self):
        self.start = time.perf_counter()
        self.cpu_start = _cpu_time()

    @property
    def seconds(self) -> float:
        return round(time.perf_counter() - self.start, 2)

    @property
    def cpu_seconds(self) -> float | None:
        now = _cpu_time()
        return None if now is None else round(now - self.cpu_start, 2)


def _cpu_time() -> float | None:
    try:
        import resource
    except ImportError:   # Windows
        return None
    usage = [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    return sum(u.ru_utime + u.ru_stime for u in usage)


def row(quantity: str, paper: Any, ours: Any) -> dict:
    """One line of the report: a published value or claim beside ours."""
    return {"quantity": quantity, "paper": paper, "ours": ours}


def write_outputs(out: Path | None, name: str, fig, data: dict) -> dict:
    """Write ``<name>.png`` and ``<name>.json`` to ``out`` and return ``data``."""
    out = Path(out) if out is not None else DEFAULT_OUT
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / f"{name}.png", dpi=150, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    (out / f"{name}.json").write_text(json.dumps(_jsonable(data), indent=1))
    return data


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        return value if np.isfinite(value) else str(value)
    return obj


def cli(main, default_runs: int, description: str) -> None:
    """``--runs --seed --out --workers`` for a figure script run on its own."""
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--runs", type=int, default=default_runs,
                        help=f"Monte Carlo runs (default {default_runs})")
    parser.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output directory")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: 2)")
    args = parser.parse_args()
    result = main(runs=args.runs, seed=args.seed, out=args.out, workers=args.workers)
    for r in result["rows"]:
        print(f"{r['quantity']}: paper {r['paper']} | ours {r['ours']}")
