"""The same Monte-Carlo runs on the default process pool and on a 2-worker local Dask cluster.

Runs the trials of smoothing Figs. 6 (many cheap runs) and 3 (fewer, heavier runs) through
`setsmooth.runs.montecarlo.run` with ``executor=None`` (a 2-process pool started per call, as the figure
scripts do) and with a ``dask.distributed.Client`` on a ``LocalCluster`` of 2 worker processes on
loopback (started once; its start-up time is printed apart). Prints median wall times over
``--repeats`` and the ratio Dask / pool, and checks that both give bit-identical results.

    PYTHONPATH=. python benchmarks/bench_dask.py [--runs3 60] [--runs6 2000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

FIGURES = Path(__file__).resolve().parents[1] / "paper_figures"
sys.path.insert(0, str(FIGURES))

from distributed import Client, LocalCluster  # noqa: E402

import smoothing_fig3  # noqa: E402
import smoothing_fig6  # noqa: E402
from setsmooth.runs.montecarlo import run  # noqa: E402


def timed(trial, runs: int, executor, repeats: int) -> tuple[float, list]:
    times, results = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        results = run(trial, runs, seed=0, executor=executor, progress=False, workers=None)
        times.append(time.perf_counter() - start)
    return statistics.median(times), results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs3", type=int, default=60, help="runs of the Fig. 3 trial")
    parser.add_argument("--runs6", type=int, default=2000, help="runs of the Fig. 6 trial")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    start = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                           dashboard_address=":0", silence_logs=40)
    client = Client(cluster)
    client.run(lambda: __import__("smoothing_fig3") and __import__("smoothing_fig6"))  # warm imports
    print(f"local cluster start-up (2 worker processes, imports warm): {time.perf_counter() - start:.1f} s")
    print(f"median of {args.repeats} repeats\n")
    print("| trial | runs | process pool (2) s | Dask LocalCluster (2) s | Dask / pool | identical |")
    print("| --- | --- | --- | --- | --- | --- |")
    try:
        for name, trial, runs in (("smoothing Fig. 6", smoothing_fig6.trial, args.runs6),
                                  ("smoothing Fig. 3", smoothing_fig3.trial, args.runs3)):
            pool_s, pool_results = timed(trial, runs, None, args.repeats)
            dask_s, dask_results = timed(trial, runs, client, args.repeats)
            same = _plain(pool_results) == _plain(dask_results)
            print(f"| {name} | {runs} | {pool_s:.2f} | {dask_s:.2f} | {dask_s / pool_s:.2f} | {same} |")
    finally:
        client.close()
        cluster.close()


def _plain(results: list):
    """The runs' numbers as bytes (the trials return dicts/tuples of arrays and floats)."""
    import numpy as np

    def convert(value):
        if isinstance(value, dict):
            return {k: convert(v) for k, v in sorted(value.items())}
        if isinstance(value, (list, tuple)):
            return [convert(v) for v in value]
        if isinstance(value, np.ndarray):
            return (value.dtype.str, value.shape, value.tobytes())
        return np.asarray(value).tobytes()   # floats and NumPy scalars by their bits

    return convert(results)


if __name__ == "__main__":
    main()
