"""Hit-and-run on constrained zonotopes: chords kept along the walk vs one fresh program per chord.

`setsmooth.sets.sampling.hit_and_run` draws the chord {x + t d} ∩ Z of a set with a constrained-zonotope
form as max and min of t over one program whose matrix changes from move to move only in the column
−d (`sampling._CZChords`, a `ParametricPoints` session). The reference is the generic chord, the interval
hull of the 1-D set {t : x + t d ∈ Z} built and solved afresh at every move (``program_chord``).

For random CZs (n states, 2n generators, n // 2 constraints, seeded) both walks run from the same seed,
alternating, ``--repeats`` times. The table gives the median process CPU milliseconds per move of each,
the ratio, and the largest distance between the two walks' draws relative to the set's size (the chords
agree to the solver's accuracy, so the walks stay together).

Usage: python benchmarks/bench_hit_and_run.py [--dims 3 5 8] [--draws 20] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import setsmooth as ss  # noqa: E402
from setsmooth.sets import sampling  # noqa: E402

from side_by_side import patched  # noqa: E402


def random_cz(n: int, seed: int) -> ss.ConstrainedZonotope:
    rng = np.random.default_rng([seed, n])
    ng, nc = 2 * n, n // 2
    return ss.ConstrainedZonotope(rng.standard_normal((n, ng)), rng.standard_normal(n),
                                  A=0.3 * rng.standard_normal((nc, ng)), b=np.zeros(nc))


def walk(Z, draws: int, seed: int) -> tuple[float, np.ndarray, int]:
    """(CPU seconds, draws, moves) of one hit-and-run walk."""
    n = Z.dim
    moves = 20 * n * n + 50 + (2 * n + 1) * draws
    t0 = time.process_time()
    X = sampling.hit_and_run(Z, np.random.default_rng(seed), draws)
    return time.process_time() - t0, X, moves


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dims", type=int, nargs="+", default=[3, 5, 8])
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    fresh = {"_CZChords": lambda cz, program_chord: program_chord}
    print(f"setsmooth {ss.__version__}: hit-and-run on a CZ, CPU ms per move, medians of {args.repeats}\n")
    print("| n | moves | fresh program per chord | kept chords | ratio | largest draw difference |")
    print("|---|---|---|---|---|---|")
    for n in args.dims:
        Z = random_cz(n, args.seed)
        size = float(Z.interval_hull().widths().max())
        kept_s, fresh_s, diff = [], [], 0.0
        for _ in range(args.repeats):
            t_kept, X_kept, moves = walk(Z, args.draws, args.seed)
            with patched(sampling, fresh):
                t_fresh, X_fresh, _ = walk(Z, args.draws, args.seed)
            kept_s.append(t_kept / moves)
            fresh_s.append(t_fresh / moves)
            diff = max(diff, float(np.abs(X_kept - X_fresh).max()) / size)
        k, f = statistics.median(kept_s), statistics.median(fresh_s)
        print(f"| {n} | {moves} | {f * 1e3:.2f} | {k * 1e3:.2f} | {f / k:.1f}× | {diff:.1e} |", flush=True)


if __name__ == "__main__":
    main()
