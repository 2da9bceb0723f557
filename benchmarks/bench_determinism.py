"""The same answers, bit for bit, alone and beside a CPU-heavy competing load.

A subset of the reliability cases (`setsmooth/reliability/random_systems.py`, seed 2026) is run in a fresh
process twice: once alone, once while ``--burners`` processes spin on every core. Each run computes
the plain and the certified interval hulls of every set of the filter, the trajectory smoother and
the recursion smoother, and prints a SHA-256 of all their endpoints (the exact bytes). No answer of
setsmooth may depend on wall-clock time: the two digests must be equal.

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_determinism.py [--cases 0 18 69]
"""

from __future__ import annotations

import argparse
import hashlib
import multiprocessing
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

REGIMES = ("scale1", "scale1e-06", "scale1e+03", "offset1e+06")


def digest(cases: list[int]) -> tuple[str, float, int]:
    """(SHA-256 of every hull endpoint, CPU seconds, number of hulls) of the subset."""
    from benchmarks.side_by_side import hulls
    from setsmooth.reliability.random_systems import base_case, in_regime

    start = time.process_time()
    h = hashlib.sha256()
    count = 0
    for index in cases:
        for regime in REGIMES:
            case = in_regime(base_case(2026, index, T_range=(10, 14), n_range=(2, 4)), regime)
            for estimator in ("filter", "trajectory", "recursion"):
                rows = np.ascontiguousarray(hulls(case, estimator))
                h.update(rows.tobytes())
                count += rows.shape[0]
    return h.hexdigest(), time.process_time() - start, count


def _burn(stop) -> None:
    x = 0.0
    while not stop.is_set():
        for i in range(100_000):
            x += i * 1e-9


def run_child(cases: list[int]) -> str:
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, __file__, "--child", *map(str, cases)], env=env,
                         capture_output=True, text=True, check=True)
    return out.stdout.strip()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, nargs="+", default=[0, 18, 69])
    ap.add_argument("--burners", type=int, default=max(2, os.cpu_count() or 2))
    ap.add_argument("--child", type=int, nargs="+", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        sha, cpu, count = digest(args.child)
        print(f"{sha} {cpu:.1f} {count}")
        return
    alone = run_child(args.cases)
    stop = multiprocessing.Event()
    burners = [multiprocessing.Process(target=_burn, args=(stop,)) for _ in range(args.burners)]
    for p in burners:
        p.start()
    try:
        loaded = run_child(args.cases)
    finally:
        stop.set()
        for p in burners:
            p.join()
    sha_a, cpu_a, n = alone.split()
    sha_b, cpu_b, _ = loaded.split()
    print(f"cases {args.cases} x {len(REGIMES)} regimes x 3 estimators: {n} hulls")
    print(f"alone   {sha_a[:16]}  {float(cpu_a):7.1f} s CPU")
    print(f"loaded  {sha_b[:16]}  {float(cpu_b):7.1f} s CPU  ({args.burners} burners)")
    print("bit for bit: " + ("yes" if sha_a == sha_b else "NO"))
    if sha_a != sha_b:
        sys.exit(1)


if __name__ == "__main__":
    main()
