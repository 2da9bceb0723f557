"""The replay corpus: one file per incident of the reliability runs, replayed against its stored
exact answer.

Each file of ``cases/`` names one set of one estimator on one reliability case
(`random_systems.base_case`, `random_systems.in_regime`) and stores the exact interval hull of that
set, computed once by the trajectory LP oracle (`oracle.TrajectoryOracle`), with the incident's
history. `replay` recomputes the set with the library and returns its plain and certified hulls;
the test (`test_replay.py`) holds them to the stored answer: plain within 1e-6 of the width,
certified enclosing it to 1e-9 and within 1e-6.

Record a new incident (computes the oracle's answer; run from the repository's root):

    PYTHONPATH=. python -m tests.reliability.replay 184 scale1e+03 recursion 17 "what happened"

(``all`` instead of the step stores every set of the estimator.)
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import setsmooth as ss

from setsmooth.reliability.oracle import TrajectoryOracle, data_scale
from setsmooth.reliability.random_systems import base_case, in_regime

CASES = Path(__file__).parent / "cases"
ESTIMATORS = ("filter", "trajectory", "recursion")


@dataclass(frozen=True)
class Incident:
    """One corpus entry: the set ``estimator``[k] of reliability case ``index`` in ``regime`` (every
    set of the estimator when ``k`` is None; ``lo``, ``hi`` then have one row per set)."""

    index: int
    regime: str
    estimator: str
    k: int | None
    history: str
    lo: np.ndarray
    hi: np.ndarray
    sigma: float
    seed: int = 2026
    T_range: tuple[int, int] = (10, 40)
    n_range: tuple[int, int] = (2, 6)
    cap_singular_radius: bool = True
    noise: str | None = None  # `base_case`'s noise type (None: its box/CZ alternation)

    @property
    def name(self) -> str:
        at = "all" if self.k is None else f"k{self.k}"
        return f"case{self.index:03d}_{self.regime}_{self.estimator}_{at}"

    @property
    def unit(self) -> np.ndarray:
        """The hull's width plus the noise scale: what 1e-6 is relative to."""
        return self.hi - self.lo + self.sigma

    def case(self):
        return in_regime(base_case(self.seed, self.index, T_range=self.T_range,
                                   n_range=self.n_range, noise=self.noise,
                                   cap_singular_radius=self.cap_singular_radius), self.regime)


def load(path: Path) -> Incident:
    data = json.loads(path.read_text())
    return Incident(index=data["index"], regime=data["regime"], estimator=data["estimator"],
                    k=data["k"], history=data["history"], lo=np.array(data["lo"], dtype=float),
                    hi=np.array(data["hi"], dtype=float), sigma=float(data["sigma"]),
                    seed=data["seed"], T_range=tuple(data["T_range"]),
                    n_range=tuple(data["n_range"]),
                    cap_singular_radius=data.get("cap_singular_radius", True),
                    noise=data.get("noise"))


def corpus() -> list[Path]:
    return sorted(CASES.glob("*.json"))


def estimate(case, estimator: str):
    """The library's sets of ``estimator`` on ``case``."""
    if estimator == "filter":
        return ss.classical_filter(case.system, case.X0, case.ys)
    return ss.optimal_smoother(case.system, case.X0, case.ys, method=estimator)


def replay(incident: Incident) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(plain lo, plain hi, certified lo, certified hi) of the incident's set (or every set, rows),
    computed by the library."""
    sets = estimate(incident.case(), incident.estimator)
    chosen = list(sets) if incident.k is None else [sets[incident.k]]
    plain = [S.interval_hull(certified=False) for S in chosen]
    cert = [S.interval_hull(certified=True) for S in chosen]
    out = [np.array([getattr(H, side) for H in hulls]) for hulls in (plain, cert)
           for side in ("lo", "hi")]
    if incident.k is not None:
        out = [a[0] for a in out]
    return tuple(out)


def record(index: int, regime: str, estimator: str, k: int | None, history: str,
           **case_kwargs) -> Path:
    """Compute the exact hull (every set's when ``k`` is None) by the oracle and write the file."""
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator must be one of {ESTIMATORS}, got {estimator!r}")
    draft = Incident(index, regime, estimator, k, history, np.zeros(0), np.zeros(0), 0.0,
                     **case_kwargs)
    case = draft.case()
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    steps = range(case.T + 1) if k is None else [k]
    hulls = [oracle.hull(j, upto=j if estimator == "filter" else None) for j in steps]
    lo, hi = np.array([h[0] for h in hulls]), np.array([h[1] for h in hulls])
    if k is not None:
        lo, hi = lo[0], hi[0]
    data = {"index": index, "regime": regime, "estimator": estimator, "k": k, "history": history,
            "seed": draft.seed, "T_range": list(draft.T_range), "n_range": list(draft.n_range),
            "cap_singular_radius": draft.cap_singular_radius, "noise": draft.noise,
            "sigma": data_scale(case.system, case.X0), "lo": lo.tolist(), "hi": hi.tolist()}
    CASES.mkdir(exist_ok=True)
    path = CASES / f"{draft.name}.json"
    path.write_text(json.dumps(data, indent=1) + "\n")
    return path


if __name__ == "__main__":
    index, regime, estimator, k, history = sys.argv[1:6]
    print(record(int(index), regime, estimator, None if k == "all" else int(k), history))
