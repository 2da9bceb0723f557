"""Interval hulls of constrained zonotopes: the fast path against Clarabel, CVXPY and ZonoOpt.

For random feasible CZs Z(G, c, A, b) (factor bounds 1) this times ``interval_hull()``, i.e. the 2n
support functions h_Z(±e_i), side by side in one run:

  fast          ``Z.interval_hull()`` on a fresh CZ per repeat, so assembling the LP and setting up
                Clarabel are counted; "warm" repeats the query on the same object
  clarabel      Clarabel's own time for the fast path's 2n LPs (``Z._program.last_solve_time``):
                the solve_time it reports for the first, set-up included, plus the duration of
                each re-solve call on the same instance (whose reported solve_time re-counts the
                set-up)
  generic       ``Z.interval_hull(path="generic")`` through CVXPY: "cold" on a fresh object (CVXPY
                compiles the problem once), "warm" re-solving the compiled problem
  zonoopt       ZonoOpt's ``ConZono.bounding_box()`` at its default settings, when ``zonoopt`` is
                installed (``pip install zonoopt``; not a setsmooth dependency)

and the closed-form interval hull of a zonotope against an LP-based hull of the same zonotope.
Times are medians over the repeats.

    python benchmarks/bench_support.py            # (2, 20, 8) and (10, 100, 40), well under a minute
    python benchmarks/bench_support.py --full     # adds (30, 300, 120) and (10, 1000, 400): ~20 min
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from importlib.metadata import version

import numpy as np
import scipy.sparse as sp

import setsmooth as ss

try:
    import zonoopt
except ImportError:  # optional comparison
    zonoopt = None

#: (n, ng, nc) and default repeats; each (10, 1000, 400) hull takes about a minute per path.
SMALL = {(2, 20, 8): 15, (10, 100, 40): 15}
LARGE = {(30, 300, 120): 5, (10, 1000, 400): 3}


def random_cz(rng: np.random.Generator, n: int, ng: int, nc: int):
    """(G, c, A, b) of a CZ with a relative interior: b = Aξ₀ for a ξ₀ strictly inside the unit box."""
    G = rng.standard_normal((n, ng))
    c = rng.standard_normal(n)
    A = rng.standard_normal((nc, ng))
    b = A @ rng.uniform(-0.5, 0.5, ng)
    return G, c, A, b


def timed(fn):
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def box_error(lo, hi, box) -> float:
    return float(max(np.abs(lo - box.lo).max(), np.abs(hi - box.hi).max()))


@dataclass
class Row:
    size: tuple[int, int, int]
    repeats: int
    fast: float
    fast_warm: float
    clarabel: float
    generic_cold: float
    generic_warm: float
    generic_error: float
    zonoopt: float = float("nan")
    zonoopt_error: float = float("nan")


def measure(size, repeats: int, rng: np.random.Generator) -> Row:
    """Each path is timed in its own loop of ``repeats`` calls on the same set, after one untimed
    call on another fresh object of the same set (small sizes only)."""
    G, c, A, b = random_cz(rng, *size)
    fast, fast_warm, clarabel, cold, warm, zono = ([] for _ in range(6))
    if size in SMALL:  # warm the interpreter's and libraries' first-call paths (not the sets)
        ss.ConstrainedZonotope(G, c, A, b).interval_hull()
        ss.ConstrainedZonotope(G, c, A, b).interval_hull(path="generic")
    for _ in range(repeats):
        Z = ss.ConstrainedZonotope(G, c, A, b)  # fresh: nothing assembled, set up or cached yet
        seconds, ours = timed(Z.interval_hull)
        fast.append(seconds)
        clarabel.append(Z._program.last_solve_time)
        fast_warm.append(timed(Z.interval_hull)[0])
    for _ in range(repeats):
        Z = ss.ConstrainedZonotope(G, c, A, b)
        seconds, generic = timed(lambda: Z.interval_hull(path="generic"))
        cold.append(seconds)
        warm.append(timed(lambda: Z.interval_hull(path="generic"))[0])
    row = Row(size, repeats, *(float(np.median(t)) for t in (fast, fast_warm, clarabel, cold, warm)),
              generic_error=box_error(generic.lo, generic.hi, ours))
    if zonoopt is not None:
        for _ in range(repeats):
            theirs = zonoopt.ConZono(sp.csc_matrix(G), c, sp.csc_matrix(A), b)
            seconds, box = timed(theirs.bounding_box)
            zono.append(seconds)
        row.zonoopt = float(np.median(zono))
        row.zonoopt_error = box_error(np.asarray(box.lower()), np.asarray(box.upper()), ours)
    return row


def closed_form_vs_lp(rng: np.random.Generator, n: int = 10, ng: int = 100, repeats: int = 15):
    """Median seconds of Zonotope.interval_hull() and of the generic LP hull of the same zonotope."""
    Z = ss.Zonotope(rng.standard_normal((n, ng)), rng.standard_normal(n))
    loops = 2000
    closed = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(loops):
            box = Z.interval_hull()
        closed.append((time.perf_counter() - start) / loops)
    Z.interval_hull(path="generic")  # compile once: time the LP re-solves only
    lp = [timed(lambda: Z.interval_hull(path="generic")) for _ in range(max(3, repeats // 3))]
    error = box_error(lp[-1][1].lo, lp[-1][1].hi, box)
    return float(np.median(closed)), float(np.median([t for t, _ in lp])), error


def ms(seconds: float) -> str:
    return "—" if np.isnan(seconds) else f"{1e3 * seconds:.3g}"


def ratio(a: float, b: float) -> str:
    return "—" if np.isnan(a) or np.isnan(b) else f"{a / b:.2f}"


def print_tables(rows: list[Row]) -> None:
    print("Wall time of interval_hull() in ms (median); fast = fresh ConstrainedZonotope per repeat,")
    print("so LP assembly and Clarabel set-up are included; clarabel = Clarabel's own time in it.\n")
    head = (f"{'(n, ng, nc)':<16}{'reps':>5}{'fast':>10}{'fast warm':>11}{'clarabel':>10}"
            f"{'generic cold':>14}{'generic warm':>14}{'zonoopt':>10}")
    print(head)
    print("-" * len(head))
    for r in rows:
        print(f"{str(r.size):<16}{r.repeats:>5}{ms(r.fast):>10}{ms(r.fast_warm):>11}{ms(r.clarabel):>10}"
              f"{ms(r.generic_cold):>14}{ms(r.generic_warm):>14}{ms(r.zonoopt):>10}")
    print("\nRatios and agreement (max |Δ| over the box corners, against the fast path's box)\n")
    head = (f"{'(n, ng, nc)':<16}{'fast/clarabel':>15}{'generic cold/fast':>19}"
            f"{'generic warm/fast':>19}{'zonoopt/fast':>14}{'|Δ| generic':>13}{'|Δ| zonoopt':>13}")
    print(head)
    print("-" * len(head))
    for r in rows:
        print(f"{str(r.size):<16}{ratio(r.fast, r.clarabel):>15}{ratio(r.generic_cold, r.fast):>19}"
              f"{ratio(r.generic_warm, r.fast):>19}{ratio(r.zonoopt, r.fast):>14}"
              f"{r.generic_error:>13.1e}{r.zonoopt_error:>13.1e}")
    if zonoopt is None:
        print("\n(zonoopt is not installed: `pip install zonoopt` to add its column)")
    else:
        print("\nZonoOpt runs ADMM at its default tolerances (eps_prim = 1e-3), so its box is only as close")
        print("as |Δ| zonoopt says and may lie inside the true interval hull.")


def check(label: str, ok: bool) -> None:
    print(f"  [{'met' if ok else 'MISSED'}] {label}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--full", action="store_true", help="add (30, 300, 120) and (10, 1000, 400)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random sets (default 0)")
    parser.add_argument("--repeats", type=int, default=None,
                        help="repeats per size (default 15, 15, 5, 3)")
    args = parser.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    sizes = {**SMALL, **LARGE} if args.full else SMALL
    rows = [measure(size, args.repeats or repeats, rng) for size, repeats in sizes.items()]
    print(f"setsmooth {ss.__version__}, clarabel {version('clarabel')}, cvxpy {version('cvxpy')}"
          + (f", zonoopt {version('zonoopt')}" if zonoopt else "") + f"; seed {args.seed}")
    print()
    print_tables(rows)

    closed, lp, error = closed_form_vs_lp(rng)
    print(f"\nZonotope (n, ng) = (10, 100): closed-form interval_hull {1e6 * closed:.3g} µs, "
          f"LP hull (generic path, compiled) {1e3 * lp:.3g} ms: {lp / closed:,.0f}× (|Δ| {error:.1e})")

    print("\nTargets")
    by_size = {r.size: r for r in rows}
    check("fast within 1.3× of Clarabel at (10, 100, 40)",
          by_size[(10, 100, 40)].fast <= 1.3 * by_size[(10, 100, 40)].clarabel)
    check("fast within 2× of Clarabel at (2, 20, 8)",
          by_size[(2, 20, 8)].fast <= 2 * by_size[(2, 20, 8)].clarabel)
    for r in rows:
        need = 1.5 if r.size in SMALL else 1.0
        check(f"fast ≥ {need}× faster than generic (warm re-solve) at {r.size}",
              r.generic_warm >= need * r.fast)
    check("zonotope closed form ≥ 1000× faster than an LP hull", lp >= 1000 * closed)


if __name__ == "__main__":
    main()
