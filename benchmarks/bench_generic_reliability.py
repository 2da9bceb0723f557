"""Counts for issue 7 on the generic path and threads: run `python benchmarks/bench_generic_reliability.py`.

Prints, side by side for the generic ('generic') and fast ('auto') paths:

* thread safety: one CZ queried in 80 directions from 4 threads, values differing from the serial
  ones or raising;
* 1e±12 rescalings: 60 random CZs re-represented by scalings of rows, factors or coordinates
  (20 each), 6 directions each, checked against HiGHS on the well-scaled form; a case is "wrong" when
  a finite value is off by more than 1e-6 of the set's scale (or infinite), "refused" when it raises
  SolverError only;
* nearly empty H-polytope intersections, gaps ±3e-9 … ±3e-5: SolverErrors, and verdicts differing
  from the exact one where the gap exceeds twice the emptiness tolerance.
"""

from __future__ import annotations

import pickle
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from scipy.optimize import linprog

import setsmooth as ss
from setsmooth import tolerances as tol
from setsmooth.reliability.rescaling import rewrite

warnings.filterwarnings("ignore")


def threads(path: str) -> tuple[int, int]:
    rng = np.random.default_rng(0)
    G, A = rng.standard_normal((3, 8)), rng.standard_normal((3, 8))
    Z = ss.ConstrainedZonotope(G, rng.uniform(-1, 1, 3), A=A, b=A @ rng.uniform(-0.5, 0.5, 8))
    D = rng.standard_normal((80, 3))
    serial = np.array([Z.support(d, path=path) for d in D])
    fresh = pickle.loads(pickle.dumps(Z))

    def query(d):
        try:
            return fresh.support(d, path=path)
        except Exception:  # noqa: BLE001 — counted
            return None

    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(query, D))
    errors = sum(g is None for g in got)
    wrong = sum(g is not None and abs(g - s) > 1e-6 * (1 + abs(s)) for g, s in zip(got, serial))
    return wrong, errors


def highs(G, c, A, b, h, d):
    norm = np.linalg.norm(d)
    res = linprog(-(G.T @ (d / norm)), A_eq=A, b_eq=b, bounds=list(zip(-h, h)), method="highs")
    return (-res.fun + (d / norm) @ c) * norm


def rescaled(path: str, k: float = 12) -> tuple[int, int]:
    rng = np.random.default_rng(7)
    wrong = refused = 0
    for s in range(20):
        n, ng, nc = 2 + s % 3, 5 + s % 4, 1 + s % 3
        G, c, A = rng.standard_normal((n, ng)), rng.standard_normal(n), rng.standard_normal((nc, ng))
        b, h = A @ rng.uniform(-0.5, 0.5, ng), np.ones(ng)
        D = rng.standard_normal((6, n))
        for kind in ("rows", "factors", "coordinates"):
            Z, sig = rewrite(rng, kind, k, G, c, A, b, h)
            bad = raised = False
            for d in D:
                exact = highs(G, c, A, b, h, sig * d)
                scale = np.abs(sig * d) @ (np.abs(G).sum(axis=1) + np.abs(c))
                try:
                    v = Z.support(d, path=path)
                except ss.SolverError:
                    raised = True
                    continue
                bad |= not abs(v - exact) <= 1e-6 * scale
            wrong += bad
            refused += raised and not bad
    return wrong, refused


def near_empty(path: str) -> tuple[int, int, int]:
    errors = wrong = cases = 0
    for gap in np.logspace(np.log10(3e-9), np.log10(3e-5), 13):
        for sign in (1, -1):
            square = ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), [1.0, 1.0, 0.0, 0.0])
            S = square & ss.HPolytope([[-1.0, 0.0]], [-(1.0 + sign * gap)])
            cases += 1
            try:
                verdict = S.is_empty(path=path)
            except ss.SolverError:
                errors += 1
                continue
            decided = sign < 0 or gap / 2 > 2 * tol.EMPTINESS_TOL
            wrong += decided and verdict != (sign > 0)
    return errors, wrong, cases


if __name__ == "__main__":
    print(f"{'measure':<52}{'generic':>10}{'auto':>10}")
    (gw, ge), (aw, ae) = threads("generic"), threads("auto")
    print(f"{'4 threads, 80 directions: wrong values':<52}{gw:>10}{aw:>10}")
    print(f"{'4 threads, 80 directions: errors':<52}{ge:>10}{ae:>10}")
    (gw, gr), (aw, ar) = rescaled("generic"), rescaled("auto")
    print(f"{'1e±12 rescaled CZs (60): silently wrong':<52}{gw:>10}{aw:>10}")
    print(f"{'1e±12 rescaled CZs (60): refused (SolverError only)':<52}{gr:>10}{ar:>10}")
    e, w, n = near_empty("auto")  # HPolytope: the generic path is its only path
    print(f"{f'nearly empty HPolytope ∩ HPolytope ({n}): SolverErrors':<52}{e:>10}{'-':>10}")
    print(f"{f'nearly empty HPolytope ∩ HPolytope ({n}): wrong verdicts':<52}{w:>10}{'-':>10}")
