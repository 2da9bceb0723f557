"""LSU paper filters: per-step cost of LSU-CZ, LSUO and LSUP on the Section 4 model, and where it goes.

One data sequence of t̄ steps at one noise level K; each filter is timed over ``--repeats`` runs
(median), then profiled once to split its time into the parts below (cumulative seconds of the named
functions, as a share of the filter's profiled time):

  LSU-CZ   algebra (prediction (16) + generalized intersection (15)), reduction (Rescale → Eliminate
           → Girard), vertices (enumeration), hull (Qhull: centroid, spread), Method 2 (closest point
           from the hull's vertices up to 3-D, one LP beyond)
  LSUO     algebra, vertices (box ∩ strip), interval hull of the prediction
  LSUP     algebra, vertices (parallelotope ∩ strips), the parallelotope choices

    python benchmarks/bench_lsu.py                 # K = 1, t̄ = 600, 3 repeats: ~30 s
    python benchmarks/bench_lsu.py --K 0 --T 200
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import time
from pathlib import Path

import numpy as np

import setsmooth as ss

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "paper_figures"))
import _lsu_examples as ex  # noqa: E402

PARTS = {
    "LSU-CZ": {"algebra": ("steps.py", ("_predict", "_update")),
               "reduction": ("__init__.py", ("apply_methods",)),
               "vertices": ("cz_vertices.py", ("cz_vertices",)),
               "hull (Qhull)": ("cz_vertices.py", ("hull_geometry",)),
               "Method 2": ("estimates.py", ("closest_point_of_hull", "closest_to_zonotope_center"))},
    "LSUO": {"algebra": ("algebra.py", ("generalized_intersection", "minkowski_sum", "linear_map")),
             "vertices": ("cz_vertices.py", ("cz_vertices",)),
             "prediction hull": ("_base.py", ("apply",))},
    "LSUP": {"algebra": ("algebra.py", ("generalized_intersection",)),
             "vertices": ("cz_vertices.py", ("cz_vertices",)),
             "data update choice": ("parallelotope.py", ("parallelotope_update",)),
             "time update choice": ("parallelotope.py", ("parallelotope_predict",))},
}


def run(name, model, ys, us):
    if name == "LSU-CZ":
        return ss.lsu_cz_filter(model, ys, us)
    return (ss.lsuo_filter if name == "LSUO" else ss.lsup_filter)(model, ys, us)


def profile_parts(name, model, ys, us) -> tuple[float, dict]:
    prof = cProfile.Profile()
    prof.enable()
    run(name, model, ys, us)
    prof.disable()
    stats = pstats.Stats(prof).stats
    total = max(v[3] for v in stats.values())
    parts = {}
    for part, (file, functions) in PARTS[name].items():
        parts[part] = sum(v[3] for (f, _, fn), v in stats.items() if f.endswith(file) and fn in functions)
    return total, parts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--K", type=float, default=1.0)
    parser.add_argument("--T", type=int, default=ex.T)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    model = ex.model(args.K)
    rng = np.random.default_rng(0)
    us = rng.standard_normal((args.T, 1))
    xs, ys = model.simulate(us, rng)
    print(f"LSU model of Section 4, K = {args.K:g}, t̄ = {args.T}; medians of {args.repeats} runs")
    print(f"{'filter':8s} {'s/run':>8s} {'ms/step':>8s} {'vs LSUO':>8s}   where the time goes (profiled)")
    medians = {}
    for name in ("LSUO", "LSUP", "LSU-CZ"):
        times = []
        for _ in range(args.repeats):
            clock = time.perf_counter()
            run(name, model, ys, us)
            times.append(time.perf_counter() - clock)
        medians[name] = float(np.median(times))
    total_all = 0.0
    for name in ("LSU-CZ", "LSUO", "LSUP"):
        med = medians[name]
        total_all += med
        total, parts = profile_parts(name, model, ys, us)
        split = ", ".join(f"{p} {100 * s / total:.0f}%" for p, s in parts.items())
        print(f"{name:8s} {med:8.2f} {1e3 * med / args.T:8.2f} {med / medians['LSUO']:8.1f}   {split}")
    print(f"all filters at one K: {total_all:.2f} s per run of {args.T} steps "
          f"(x 11 noise levels = {11 * total_all:.0f} s per Monte Carlo run of the paper's experiment)")


if __name__ == "__main__":
    main()
