"""The CZ interval hull against a direct Clarabel solve of the same LPs, side by side in one run.

For random feasible CZs Z(G, c, A, b) with unit factor bounds (sizes (n, ng, nc)), alternating on the
same sets:

  hull      ``Z.interval_hull(certified=...)`` on a fresh ConstrainedZonotope (presolve, solver
            set-up, the policy's attempts, the certificate bracket and its escalations included)
  direct    the same 2n LPs max ±e_iᵀ(Gξ + c) s.t. Aξ = b, |ξ| ≤ 1 written straight into one
            Clarabel instance (objective updated per direction): no presolve, no check, no bound

Prints the median process CPU time of each, their ratio per size, and the largest difference of
the hull endpoints relative to the box width (both must agree to solver accuracy).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_hull_vs_direct.py [--large] [--plain]
"""

from __future__ import annotations

import argparse
import time

import clarabel
import numpy as np
import scipy.sparse as sp

import setsmooth as ss

SIZES = {"S": (2, 20, 8), "M": (10, 100, 40), "L": (30, 300, 120)}


def random_cz(rng: np.random.Generator, n: int, ng: int, nc: int) -> dict:
    G = rng.standard_normal((n, ng))
    A = rng.standard_normal((nc, ng))
    xi = rng.uniform(-0.8, 0.8, ng)
    return dict(G=G, c=rng.standard_normal(n), A=A, b=A @ xi)


def direct(data: dict) -> tuple[np.ndarray, np.ndarray]:
    """The 2n LPs in one Clarabel instance, objective replaced per direction."""
    G, c, A, b = data["G"], data["c"], data["A"], data["b"]
    nc, ng = A.shape
    M = sp.vstack([sp.csc_matrix(A), sp.identity(ng), -sp.identity(ng)], format="csc")
    rhs = np.concatenate([b, np.ones(2 * ng)])
    cones = [clarabel.ZeroConeT(nc), clarabel.NonnegativeConeT(2 * ng)]
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solver = clarabel.DefaultSolver(sp.csc_matrix((ng, ng)), np.zeros(ng), M, rhs, cones,
                                    settings)
    n = G.shape[0]
    values = np.empty(2 * n)
    for i, d in enumerate(np.vstack([np.eye(n), -np.eye(n)])):
        solver.update(q=-(G.T @ d))
        sol = solver.solve()
        values[i] = d @ c + (G.T @ d) @ np.asarray(sol.x)
    return -values[n:], values[:n]


def library(data: dict, certified: bool) -> tuple[np.ndarray, np.ndarray]:
    Z = ss.ConstrainedZonotope(data["G"], data["c"], A=data["A"], b=data["b"])
    H = Z.interval_hull(certified=certified)
    return H.lo, H.hi


def cpu(fn, *args) -> tuple[float, tuple]:
    start = time.process_time()
    out = fn(*args)
    return time.process_time() - start, out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--large", action="store_true", help="add L = (30, 300, 120)")
    ap.add_argument("--plain", action="store_true", help="certified=False (default: certified)")
    ap.add_argument("--sets", type=int, default=15, help="random sets per size (default 15)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    names = ["S", "M"] + (["L"] if args.large else [])
    print(f"setsmooth {ss.__version__}; interval_hull(certified={not args.plain}) on fresh sets;"
          f" {args.sets} sets per size, process CPU time, medians")
    print(f"{'size':4} {'(n, ng, nc)':16} {'hull ms':>9} {'direct ms':>10} {'ratio':>7} "
          f"{'max |Δ|/width':>14}")
    for name in names:
        hull_t, direct_t, err = [], [], 0.0
        sets = [random_cz(rng, *SIZES[name]) for _ in range(args.sets)]
        library(sets[0], not args.plain)  # imports and first-use set-up out of the timing
        for data in sets:
            t1, (lo1, hi1) = cpu(library, data, not args.plain)
            t2, (lo2, hi2) = cpu(direct, data)
            hull_t.append(t1)
            direct_t.append(t2)
            width = np.maximum(hi2 - lo2, 1e-12)
            err = max(err, float(np.max(np.maximum(np.abs(lo1 - lo2), np.abs(hi1 - hi2)) / width)))
        h, d = np.median(hull_t) * 1e3, np.median(direct_t) * 1e3
        ratios = np.array(hull_t) / np.array(direct_t)
        print(f"{name:4} {str(SIZES[name]):16} {h:9.2f} {d:10.2f} {np.median(ratios):7.2f} "
              f"{err:14.1e}")


if __name__ == "__main__":
    main()
