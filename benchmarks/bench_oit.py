"""Stability paper Table 1 side by side, and what the OIT-CZ interval hull costs by three methods.

Part 1 (the table): for n = p = m ∈ {10, 20, 30}, random observable systems, ⟦x_0⟧ = [−10, 10]ⁿ, the
OIT-CZ SMF (δ̄ = 3) and the classical filter with ``ss.CORA_GIRARD`` / ``ss.CORA_COMBASTEL`` run on the
same trajectories in one process (`paper_figures/stability_table1.measure`); printed: median CPU
seconds per step, "step only" and "step + certified interval hull", the ratios, the mean hull radius.

Part 2 (``--hull-methods``): the 2n support LPs of the OIT-CZ window, whose constraint matrix is the
same every step and whose right-hand side b is new, solved per step by
  * fresh  — ``Z.interval_hull(certified=True)`` on a new CZ (presolve, simplex, certificate);
  * kept   — `ParametricSupport` (what `oit_cz_filter(hulls=True)` uses): one HiGHS model per
             direction, the dual simplex method from its previous basis after the change of b, the
             weak-duality certificate from its row duals; with the mean simplex pivots per LP.

Part 3 (``--formulations``): why nothing else came near: the kept models' pivots against the same
LPs with the n free columns eliminated exactly (QR of their block; denser), and with the measurement
noises' columns (one entry each, not in G) folded into range rows b ± |a| h (half the columns), and
how often a direction's optimal basis repeats along time (what a basis cache would need).

Usage: python benchmarks/bench_oit.py [--runs 3] [--steps 30] [--hull-methods] [--formulations]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy loads OpenBLAS

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth import analysis  # noqa: E402
from setsmooth.filters._window import Window  # noqa: E402
from setsmooth.solvers import highs  # noqa: E402
from setsmooth.solvers.parametric import ParametricSupport  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "paper_figures"))
from stability_table1 import DIMENSIONS, PUBLISHED_RADIUS, PUBLISHED_TIME, measure  # noqa: E402


def table(runs: int, steps: int) -> None:
    print(f"Table 1: {runs} run(s) x {steps + 1} steps, CPU seconds per step (median over runs)")
    header = f"{'n':>3} {'filter':>10} {'step':>10} {'step+hull':>10} {'radius':>8} {'paper step':>11} {'paper r':>8}"
    print(header)
    rng = np.random.default_rng(2024)
    for i, n in enumerate(DIMENSIONS):
        results = [measure(rng, n, steps) for _ in range(runs)]
        med = {f: {key: statistics.median(r[f][key] for r in results) for key in ("step", "hull", "radius")}
               for f in ("girard", "combastel", "oit")}
        for f, m in med.items():
            print(f"{n:>3} {f:>10} {m['step']:>10.2e} {m['step'] + m['hull']:>10.2e} {m['radius']:>8.2f} "
                  f"{PUBLISHED_TIME[f][i]:>11.4f} {PUBLISHED_RADIUS[f][i]:>8.2f}")
        steady = statistics.median(r["oit"]["step_steady"] for r in results)
        g, o = med["girard"], med["oit"]
        print(f"    ratios girard/OIT: step only {g['step'] / o['step']:.0f}x (steady k >= 3: "
              f"{g['step'] / steady:.0f}x; paper {PUBLISHED_TIME['girard'][i] / PUBLISHED_TIME['oit'][i]:.0f}x), "
              f"step + hull {(g['step'] + g['hull']) / (o['step'] + o['hull']):.2f}x, radius "
              f"{g['radius'] / o['radius']:.2f}x (paper {PUBLISHED_RADIUS['girard'][i] / PUBLISHED_RADIUS['oit'][i]:.2f}x)")


def hull_methods(steps: int) -> None:
    print(f"\nInterval hull of the OIT-CZ window, {steps} steps, CPU ms per step (2n certified support LPs)")
    for n in DIMENSIONS:
        rng = np.random.default_rng(n)
        drawn = analysis.random_observable_system(rng, n, n, n)
        system = drawn.linear_system()
        X0 = ss.Box(-10.0 * np.ones(n), 10.0 * np.ones(n))
        _, ys = ss.simulate(system, X0, steps + 3, rng)
        window = Window(system, 3, np.eye(n))
        D = np.vstack([np.eye(n), -np.eye(n)])
        data = [window.data(ys, k, np.zeros(n), np.full(n, np.inf)) for k in range(3, steps + 4)]
        t = time.process_time()
        fresh = [window.estimate_from(*d).support_many(D, certified=True) for d in data]
        t_fresh = (time.process_time() - t) / len(data)
        engine = ParametricSupport(window.G, window.A, D, window.free(n)).session()
        pivots = []
        t = time.process_time()
        kept = []
        for d in data:
            kept.append(engine.values(*d))
            pivots.extend(model.getInfo().simplex_iteration_count for model in _highs_models(engine))
        t_kept = (time.process_time() - t) / len(data)
        print(f"n = {n}: fresh {1e3 * t_fresh:8.1f}   kept {1e3 * t_kept:8.1f} ({np.mean(pivots):.0f} pivots/LP; "
              f"max |kept - fresh| {np.max(np.abs(np.array(kept) - np.array(fresh))):.1e})")


def _highs_models(session) -> list:
    """The HiGHS models of a `WarmSession`'s sequence backends (`highs.DirectionModels`)."""
    return [model for state in session.states.values() for model in (state.models.models or [])]


