"""CPU time of Algorithm 2 (`sampled_optimal_filter`), vectorised vs the algorithm box's loop, side by side.

Example (27)–(28) of the rethinking paper, T steps, N accepted samples per step. Three ways, the same
statistics (N uniform accepted candidates per step and run):

* ``loop``: the algorithm box as printed, one candidate per Python iteration (one run only: it is slow);
* ``vectorised, 1 run``: `sampled_optimal_filter` on one run;
* ``vectorised, R runs``: `sampled_optimal_filter` on R runs at once (how Fig. 2 uses it).

Times are CPU seconds (``time.process_time``: the machine is shared) per accepted sample, medians over the
repeats; the last column is the speed-up over the loop. The paper-size Fig. 2 (10,000 runs × N = 10,000,
T = 20) needs 2·10⁹ accepted samples: multiply the ``R runs`` figure by that for its CPU time.

Usage: python benchmarks/bench_sampled_filter.py [--samples 2000] [--runs 50] [--horizon 5] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import setsmooth as ss
from setsmooth.papers.rethinking_examples import eta_27, rethinking_example_27


def loop_filter(system, ys: np.ndarray, rng: np.random.Generator, N: int) -> tuple[np.ndarray, np.ndarray]:
    """Algorithm 2 exactly as the box reads: draw, test, keep until N are accepted."""
    lo, hi = np.empty(len(ys)), np.empty(len(ys))
    lo[0], hi[0] = max(0.0, ys[0] / 2), min(1.0, ys[0])
    for k in range(1, len(ys)):
        kept = []
        while len(kept) < N:
            x_prev, w = rng.uniform(lo[k - 1], hi[k - 1]), rng.uniform(0, 1)
            x = eta_27(x_prev) + w
            if 1.0 <= ys[k] / x <= 2.0 - w:
                kept.append(x)
        lo[k], hi[k] = min(kept), max(kept)
    return lo, hi


def cpu(fn) -> float:
    start = time.process_time()
    fn()
    return time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2000)
    parser.add_argument("--runs", type=int, default=50)
    parser.add_argument("--horizon", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    system = rethinking_example_27()
    _, ys = system.simulate(args.horizon, np.random.default_rng(0), runs=args.runs)
    N, T = args.samples, args.horizon
    cases = {
        "loop, 1 run": (lambda: loop_filter(system, ys[0], np.random.default_rng(1), N), N * T),
        "vectorised, 1 run": (lambda: ss.sampled_optimal_filter(system, ys[0], np.random.default_rng(1), N), N * T),
        f"vectorised, {args.runs} runs": (lambda: ss.sampled_optimal_filter(system, ys, np.random.default_rng(1), N),
                                          N * T * args.runs),
    }
    per_sample = {name: statistics.median(cpu(fn) / count for _ in range(args.repeats))
                  for name, (fn, count) in cases.items()}
    base = per_sample["loop, 1 run"]
    print(f"Algorithm 2 on (27)-(28): N = {N}, T = {T}, median of {args.repeats} repeats")
    print(f"{'variant':<24}{'CPU ns / accepted sample':>26}{'speed-up':>12}")
    for name, value in per_sample.items():
        print(f"{name:<24}{value * 1e9:>26.1f}{base / value:>12.1f}")
    paper = per_sample[f"vectorised, {args.runs} runs"] * 2e9
    print(f"paper-size Fig. 2 (2e9 accepted samples): {paper:.0f} CPU s, {paper / 2:.0f} s on 2 cores")


if __name__ == "__main__":
    main()
