"""Long horizons and custom sets (issue 8's targets): time and peak memory per case, medians.

Cases (full size / ``--quick`` size):

* ``filter31``: the smoothing paper's example (31) from X0 = [−5, 5]², `classical_filter` and the
  certified interval hull of every posterior, T = 100, 400, 800 (quick: 25, 50, 100). Reported: ms per
  step and the process's peak memory.
* ``smoother3``: the trajectory smoother of a 3-state system (`bench_smoothing.py`'s), T = 600
  (quick 150): build + every certified hull; ``smoother3x2`` the same with the hulls split over two
  threads (`SetEstimates.interval_hulls` with ``workers=2``).
* ``custom``: example (31)'s dynamics with an ℓ1-ball W and a V-polytope V, both given only by
  ``constraints(x)``, T = 50 (quick 10): filter + smoother + every interval hull (filter and smoother
  times also apart).
* ``triangle``: example (31)'s dynamics with B = I and the triangle CZ of
  ``examples/new_set_representation.py`` as W, T = 800 (quick 100): filter + every certified hull.
* ``crossover``: example (31)'s exact filter with certified hulls as posterior views and as the
  recursion's CZs, on the same data in one process (`classical_filter(..., form=...)`), T = 50, 100.
* ``fig3``: one Monte-Carlo run of the smoothing paper's Fig. 3 (``paper_figures/smoothing_fig3.py``,
  T = 50), median over repeats with different seeds.

Every (case, size, repeat) runs in a fresh subprocess, so peak memory (``ru_maxrss``, which includes the
≈ 150–250 MB of the imported libraries and the solvers' native memory) is the case's own. Times are
wall-clock (``time.perf_counter``) and CPU (``time.process_time``; the machine may be shared). A case
that raises is reported with its error, one that exceeds ``--timeout`` as a timeout.

Usage: python benchmarks/bench_long_horizon.py [--quick] [--repeats N] [--cases filter31,custom,...]
                                               [--checkout DIR] [--compare DIR] [--timeout S]

``--checkout DIR`` measures the library of another checkout (default: this one); ``--compare DIR``
measures both, alternating, and prints the ratios side by side.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

FULL = {"filter31": [100, 400, 800], "smoother3": [600], "smoother3x2": [600], "custom": [50],
        "triangle": [800], "fig3": [50],
        "crossover": [50, 100]}
QUICK = {"filter31": [25, 50, 100], "smoother3": [150], "smoother3x2": [150], "custom": [10],
         "triangle": [100], "fig3": [50],
         "crossover": [50]}


# -- the cases (run in the child process, with the measured checkout's setsmooth) ----------------------
def _example_31(B_identity_triangle: bool = False):
    import numpy as np

    import setsmooth as ss
    from setsmooth.papers.smoothing_examples import smoothing_example_31

    base = smoothing_example_31()
    if not B_identity_triangle:
        return base
    W = ss.ConstrainedZonotope(G=[[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], c=[0.0, 0.0],
                               A=[[1.0, 1.0, 1.0]], b=[1.0])
    return ss.LinearSystem(base.A_at(0), None, base.C_at(0), F=base.F_at(0), W=W, V=base.V)


def _custom_system():
    import setsmooth as ss
    from setsmooth.papers.smoothing_examples import smoothing_example_31
    from setsmooth.sets.constraint_only import L1Ball, VertexHull

    base = smoothing_example_31()
    V = VertexHull([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [0.0, 1.2]])
    return ss.LinearSystem(base.A_at(0), None, base.C_at(0), E=base.E_at(0), F=base.F_at(0),
                           W=L1Ball([0.0], 1.0), V=V)


def _filter_with_hulls(system, T: int, seed: int, certified: bool = True) -> dict:
    import numpy as np

    import setsmooth as ss

    X0 = ss.Box([-5.0, -5.0], [5.0, 5.0])
    _, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    posteriors = ss.classical_filter(system, X0, ys)
    hulls = [P.interval_hull(certified=certified) for P in posteriors]
    return {"steps": T + 1, "empty": sum(isinstance(h, ss.EmptySet) for h in hulls)}


def run_case(case: str, size: int, seed: int) -> dict:
    """One measurement; returns times, peak memory and what the case reports."""
    import numpy as np

    import setsmooth as ss
    # Load every module before the clock starts: a checkout whose `import setsmooth` is lazy would
    # otherwise pay its imports (CVXPY, SciPy) inside the first timed call.
    import setsmooth.filters  # noqa: F401
    import setsmooth.sets  # noqa: F401
    import setsmooth.smoothers  # noqa: F401
    import setsmooth.trajectories  # noqa: F401

    wall, cpu = time.perf_counter(), time.process_time()
    extra: dict = {}
    if case == "filter31":
        extra = _filter_with_hulls(_example_31(), size, seed)
    elif case == "triangle":
        extra = _filter_with_hulls(_example_31(B_identity_triangle=True), size, seed)
    elif case in ("smoother3", "smoother3x2"):
        A = np.array([[0.9, 0.2, 0.0], [-0.2, 0.9, 0.1], [0.0, 0.0, 0.95]])
        B = np.array([[0.1, 0.0], [0.0, 0.1], [0.05, 0.05]])
        C = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
        system = ss.LinearSystem(A, None, C, E=B, W=ss.Box([-1, -1], [1, 1]),
                                 V=ss.Box([-0.5, -0.5], [0.5, 0.5]))
        X0 = ss.Box(-np.ones(3), np.ones(3))
        _, ys = ss.simulate(system, X0, size, np.random.default_rng(seed))
        wall, cpu = time.perf_counter(), time.process_time()  # build + hulls only
        smoothed = ss.optimal_smoother(system, X0, ys, method="trajectory")
        workers = 2 if case == "smoother3x2" else 1
        if hasattr(smoothed, "interval_hulls"):
            smoothed.interval_hulls(certified=True, workers=workers)
        elif workers == 1:  # a checkout from before SetEstimates.interval_hulls
            [S.interval_hull(certified=True) for S in smoothed]
        else:
            raise RuntimeError("this checkout has no SetEstimates.interval_hulls(workers=...)")
        extra = {"steps": size + 1}
    elif case == "custom":
        system = _custom_system()
        X0 = ss.Box([-5.0, -5.0], [5.0, 5.0])
        xs, ys = ss.simulate(system, ss.Box([-1.0, -1.0], [1.0, 1.0]), size, np.random.default_rng(seed))
        wall, cpu = time.perf_counter(), time.process_time()
        posteriors = ss.classical_filter(system, X0, ys)
        filtered = [P.interval_hull() for P in posteriors]
        filter_s = time.perf_counter() - wall
        smoothed = [S.interval_hull() for S in ss.optimal_smoother(system, X0, ys)]
        inside = all(np.all(h.lo - 1e-6 <= x) and np.all(x <= h.hi + 1e-6)
                     for hulls in (filtered, smoothed) for h, x in zip(hulls, xs))
        extra = {"steps": size + 1, "filter_s": filter_s,
                 "smoother_s": time.perf_counter() - wall - filter_s, "true_states_inside": bool(inside)}
    elif case == "crossover":
        system, X0 = _example_31(), ss.Box([-5.0, -5.0], [5.0, 5.0])
        _, ys = ss.simulate(system, X0, size, np.random.default_rng(seed))
        times = {}
        for form in ("views", "recursion"):
            start = time.process_time()
            [P.interval_hull(certified=True) for P in ss.classical_filter(system, X0, ys, form=form)]
            times[form] = time.process_time() - start
        extra = {"steps": size + 1, "views_cpu_s": times["views"], "recursion_cpu_s": times["recursion"]}
    elif case == "fig3":
        figures = os.path.join(os.environ.get("BENCH_CHECKOUT", ROOT), "paper_figures")
        sys.path.insert(0, figures)
        import smoothing_fig3

        smoothing_fig3.trial(np.random.default_rng(seed + 1000))  # imports and first compilations
        wall, cpu = time.perf_counter(), time.process_time()
        smoothing_fig3.trial(np.random.default_rng(seed))
        extra = {"steps": size + 1}
    else:
        raise ValueError(f"unknown case {case!r}")
    out = {"wall_s": time.perf_counter() - wall, "cpu_s": time.process_time() - cpu, **extra}
    return out


def _peak_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux


def _child(case: str, size: int, seed: int) -> None:
    try:
        out = run_case(case, size, seed)
    except Exception as exc:  # reported in the table: a failure is a result of the benchmark
        out = {"error": f"{type(exc).__name__}: {exc}"[:120]}
    out["peak_mb"] = _peak_mb()
    print("RESULT " + json.dumps(out))


# -- the driver -------------------------------------------------------------------------------------------
#: issue 8's targets per (case, full size): what is asked, and what the summary shows of it.
TARGETS = {
    ("filter31", 800): ("completes, <= 40 ms per step, peak <= 500 MB",
                        lambda s: f"completes, {s['ms_step']:.1f} ms/step wall ({s['cpu_ms_step']:.1f} cpu), "
                                  f"peak {s['peak_mb']:.0f} MB"),
    ("smoother3", 600): ("build + all certified hulls <= 30 s",
                         lambda s: f"{s['wall_s']:.1f} s wall ({s['cpu_s']:.1f} s cpu)"),
    ("smoother3x2", 600): ("build + all certified hulls <= 30 s (2 threads)",
                           lambda s: f"{s['wall_s']:.1f} s wall ({s['cpu_s']:.1f} s cpu)"),
    ("custom", 50): ("filter + smoother + hulls <= 30 s",
                     lambda s: f"{s['wall_s']:.1f} s wall ({s['cpu_s']:.1f} s cpu)"),
    ("triangle", 800): ("completes", lambda s: f"completes, {s['wall_s']:.1f} s wall ({s['cpu_s']:.1f} s cpu)"),
    ("fig3", 50): ("one Monte-Carlo run <= 0.15 s",
                   lambda s: f"{s['wall_s']:.3f} s wall ({s['cpu_s']:.3f} s cpu)"),
}


def _measure(checkout: str, case: str, size: int, seed: int, timeout: float) -> dict:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout), BENCH_CHECKOUT=os.path.abspath(checkout))
    cmd = [sys.executable, os.path.abspath(__file__), "--child", case, str(size), str(seed)]
    try:
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout > {timeout:.0f} s"}
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[len("RESULT "):])
    return {"error": f"child failed: {proc.stderr.strip().splitlines()[-1:]}"}


def _summary(results: list[dict]) -> dict:
    ok = [r for r in results if "error" not in r]
    if not ok:
        return {"error": results[0]["error"], "peak_mb": max(r.get("peak_mb", 0.0) for r in results)}
    med = lambda key: statistics.median(r[key] for r in ok)  # noqa: E731
    out = {"wall_s": med("wall_s"), "cpu_s": med("cpu_s"), "peak_mb": max(r["peak_mb"] for r in ok),
           "ms_step": 1e3 * med("wall_s") / ok[0]["steps"], "cpu_ms_step": 1e3 * med("cpu_s") / ok[0]["steps"],
           "n": len(ok), "failed": len(results) - len(ok)}
    if "filter_s" in ok[0]:
        out["note"] = (f"filter {med('filter_s'):.2f} s, smoother {med('smoother_s'):.2f} s, "
                       f"inside {all(r['true_states_inside'] for r in ok)}")
    if "views_cpu_s" in ok[0]:
        out["note"] = (f"cpu: views {med('views_cpu_s'):.2f} s, recursion {med('recursion_cpu_s'):.2f} s "
                       f"(ratio {med('recursion_cpu_s') / med('views_cpu_s'):.2f})")
    if "empty" in ok[0]:
        out["note"] = f"empty posteriors {max(r['empty'] for r in ok)}"
    if len(ok) < len(results):
        first_error = next(r["error"] for r in results if "error" in r)
        out["note"] = "; ".join(filter(None, [out.get("note"), f"{len(results) - len(ok)} failed: {first_error}"]))
    return out


def _row(label: str, s: dict) -> str:
    if "wall_s" not in s:
        return f"{label:<22}{'–':>10}{'–':>10}{'–':>10}{'–':>10}{s['peak_mb']:>10.0f}  {s['error']}"
    return (f"{label:<22}{s['wall_s']:>10.2f}{s['cpu_s']:>10.2f}{s['ms_step']:>10.1f}{s['cpu_ms_step']:>10.1f}"
            f"{s['peak_mb']:>10.0f}"
            f"  {s.get('note', '')}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes (a few minutes in all)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--cases", default=",".join(FULL))
    parser.add_argument("--checkout", default=ROOT)
    parser.add_argument("--compare", default=None, help="a second checkout, measured alternately")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per subprocess")
    parser.add_argument("--child", nargs=3, metavar=("CASE", "SIZE", "SEED"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args.child[0], int(args.child[1]), int(args.child[2]))
        return

    sizes = QUICK if args.quick else FULL
    checkouts = [args.checkout] + ([args.compare] if args.compare else [])
    print(f"bench_long_horizon ({'quick' if args.quick else 'full'} sizes, repeats = {args.repeats}, "
          f"medians; peak = max ru_maxrss over repeats)")
    for c in checkouts:
        print(f"  checkout {os.path.abspath(c)}")
    header = f"{'case':<22}{'wall s':>10}{'cpu s':>10}{'ms/step':>10}{'cpu ms/st':>10}{'peak MB':>10}  notes"
    table: dict[tuple[str, int], list[dict]] = {}
    for case in args.cases.split(","):
        for size in sizes[case]:
            runs: list[list[dict]] = [[] for _ in checkouts]
            for r in range(args.repeats):
                for i, c in enumerate(checkouts):  # alternate, so load drifts hit both alike
                    runs[i].append(_measure(c, case, size, args.seed + r, args.timeout))
            table[(case, size)] = [_summary(rs) for rs in runs]
            print(f"  done {case} T={size}", flush=True)
    for i, c in enumerate(checkouts):
        print(f"\n[{os.path.basename(os.path.abspath(c))}]  {c}\n{header}")
        for (case, size), summaries in table.items():
            print(_row(f"{case} T={size}", summaries[i]))
    if args.compare:
        print(f"\nratio wall-clock {os.path.basename(os.path.abspath(args.compare))} / "
              f"{os.path.basename(os.path.abspath(args.checkout))} (> 1: the first checkout is faster)")
        for (case, size), (a, b) in table.items():
            ratio = f"{b['wall_s'] / a['wall_s']:.1f}x" if "wall_s" in a and "wall_s" in b else "–"
            cpu = f"{b['cpu_s'] / a['cpu_s']:.1f}x" if "cpu_s" in a and "cpu_s" in b else "–"
            print(f"{case + ' T=' + str(size):<22}{ratio:>10}  (cpu {cpu})")
    print(f"\nissue 8's targets ({os.path.basename(os.path.abspath(args.checkout))}; wall-clock and CPU, "
          f"full sizes only)")
    for (case, size), summaries in table.items():
        target = TARGETS.get((case, size))
        if target is None:
            continue
        s = summaries[0]
        if "wall_s" not in s:
            print(f"  {case} T={size}: {target[0]} -> {s['error']}")
            continue
        measured = target[1](s)
        print(f"  {case} T={size}: {target[0]} -> {measured}")


if __name__ == "__main__":
    main()