def _windows(n: int, steps: int):
    rng = np.random.default_rng(n)
    drawn = analysis.random_observable_system(rng, n, n, n)
    system = drawn.linear_system()
    _, ys = ss.simulate(system, ss.Box(-10.0 * np.ones(n), 10.0 * np.ones(n)), steps + 3, rng)
    window = Window(system, 3, np.eye(n))
    return window, [window.data(ys, k, np.zeros(n), np.full(n, np.inf)) for k in range(3, steps + 4)]


class _RangeModels(highs.DirectionModels):
    """`highs.DirectionModels`, whose `solve` also takes row bounds lower ≤ Aξ ≤ upper in place of
    Aξ = b (``upper`` given): the same models, re-solved from their last bases through `highs.ladder`."""

    def solve(self, j: int, lower: np.ndarray, h: np.ndarray, upper: np.ndarray | None = None) -> None:
        if upper is None:
            super().solve(j, lower, h)
            return
        m, p = self.A.shape
        if self.models is None:
            cols = np.where(self.free, -np.inf, -h)
            self.models = [highs.lp_model(self.A, lower, upper, cols, -cols) for _ in self.Q]
            for model, q in zip(self.models, self.Q):
                model.changeColsCost(p, np.arange(p, dtype=np.int32), q)
        model = self.models[j]
        model.changeRowsBounds(m, self.rows, lower, upper)
        if self.fin.size:
            model.changeColsBounds(self.fin.size, self.fin, -h[self.fin], h[self.fin])
        highs.ladder(model, highs.SIMPLEX_TOLERANCES)


def formulations(steps: int) -> None:
    print(f"\nOIT-CZ window LPs, {steps} steps: kept models against the free columns eliminated and the "
          "noise columns as range rows (CPU ms per step in HiGHS, pivots per LP), and repeated optimal bases")
    for n in DIMENSIONS:
        window, data = _windows(n, steps)
        A = window.A.toarray() if sp.issparse(window.A) else np.asarray(window.A)
        free = window.free(n)
        F, R = np.flatnonzero(free), np.flatnonzero(~free)
        Q, Rf = np.linalg.qr(A[:, F], mode="complete")
        Q1, Q2, Rt = Q[:, :F.size], Q[:, F.size:], Rf[:F.size]
        A_red = Q2.T @ A[:, R]
        objectives = -(np.vstack([np.eye(n), -np.eye(n)]) @ np.asarray(window.G))
        reduced = objectives[:, R] - (A[:, R].T @ (Q1 @ np.linalg.solve(Rt.T, objectives[:, F].T))).T
        # Columns with one entry and no generator (the noises v_j of the measurement rows) as range rows.
        single = np.flatnonzero((np.count_nonzero(A, axis=0) == 1) & ~np.any(window.G, axis=0) & ~free)
        rows_of, others = np.argmax(A[:, single] != 0, axis=0), np.setdiff1d(np.arange(A.shape[1]), single)

        def spread(h: np.ndarray) -> np.ndarray:  # Σ |a| h of each row's noise columns
            return np.bincount(rows_of, np.abs(A[rows_of, single]) * h[single], A.shape[0])

        forms = {"kept": (sp.csc_matrix(A), objectives, free, lambda b, h: (b, None, h)),
                 "eliminated": (sp.csc_matrix(A_red), reduced, np.zeros(R.size, bool),
                                lambda b, h: (Q2.T @ b, None, h[R])),
                 "range rows": (sp.csc_matrix(A[:, others]), objectives[:, others], free[others],
                                lambda b, h: (b - spread(h), b + spread(h), h[others]))}
        line = [f"n = {n}:"]
        for name, (M, costs, free_cols, program) in forms.items():
            models = _RangeModels(M, costs, free_cols)
            seconds, pivots, seen, repeats = 0.0, 0, [set() for _ in costs], 0
            for _, b, h in data:
                lower, upper, hh = program(b, h)
                for j in range(len(costs)):
                    t = time.process_time()
                    models.solve(j, lower, hh, upper)
                    seconds += time.process_time() - t
                    model = models.models[j]
                    pivots += model.getInfo().simplex_iteration_count
                    basis = model.getBasis()
                    key = (tuple(int(x) for x in basis.col_status), tuple(int(x) for x in basis.row_status))
                    repeats += key in seen[j]
                    seen[j].add(key)
            lps = len(data) * len(costs)
            line.append(f"{name} {M.shape[0]}x{M.shape[1]} nnz {M.nnz}: {1e3 * seconds / len(data):.1f} ms, "
                        f"{pivots / lps:.1f} pivots/LP, {repeats} of {lps} bases seen before;")
        print("  ".join(line))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--steps", type=int, default=30, help="T (k = 0..T)")
    parser.add_argument("--hull-methods", action="store_true")
    parser.add_argument("--formulations", action="store_true")
    parser.add_argument("--no-table", action="store_true", help="skip Part 1")
    args = parser.parse_args()
    if not args.no_table:
        table(args.runs, args.steps)
    if args.hull_methods:
        hull_methods(args.steps)
    if args.formulations:
        formulations(args.steps)


if __name__ == "__main__":
    main()
