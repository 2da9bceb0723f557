"""Support values of many constrained zonotopes over one factor set, solved a direction at a time.

The smoothed ranges of a data set are the projections x_k of one trajectory set: 601 programs at
T = 600 that differ only in G (which state they read), over one presolved factor set. Solved set by
set, each set's first direction starts from the program's feasible basis (a batch is one support
call, `warm_simplex`), and the maximizer of x_k along e_j is found some 24 pivots away on average.
Here every direction is a *chain*: e_j at k = 0, 1, …, T, each LP warm-started from the optimum of
the same direction one step earlier, whose trajectory differs from the new one near k only (8.4
pivots on average at T = 600). Each chain is a `Batch` with a simplex model of its own, starting
from the program's feasible basis; the chains advance in step, a set at a time, and each set's
certificates and brackets are checked as `CZProgram.support` checks them (vectorized over its
directions) before the next set is solved, so only one set's factors and multipliers are held.

A chain's answers are a function of the programs and its direction alone, so the chains of a step
can run in threads with the same answers, bit for bit. They agree with each set's own
`CZProgram.support` to the accuracy its check accepts (`tolerances.SUPPORT_GAP_TOL` of the width),
not bit for bit: a degenerate LP's optimal vertex depends on where the simplex method starts. The
certified values are weak-duality bounds either way.
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
                    ) -> list[tuple[np.ndarray, np.ndarray | None]] | None:
    """Every program's support values and certified bounds (`CZProgram.support_and_bounds`, or
    `CZProgram.support` with ``certified=True``) from one chain of solves per direction.

    Parameters
    ----------
    programs : list of CZProgram
        Programs over one `FactorConstraints` (``program.factors`` the same object).
    D : ndarray, shape (k, n)
        The directions, the same for every program.
    certified : bool or None
        True: every bound must exist (`SolverError` otherwise), and the last attempt's answer is
        taken where none settles; False or None: as `CZProgram.support_and_bounds`.
    tick : callable, optional
        Called with k after each program's k objectives are solved (a progress bar's ``update``).
    workers : int
        Threads that share the k chains' solves of each step; the answers are the same, bit for
        bit, for every count.

    Returns
    -------
    list of (values, bounds) or None
        Per program, the solver's values and the certified bounds (shape (k,) each; bounds None
        where no sound bound exists, as in `CZProgram.support_and_bounds`). None when the factor
        set is empty or infeasible: the caller asks each program alone, which settles what an
        empty stored set means (`ConstrainedZonotope._support`).

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
    # One chain per direction, each a batch with its own warm model (made here, in this thread).
    # A chain lists no objectives ahead: they are made a program at a time (O(T) memory), and a
    # chain is never one block LP.
    chains = [Batch(np.zeros((0, programs[0].ng)), own_model=True) for _ in range(D.shape[0])]
    for chain in chains:
        chain.model(factors.presolved)
    pool = ThreadPoolExecutor(max_workers=workers) if workers > 1 else None
    out = []
    try:
        # The chains advance in step, a program at a time, so that only one program's objectives,
        # factors and multipliers are held (O(T) memory, not O(T²)).
        for p in programs:
            objective = p._objectives(D)
            solved = _step(p, objective, chains, must, pool)
            if solved is None:
                return None
            if tick is not None:
                tick(len(chains))
            (values, _, _, _), bounds = p._verified(D, p._collected(D, objective[0], *solved), must)
            out.append((values, bounds))
    finally:
        if pool is not None:
            pool.shutdown()
    return out


def _step(p: CZProgram, objective: tuple, chains: list[Batch], must: bool,
          pool: ThreadPoolExecutor | None) -> tuple[np.ndarray, np.ndarray] | None:
    """Program ``p``'s objective j solved on chain j, for every j (in the pool's threads if any):
    its factors and multipliers, shapes (k, ng) and (k, nc); None when the factor set is
    infeasible."""
    GtD, magnitude, purpose = objective
    k = len(chains)
    xi, lam = np.full((k, p.ng), np.nan), np.full((k, p.nc), np.nan)

    def solve(j: int) -> bool:
        return p._maximize(GtD[j], magnitude[j], must, True, purpose, chains[j], xi[j], lam[j])

    settled = list(pool.map(solve, range(k))) if pool is not None else [solve(j) for j in range(k)]
    return (xi, lam) if all(settled) else None
