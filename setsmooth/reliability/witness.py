"""The witness check: a certified support value must be at least dᵀx for every feasible x.

For the trajectory smoother's sets ⟦x_k | y_0:T⟧ on a case, along the axes and random directions d, the
HiGHS oracle gives a maximizer of dᵀx_k over the trajectory LP, polished onto the equalities (residual
~1e-15 on unit rows): a feasible witness x. A certified value h with dᵀx − h > ``WITNESS_TOL · u`` +
rounding, u = ‖d‖₁ (σ + width of the exact hull at k), is unsound: the issue's case was
5.287455961e−1 < 5.287456413e−1 (a gap of 9e-8 relative).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import setsmooth as ss

from .oracle import TrajectoryOracle, data_scale
from .random_systems import Case

WITNESS_TOL = 1e-10
_EPS64 = 64 * np.finfo(float).eps


@dataclass
class WitnessOutcome:
    name: str
    checked: int = 0
    violations: int = 0
    worst: float = 0.0         # largest (dᵀx − h) / u
    example: str = ""
    error: str | None = None   # an exception raised while smoothing or certifying


def witness_check(case: Case, n_random: int = 3, seed: int = 0, method: str = "trajectory") -> WitnessOutcome:
    """Compare certified supports of the smoothed sets with the oracle's feasible witnesses."""
    out = WitnessOutcome(case.name)
    oracle = TrajectoryOracle(case.system, case.X0, case.ys)
    lo, hi = oracle.smoothed_hulls()
    sigma = data_scale(case.system, case.X0)
    n = case.system.n
    rng = np.random.default_rng(seed)
    directions, certified = [], []
    try:
        sets = ss.optimal_smoother(case.system, case.X0, case.ys, method=method)
        for S in sets:
            eye = np.eye(n)
            D = np.vstack([eye, -eye, rng.normal(size=(n_random, n))])
            directions.append(D)
            certified.append(S.support_many(D, certified=True))
    except Exception as exc:  # noqa: BLE001 - reported as a finding
        out.error = f"{type(exc).__name__}: {str(exc)[:160]}"
    # Oracle failures are not the library's: they propagate (OracleError).
    for k, (D, cert) in enumerate(zip(directions, certified)):
        for d, h in zip(D, cert):
            _, x, _ = oracle.support(k, d, point=True)
            value = float(d @ x)
            u = np.abs(d).sum() * (sigma + float((hi[k] - lo[k]).max()))
            fp = _EPS64 * np.abs(d) @ np.abs(x)
            out.checked += 1
            gap = value - h
            if gap > WITNESS_TOL * u + fp:
                out.violations += 1
                if gap / u > out.worst:
                    out.worst = gap / u
                    out.example = f"k={k}: certified {h:.12g} < witness dᵀx = {value:.12g}"
    return out
