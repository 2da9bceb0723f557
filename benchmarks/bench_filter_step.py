"""Per-step time of `classical_filter` on the smoothing paper's example (31), two checkouts side by side.

The filter runs T = 200 steps from X0 = [−5, 5]² on one simulated trajectory (seed 0); the CPU time of
one run (``time.process_time``: the machine is shared, and waiting for a core is not the filter's cost)
divided by T + 1 is the per-step time, and the table prints the median over the repeats, for the
filter as users call it (an emptiness program per step) and with ``detect_empty=False`` (the set
algebra alone, where re-validating the operands and rebuilding B·W and D·(−V) every step show most).

Usage: python benchmarks/bench_filter_step.py [--baseline DIR] [--repeats 5] [--horizon 200]

With ``--baseline DIR`` (a checkout of another version, e.g. ``git archive main | tar -x -C DIR``) the
same measurement runs for both checkouts, each in its own subprocess, alternating, in one invocation.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def measure(horizon: int, repeats: int) -> dict[str, list[float]]:
    """Per-step seconds of each repeat, for both variants (runs in the checkout on sys.path)."""
    import numpy as np

    import setsmooth as ss

    s1, c1 = np.sin(1.0), np.cos(1.0)
    system = ss.LinearSystem([[s1, c1], [-c1, s1]], None, [[0.5, 0.5], [1.0, 0.3]], E=[[0.5], [1.0]],
                             W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0, -1.0], [1.0, 1.0]))
    X0 = ss.Box([-5.0, -5.0], [5.0, 5.0])
    _, ys = ss.simulate(system, X0, horizon, np.random.default_rng(0))
    out: dict[str, list[float]] = {"detect_empty=True": [], "detect_empty=False": []}
    for _ in range(repeats):
        for name, detect in (("detect_empty=True", True), ("detect_empty=False", False)):
            start = time.process_time()
            ss.classical_filter(system, X0, ys, detect_empty=detect)
            out[name].append((time.process_time() - start) / (horizon + 1))
    return out


def _run_in(checkout: str, horizon: int, repeats: int) -> dict[str, list[float]]:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout))
    cmd = [sys.executable, os.path.abspath(__file__), "--child", "--horizon", str(horizon),
           "--repeats", str(repeats)]
    result = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(result.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", help="another checkout to measure side by side")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--horizon", type=int, default=200)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.horizon, args.repeats)))
        return

    this = os.path.dirname(HERE)
    checkouts = {"this": this} if args.baseline is None else {"baseline": args.baseline, "this": this}
    times: dict[str, dict[str, list[float]]] = {name: {} for name in checkouts}
    for _ in range(args.repeats):  # alternate the checkouts, so load drifts hit both alike
        for name, path in checkouts.items():
            for variant, values in _run_in(path, args.horizon, 1).items():
                times[name].setdefault(variant, []).extend(values)

    print(f"classical_filter on example (31), T = {args.horizon}: median CPU ms per step over {args.repeats} runs")
    header = f"{'variant':<22}" + "".join(f"{name:>12}" for name in checkouts)
    print(header + (f"{'ratio':>10}" if args.baseline else ""))
    for variant in times["this"]:
        medians = {name: 1e3 * statistics.median(times[name][variant]) for name in checkouts}
        row = f"{variant:<22}" + "".join(f"{medians[name]:>12.3f}" for name in checkouts)
        if args.baseline:
            row += f"{medians['baseline'] / medians['this']:>9.2f}x"
        print(row)
    for name, path in checkouts.items():
        print(f"  {name}: {os.path.abspath(path)}")


if __name__ == "__main__":
    main()
