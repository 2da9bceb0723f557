"""The exact classical CZ filter against the reduced (bounded) filters of CORA, side by side in one run.

Setting of the stability paper's Table 1: random observable systems from ``control.drss(n, n, n)``
(seeded, redrawn until (A, C) is observable), n = p = m, W = [−1, 1]^p, V = [−1, 1]^m, prior
⟦x̂0⟧ = [−10, 10]^n, true x0 uniform in it, steps k = 0..100. For every filter:

  step time     one step of the filter (prediction, update, and the reduction for the reduced
                filters), timed around the step only; median over the steps, and the medians of the
                first 10 and last 10 steps (a bounded filter's step time stays flat in k)
  radius        the interval-hull ∞-radius (largest half-width, certified interval hull) averaged
                over k, outside the timing ("diameters in the sense of ∞-norm" of Table 1, which the
                paper's code computes as half-widths)

Filters: 'exact' (Algorithm 1 without reduction: its CZ grows by 2n factors and n constraints per
step, so its interval hulls get expensive; its horizon is capped, see EXACT_STEPS), and the reduced
filter with each named pipeline, ``ss.CORA_GIRARD`` and ``ss.CORA_COMBASTEL``. Radii are averaged over
the exact filter's capped horizon for all filters (column 'radius@K'), and over all 101 steps for the
reduced ones. One system per n (the paper averages 100); times are this machine's.

    python benchmarks/bench_reduction.py            # n = 10, 20, 30: a few minutes
    python benchmarks/bench_reduction.py --quick    # n = 10 only, 31 steps
    PYTHONPATH=. python benchmarks/bench_reduction.py --montecarlo 1000 --mc-steps 20

``--montecarlo RUNS`` runs the Monte Carlo of tests/filters/test_reduced_filter.py (the `trial`
generator of setsmooth/reliability/reduced_filter_trials.py: drss systems n = 2..10, m ≤ n outputs,
box-uniform, box-vertex and CZ noises, the five pipelines in rotation) at a longer horizon than the
test affords, and prints how many true states fall outside their reduced posterior (the claim: 0), per
pipeline.

BLAS runs single-threaded here (OPENBLAS_NUM_THREADS=1 unless set): the filters' dense algebra is
small (≤ 120×120), and on a shared 2-core machine OpenBLAS's threads made a 120×120×90 product take
9 ms instead of 0.05 ms.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy loads OpenBLAS

import argparse  # noqa: E402
import time  # noqa: E402

import control  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.filters.steps import predict, update  # noqa: E402
from setsmooth.sets.reduction import apply_methods  # noqa: E402

#: Steps of the exact filter per n: its interval hulls are LPs over n + 2nk factors.
EXACT_STEPS = {10: 31, 20: 21, 30: 11}
PIPELINES = {"CORA_GIRARD": ss.CORA_GIRARD, "CORA_COMBASTEL": ss.CORA_COMBASTEL}


def observable_system(n: int, seed: int) -> ss.LinearSystem:
    """drss(n, n, n) redrawn until (A, C) is observable; NumPy's global state restored afterwards."""
    state = np.random.get_state()
    try:
        np.random.seed(seed)
        while True:
            s = control.drss(n, n, n)
            if np.linalg.matrix_rank(control.obsv(s.A, s.C)) == n:
                break
    finally:
        np.random.set_state(state)
    box = ss.Box(-np.ones(n), np.ones(n))
    return ss.LinearSystem(s.A, None, s.C, E=s.B, W=box, V=box)


def run_filter(system, X0, ys, methods):
    """The classical filter's loop (as in `classical_filter`), each step timed; hulls outside."""
    times, radii = [], []
    post = None
    for k, y in enumerate(ys):
        start = time.perf_counter()
        prior = X0 if k == 0 else predict(system, k - 1, post)
        post = update(system, k, prior, y)
        if methods is not None:
            post = apply_methods(post, methods)
        times.append(time.perf_counter() - start)
        hull = post.interval_hull(certified=True)
        radii.append(float(np.max(hull.widths()) / 2))
    return np.array(times), np.array(radii), post


def montecarlo(runs: int, steps: int) -> None:
    """True states outside the reduced posteriors over `runs` seeded runs of `steps` steps."""
    from collections import Counter

    from setsmooth.reliability.reduced_filter_trials import PIPELINES as MC_PIPELINES
    from setsmooth.reliability.reduced_filter_trials import holds, trial

    outside, states, runs_by, secs = Counter(), Counter(), Counter(), Counter()
    short_m = 0
    for run in range(runs):
        system, X0, xs, ys, name = trial(run, horizon=steps)
        short_m += system.m < system.n
        start = time.perf_counter()
        posteriors = ss.classical_filter(system, X0, ys, reduce=MC_PIPELINES[name], detect_empty=False)
        secs[name] += time.perf_counter() - start
        runs_by[name] += 1
        for post, x in zip(posteriors, xs):
            states[name] += 1
            outside[name] += not holds(post, x)
    print(f"Monte Carlo: {runs} runs × {steps} steps (posteriors k = 0..{steps}), m < n in {short_m} runs")
    print(f"{'pipeline':<24} {'runs':>5} {'states':>7} {'outside':>8} {'ms/step':>8}")
    for name in MC_PIPELINES:
        print(f"{name:<24} {runs_by[name]:>5} {states[name]:>7} {outside[name]:>8} "
              f"{1e3 * secs[name] / max(states[name], 1):>8.2f}")
    print(f"{'total':<24} {runs:>5} {sum(states.values()):>7} {sum(outside.values()):>8}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="n = 10 only, 31 steps")
    parser.add_argument("--seed", type=int, default=2024)
    parser.add_argument("--montecarlo", type=int, metavar="RUNS", default=0,
                        help="run the reduced-filter Monte Carlo (RUNS runs) instead of the table")
    parser.add_argument("--mc-steps", type=int, default=20, help="steps per Monte-Carlo run")
    args = parser.parse_args()
    if args.montecarlo:
        montecarlo(args.montecarlo, args.mc_steps)
        return
    sizes = [10] if args.quick else [10, 20, 30]
    steps = 31 if args.quick else 101

    print(f"{'n':>3} {'filter':<15} {'steps':>5} {'step ms':>9} {'first10':>9} {'last10':>9} "
          f"{'radius@K':>9} {'radius':>8} {'ng, nc at end':>14}")
    for n in sizes:
        system = observable_system(n, args.seed + n)
        X0 = ss.Box(-10 * np.ones(n), 10 * np.ones(n))
        rng = np.random.default_rng(args.seed + n)
        xs, ys = ss.simulate(system, X0, steps - 1, rng)
        K = min(EXACT_STEPS[n], steps)
        rows = [("exact", ys[:K], None)] + [(name, ys, methods) for name, methods in PIPELINES.items()]
        for name, data, methods in rows:
            times, radii, last = run_filter(system, X0, data, methods)
            inside = all(p.contains(x) for p, x in zip([last], xs[len(data) - 1:len(data)]))
            size = f"{last.ng}, {last.nc}" + ("" if inside else " (x_T outside!)")
            print(f"{n:>3} {name:<15} {len(data):>5} {np.median(times) * 1e3:>9.2f} "
                  f"{np.median(times[:10]) * 1e3:>9.2f} {np.median(times[-10:]) * 1e3:>9.2f} "
                  f"{radii[:K].mean():>9.3f} {radii.mean():>8.3f} {size:>14}", flush=True)


if __name__ == "__main__":
    main()
