"""Smoothing cost, measured side by side in one run.

1. One Monte-Carlo trial of the smoothing paper's example (31), T = 50 (one run of Fig. 3): classical
   filter, optimal smoother and the certified interval hulls of every filtered and smoothed set, with
   the smoother computed by the closed-form recursion (Algorithm 1, eq. (24)) on CZs, by the trajectory
   form (CZ posterior views; Fig. 3's way before polygons), and by Algorithm 1 with exact polygons
   (``classical_filter(form='polygon')`` + the recursion; Fig. 3's way now).
2. Smoothing a T = 600 horizon of a 3-state system with the trajectory form (build + all hulls).
3. Assembling the trajectory set's sparse matrix: in one step from index arrays (`setsmooth.trajectories`)
   vs one small scipy block per row group (the previous assembly, kept in setsmooth/reliability/block_assembly.py).

Usage: python benchmarks/bench_smoothing.py [--repeats N] [--seed S] [--horizon T] [--trial-only]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import setsmooth as ss
from setsmooth.papers.smoothing_examples import smoothing_example_31, smoothing_example_31_x0


def three_state_system() -> ss.LinearSystem:
    A = np.array([[0.9, 0.2, 0.0], [-0.2, 0.9, 0.1], [0.0, 0.0, 0.95]])
    B = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, 0.05]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    return ss.LinearSystem(A, None, C, E=B, W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-0.5, -0.5], [0.5, 0.5]))


def trial(system, X0, T, rng, method):
    """Filter, smoother and every certified interval hull; returns (seconds, smoothed hulls)."""
    start = time.perf_counter()
    _, ys = ss.simulate(system, X0, T, rng)
    posteriors = ss.classical_filter(system, X0, ys, form="polygon" if method == "polygon" else "auto")
    if method in ("recursion", "polygon"):
        smoothed = ss.optimal_smoother(system, X0, ys, method="recursion", posteriors=posteriors)
    else:
        smoothed = ss.optimal_smoother(system, X0, ys, method="trajectory")
    hulls_f = [P.interval_hull(certified=True) for P in posteriors]
    hulls_s = [S.interval_hull(certified=True) for S in smoothed]
    return time.perf_counter() - start, hulls_f, hulls_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--horizon", type=int, default=600)
    parser.add_argument("--trial-only", action="store_true", help="only part 1 (one Fig. 3 trial)")
    args = parser.parse_args()

    system, X0 = smoothing_example_31(), smoothing_example_31_x0()
    times = {"recursion": [], "trajectory": [], "polygon": []}
    max_gap = {"recursion": 0.0, "polygon": 0.0}
    for r in range(args.repeats):
        results = {}
        for method in times:
            seconds, _, hulls_s = trial(system, X0, 50, np.random.default_rng(args.seed + r), method)
            times[method].append(seconds)
            results[method] = hulls_s
        for method in max_gap:
            for a, b in zip(results[method], results["trajectory"]):
                max_gap[method] = max(max_gap[method], np.abs(a.lo - b.lo).max(), np.abs(a.hi - b.hi).max())
    med = {m: statistics.median(t) for m, t in times.items()}
    print("One Monte-Carlo trial of example (31), T = 50 (filter + smoother + all certified hulls)")
    print(f"{'method':<12}{'median s':>10}   (repeats = {args.repeats})")
    for m in times:
        print(f"{m:<12}{med[m]:>10.3f}")
    print(f"ratio recursion / trajectory: {med['recursion'] / med['trajectory']:.1f}x; "
          f"max |smoothed hull difference| = {max_gap['recursion']:.2e}")
    print(f"ratio trajectory / polygon: {med['trajectory'] / med['polygon']:.1f}x; "
          f"max |smoothed hull difference| = {max_gap['polygon']:.2e}")
    if args.trial_only:
        return

    system3 = three_state_system()
    X0_3 = ss.Box(-np.ones(3), np.ones(3))
    _, ys = ss.simulate(system3, X0_3, args.horizon, np.random.default_rng(args.seed))
    start = time.perf_counter()
    smoothed = ss.optimal_smoother(system3, X0_3, ys, method="trajectory")
    built = time.perf_counter() - start
    hulls = [S.interval_hull(certified=True) for S in smoothed]
    total = time.perf_counter() - start
    widths = np.array([np.max(h.hi - h.lo) for h in hulls])
    print(f"\nTrajectory form, 3 states, T = {args.horizon}: build {built:.3f} s, "
          f"build + {len(hulls)} certified hulls {total:.1f} s ({1e3 * total / len(hulls):.1f} ms per step); "
          f"mean smoothed ∞-diameter {widths.mean():.3f}")

    assembly(system3, X0_3, ys, args.repeats)


def assembly(system, X0, ys, repeats: int) -> None:
    """Median times of the one-step and the block-by-block assembly, at T = 50 and the full horizon."""
    from setsmooth.reliability.block_assembly import block_assembly

    def median_time(build) -> float:
        times = []
        for _ in range(max(repeats, 5)):
            start = time.perf_counter()
            build()
            times.append(time.perf_counter() - start)
        return statistics.median(times)

    print("\nTrajectory-set assembly (3 states), median ms")
    print(f"{'T':>6}{'one step':>12}{'blocks':>12}{'ratio':>9}")
    for T in (50, ys.shape[0] - 1):
        window = ys[:T + 1]
        new = median_time(lambda: ss.trajectory_set(system, X0, window))
        old = median_time(lambda: block_assembly(system, X0, window))
        print(f"{T:>6}{1e3 * new:>12.2f}{1e3 * old:>12.2f}{old / new:>8.1f}x")


if __name__ == "__main__":
    main()
