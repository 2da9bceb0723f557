"""Two solver configurations timed side by side in one run, alternating on the same reliability cases
(the shared loop of ``bench_bracketed_order.py`` and ``bench_warm_simplex.py``).

Each case computes the plain and certified interval hulls of every set of one estimator on one
reliability case (`setsmooth/reliability/random_systems.py`, seed 2026). The table gives the median
process CPU seconds of each configuration, the ratio second/first, and the largest difference
between the two configurations' hull endpoints relative to the hull width plus the noise scale
(issue 7 demands 1e-6 against the exact hull).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path
from types import ModuleType

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import setsmooth as ss  # noqa: E402
from setsmooth.reliability.oracle import data_scale  # noqa: E402
from setsmooth.reliability.random_systems import base_case, in_regime  # noqa: E402


def hulls(case, estimator: str) -> np.ndarray:
    """Rows (lo, hi) of the plain, then the certified interval hull of every set of ``estimator``
    ('recursion', 'trajectory' or 'filter') on ``case``."""
    out = []
    sets = (ss.classical_filter(case.system, case.X0, case.ys) if estimator == "filter" else
            ss.optimal_smoother(case.system, case.X0, case.ys, method=estimator))
    for S in sets:
        for certified in (False, True):
            H = S.interval_hull(certified=certified)
            out.append(np.concatenate([H.lo, H.hi]))
    return np.array(out)


@contextlib.contextmanager
def patched(module: ModuleType, values: dict):
    """The attributes of ``module`` set to ``values`` (name → value) for the duration."""
    saved = {name: getattr(module, name) for name in values}
    for name, value in values.items():
        setattr(module, name, value)
    try:
        yield
    finally:
        for name, value in saved.items():
            setattr(module, name, value)


def main(description: str, cases, module: ModuleType, configs: dict[str, dict],
         repeats: int) -> None:
    """Command line of a side-by-side benchmark: ``--repeats`` (default ``repeats``), then
    `compare` of ``configs`` (name → attribute values of ``module``, `patched`) on ``cases``."""
    ap = argparse.ArgumentParser(description=description,
                                 formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--repeats", type=int, default=repeats)
    args = ap.parse_args()
    compare(cases, {name: (lambda values=values: patched(module, values))
                    for name, values in configs.items()}, args.repeats)


def compare(cases, configs: dict, repeats: int) -> list[float]:
    """Print one row per (reliability index, regime, estimator) in ``cases``: the median seconds
    of the two ``configs`` (name → context-manager factory), their ratio and the largest endpoint
    difference. Returns the ratios second/first."""
    first, second = configs
    print(f"{'case':<44} {first + ' s':>12} {second + ' s':>12} {'ratio':>7} {'max diff':>9}")
    ratios = []
    for index, regime, estimator in cases:
        case = in_regime(base_case(2026, index), regime)
        times: dict[str, list[float]] = {name: [] for name in configs}
        result = {}
        for _ in range(repeats):
            for name, configured in configs.items():
                with configured():
                    start = time.process_time()
                    result[name] = hulls(case, estimator)
                    times[name].append(time.process_time() - start)
        n = case.system.n
        lo, hi = result[second][:, :n], result[second][:, n:]
        unit = np.concatenate([hi - lo, hi - lo], axis=1) + data_scale(case.system, case.X0)
        diff = float(np.max(np.abs(result[second] - result[first]) / unit))
        t = {name: float(np.median(v)) for name, v in times.items()}
        ratios.append(t[second] / t[first])
        print(f"{case.name + ' ' + estimator:<44} {t[first]:12.2f} {t[second]:12.2f} "
              f"{ratios[-1]:7.3f} {diff:9.1e}", flush=True)
    print(f"\nmedian ratio {second}/{first}: {np.median(ratios):.3f}")
    return ratios
