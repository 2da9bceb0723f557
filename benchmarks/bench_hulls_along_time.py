"""Interval hulls along time: what a step costs with its hull, early and late in a run, in one process.

Rows (CPU seconds of this process, medians; the issue "Hulls along time" states the targets):

* ``exact filter, 4 states``: a random stable 4-state system (``control.drss``, seeded), T steps.
  The hulls of every posterior along time (`setsmooth.filters.hulls_along_time.filtered_hulls`,
  what ``classical_filter(...).interval_hulls()`` and ``.lo/.hi`` use), their median cost per step
  near k = T/10 and near k = T, and their total; beside it, one posterior's own hull solved alone
  (``P[k].interval_hull(certified=True)``, a program over all of 0..k) at the same two k. Peak
  memory of the process (ru_maxrss).
* ``example (31), certified hulls``: the smoothing paper's example (31) filter with certified hulls
  along time, per step (build + hulls) at T = 800 (``--quick``: 200).
* ``trajectory smoother, 3 states``: build + certified hulls at T = 600 (``--quick``: 150), the
  system of ``bench_long_horizon.py``'s ``smoother3``.
* ``OIT-CZ (n) + hull`` against ``reduced SMF (n) + hull`` (``ss.CORA_GIRARD``), stability Table 1's
  systems, per step, n = 10, 20, 30 (``--quick``: 10).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_hulls_along_time.py [--quick] [--T 3000]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy loads OpenBLAS

import argparse  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402

import control  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth import analysis  # noqa: E402
from setsmooth.filters.hulls_along_time import filtered_hulls  # noqa: E402


def _cpu(fn, *args, **kwargs):
    start = time.process_time()
    out = fn(*args, **kwargs)
    return time.process_time() - start, out


def _drss_system(seed: int, n: int = 4, p: int = 2, m: int = 2):
    """A stable random system from control.drss (seeded through NumPy's global state, restored)."""
    saved = np.random.get_state()
    np.random.seed(seed)
    try:
        plant = control.drss(n, m, p)
    finally:
        np.random.set_state(saved)
    W = ss.Box(-0.1 * np.ones(p), 0.1 * np.ones(p))
    V = ss.Box(-0.2 * np.ones(m), 0.2 * np.ones(m))
    return ss.LinearSystem(np.array(plant.A), None, np.array(plant.C), E=np.array(plant.B), F=np.eye(m),
                           W=W, V=V)


class _StepClock:
    """CPU time of every step of `filtered_hulls` (the tqdm iterator's ticks)."""

    def __init__(self):
        self.marks: list[float] = []

    def __call__(self, iterable, **_):
        for item in iterable:
            self.marks.append(time.process_time())
            yield item
        self.marks.append(time.process_time())

    def per_step(self) -> np.ndarray:
        return np.diff(self.marks)


def exact_filter_rows(T: int, seed: int) -> list[str]:
    import tqdm.auto

    system = _drss_system(seed)
    X0 = ss.Box(-np.ones(system.n), np.ones(system.n))
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    clock = _StepClock()
    saved, tqdm.auto.tqdm = tqdm.auto.tqdm, clock
    try:
        total, hulls = _cpu(filtered_hulls, system, X0, ys, certified=True, progress=False)
    finally:
        tqdm.auto.tqdm = saved
    per_step = clock.per_step()
    early, late = max(T // 10, 1), T
    window = max(T // 100, 5)
    early_s = float(np.median(per_step[early - window:early + window]))
    late_s = float(np.median(per_step[late - 2 * window:late + 1]))
    posteriors = ss.classical_filter(system, X0, ys)
    alone_early, _ = _cpu(posteriors[early].interval_hull, certified=True)
    alone_late, _ = _cpu(posteriors[late].interval_hull, certified=True)
    inside = all(np.all(h.lo - 1e-9 <= x) and np.all(x <= h.hi + 1e-9) for h, x in zip(hulls, xs))
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return [f"| exact filter, 4 states, T = {T} | along time: {early_s * 1e3:.0f} ms/step at k ≈ {early}, "
            f"{late_s * 1e3:.0f} ms at k ≈ {late} (ratio {late_s / early_s:.2f}); all {T + 1} hulls "
            f"{total:.0f} s; truth inside: {inside}; peak {peak_mb:.0f} MB | one hull alone: "
            f"{alone_early * 1e3:.0f} ms at k = {early}, {alone_late * 1e3:.0f} ms at k = {late} |"]


def example31_row(T: int, seed: int) -> str:
    from setsmooth.papers.smoothing_examples import smoothing_example_31, smoothing_example_31_x0

    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    _, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    total, _ = _cpu(lambda: ss.classical_filter(system, X0, ys).interval_hulls(certified=True,
                                                                               progress=False))
    return f"| example (31) filter + certified hulls, T = {T} | {total / (T + 1) * 1e3:.1f} ms/step | |"


def smoother_row(T: int, seed: int) -> str:
    A = np.array([[0.9, 0.2, 0.0], [-0.2, 0.9, 0.1], [0.0, 0.0, 0.95]])
    E = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, 0.05]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    system = ss.LinearSystem(A, None, C, E=E, F=np.eye(2), W=ss.Box([-1, -1], [1, 1]),
                             V=ss.Box([-0.5, -0.5], [0.5, 0.5]))
    X0 = ss.Box(-np.ones(3), np.ones(3))
    _, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    total, _ = _cpu(lambda: ss.optimal_smoother(system, X0, ys, method="trajectory")
                    .interval_hulls(certified=True, progress=False))
    return f"| trajectory smoother, 3 states, T = {T}, build + certified hulls | {total:.1f} s | |"


def oit_rows(dims: list[int], T: int, seed: int) -> list[str]:
    rows = []
    for n in dims:
        rng = np.random.default_rng([seed, n])
        drawn = analysis.random_observable_system(rng, n, n, n)
        system = drawn.linear_system()
        X0 = ss.Box(-10.0 * np.ones(n), 10.0 * np.ones(n))
        _, ys = ss.simulate(system, X0, T, rng)
        res = ss.oit_cz_filter(system, X0, ys, delta_bar=3, decomposition=drawn.decomposition, hulls=True)
        oit = float(np.median(res.step_seconds[3:] + res.hull_seconds[3:]))
        smf, _ = _cpu(lambda: [Z.interval_hull(certified=True)
                               for Z in ss.classical_filter(system, X0, ys, reduce=ss.CORA_GIRARD)])
        smf /= T + 1
        rows.append(f"| OIT-CZ + certified hull, n = {n} | {oit * 1e3:.1f} ms/step | reduced SMF + hull "
                    f"{smf * 1e3:.1f} ms/step ({smf / oit:.1f}× the OIT-CZ) |")
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (a few minutes)")
    ap.add_argument("--T", type=int, default=None, help="horizon of the 4-state exact filter (3000; quick 600)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--rows", default="exact,example31,smoother,oit",
                    help="comma-separated subset of exact, example31, smoother, oit")
    args = ap.parse_args(argv)
    rows = {r.strip() for r in args.rows.split(",") if r.strip()}
    unknown = rows - {"exact", "example31", "smoother", "oit"}
    if unknown:
        ap.error(f"--rows must name some of exact, example31, smoother, oit; got {sorted(unknown)}")
    T = args.T or (600 if args.quick else 3000)
    print(f"setsmooth {ss.__version__}: hulls along time, CPU seconds of one process\n")
    print("| row | measured | beside it |")
    print("|---|---|---|")
    if "exact" in rows:
        for line in exact_filter_rows(T, args.seed):
            print(line, flush=True)
    if "example31" in rows:
        print(example31_row(200 if args.quick else 800, args.seed), flush=True)
    if "smoother" in rows:
        print(smoother_row(150 if args.quick else 600, args.seed), flush=True)
    if "oit" in rows:
        for line in oit_rows([10] if args.quick else [10, 20, 30], 30, args.seed):
            print(line, flush=True)


if __name__ == "__main__":
    main()
