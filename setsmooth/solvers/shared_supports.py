"""Support values of many constrained zonotopes over one factor set, solved a direction at a time.

The smoothed ranges of a data set are the projections x_k of one trajectory set: 601 programs at
T = 600 that differ only in G (which state they read), over one presolved factor set and one kept
simplex model. Solved set by set, each set's first direction starts from the program's feasible
basis (a batch is one support call, `warm_simplex`), and the maximizer of x_k along e_j is found
some 24 pivots away on average. Solved *direction by direction across the sets* — a chain per
direction, e_j at k = 0, 1, …, T — each LP starts from the optimum of the same direction one step
earlier, whose trajectory differs from the new one near k only (8.4 pivots on average at T = 600).
The sets' certificates and brackets are then checked set by set as `CZProgram.support` checks them
(vectorized over a set's directions), from the same solves.

Each chain is one `Batch`: its answers are a function of the programs and the direction alone, the
same in every thread and whatever was queried before, so the chains can run in threads. They agree
with each set's own `CZProgram.support` to the accuracy its check accepts
(`tolerances.SUPPORT_GAP_TOL` of the width), not bit for bit: a degenerate LP's optimal vertex
depends on where the simplex method starts. The certified values are weak-duality bounds either way.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import numpy as np

from .cz_program import CZProgram
from .warm_simplex import Batch

__all__ = ["shared_supports"]


def shared_supports(programs: list[CZProgram], D: np.ndarray, certified: bool | None,
                    tick: Callable[[int], object] | None = None, workers: int = 1
                    ) -> list[np.ndarray] | None:
    """``[program.support(D, certified)[0] for program in programs]`` from one chain of solves per
    direction.

    Parameters
    ----------
    programs : list of CZProgram
        Programs over one `FactorConstraints` (``program.factors`` the same object).
    D : ndarray, shape (k, n)
        The directions, the same for every program.
    certified : bool or None
        As in `CZProgram.support`.
    tick : callable, optional
        Called with 1 after each program's objective is solved (a progress bar's ``update``).
    workers : int
        Threads that share the k chains (each thread builds its own solver instances,
        `solvers.instances`); the answers are the same, bit for bit, for every count.

    Returns
    -------
    list of ndarray, shape (k,) each, or None
        None when the factor set is empty or infeasible: the caller asks each program alone, which
        settles what an empty stored set means (`ConstrainedZonotope._support`).

    Raises
    ------
    ValueError
        When the programs do not share one factor set.
    SolverError
        As `CZProgram.support`.
    """
    if not programs:
        return []
    factors = programs[0].factors
    if any(p.factors is not factors for p in programs):
        raise ValueError("programs must share one factor set (program.factors the same object)")
    if factors._empty:
        return None
    must = certified is True
    objectives = [p._objectives(D) for p in programs]

    def chain(j: int):
        return _chain(programs, objectives, j, must, tick)

    if workers > 1:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            chains = list(pool.map(chain, range(D.shape[0])))
    else:
        chains = [chain(j) for j in range(D.shape[0])]
    if any(c is None for c in chains):
        return None
    out = []
    for i, (p, (GtD, _, _)) in enumerate(zip(programs, objectives)):
        xi = np.stack([c[0][i] for c in chains])
        lam = np.stack([c[1][i] for c in chains])
        (values, _, _, _), bounds = p._verified(D, p._collected(D, GtD, xi, lam), must)
        out.append(values if certified is False or bounds is None else bounds)
    return out


def _chain(programs: list[CZProgram], objectives: list, j: int, must: bool, tick
           ) -> tuple[np.ndarray, np.ndarray] | None:
    """Direction j of every program, in order, as one batch: (factors, multipliers) of shape
    (programs, ng) and (programs, nc), or None when the factor set is infeasible."""
    p0 = programs[0]
    batch = Batch(np.stack([GtD[j] for GtD, _, _ in objectives]))
    xi = np.full((len(programs), p0.ng), np.nan)
    lam = np.full((len(programs), p0.nc), np.nan)
    for i, (p, (GtD, magnitude, purpose)) in enumerate(zip(programs, objectives)):
        if not p._maximize(GtD[j], magnitude[j], must, True, purpose, batch, xi[i], lam[i]):
            return None
        if tick is not None:
            tick(1)
    return xi, lam
