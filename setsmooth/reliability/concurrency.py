"""Threads and processes: one set queried from several threads, pickling after queries, Monte Carlo guards.

* `threaded_support`: ``workers`` threads query the same set object at once (started together by a
  barrier, each over all directions in its own order) on one path; the answers are compared with a
  serial run on an identical, freshly built set. Exceptions in threads are collected, never lost, and
  a thread still running after ``timeout`` seconds counts as a hang.
* `montecarlo_lambda_probe`: ``montecarlo.run`` with an unpicklable (lambda) trial, in a subprocess
  whose own watchdog thread reports a hang, so a stuck process pool cannot stall the caller; the
  subprocess is started in its own session and its whole process group is killed afterwards.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import threading
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import setsmooth as ss


def set_factories() -> dict[str, Callable[[], ss.ConvexSet]]:
    """One builder per set type; each call builds a new, identical set."""
    return {
        "Box": lambda: ss.Box([-1.0, -0.5, 0.0], [1.0, 2.0, 0.5]),
        "Zonotope": lambda: ss.Zonotope([[1.0, 0.5, 0.0, 0.2], [0.0, 1.0, 0.3, -0.4], [0.2, 0.0, 1.0, 0.1]],
                                        [0.1, -0.2, 0.3]),
        "ConstrainedZonotope": lambda: ss.ConstrainedZonotope(
            [[1.0, 0.5, 0.0, 0.2, 0.3], [0.0, 1.0, 0.3, -0.4, 0.1], [0.2, 0.0, 1.0, 0.1, -0.5]],
            [0.1, -0.2, 0.3], [[1.0, 1.0, -0.5, 0.2, 0.3]], [0.4]),
        "HPolytope": lambda: ss.HPolytope(np.vstack([np.eye(3), -np.eye(3), [[1.0, 1.0, 1.0]]]),
                                          [1.0, 2.0, 0.5, 1.0, 0.5, 0.0, 1.5]),
        "Ellipsoid": lambda: ss.Ellipsoid([0.0, 1.0, -1.0], np.diag([1.0, 0.5, 2.0]) + 0.1),
        "Intersection": lambda: (ss.Box([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
                                 & ss.Ellipsoid([0.5, 0.0, 0.0], np.eye(3) * 1.5)),
    }


@dataclass
class ThreadOutcome:
    name: str
    path: str
    queries: int = 0
    wrong: int = 0
    worst: float = 0.0
    errors: list[str] = field(default_factory=list)
    hung: int = 0


def threaded_support(name: str, build: Callable[[], ss.ConvexSet], path: str, workers: int = 4,
                     n_directions: int = 20, seed: int = 0, timeout: float = 60.0,
                     tol: float = 1e-7) -> ThreadOutcome:
    """Query one set of type ``name`` from ``workers`` threads at once and compare with a serial run."""
    out = ThreadOutcome(name, path)
    S0 = build()
    D = np.random.default_rng(seed).normal(size=(n_directions, S0.dim))
    reference = np.array([S0.support(d, path=path) for d in D])
    S = build()
    barrier = threading.Barrier(workers)
    results: list[list[tuple[int, float]]] = [[] for _ in range(workers)]
    lock = threading.Lock()

    def work(w: int) -> None:
        order = np.random.default_rng(seed + 1 + w).permutation(n_directions)
        try:
            barrier.wait(timeout)
            for i in order:
                results[w].append((int(i), S.support(D[i], path=path)))
        except Exception as exc:  # noqa: BLE001 - collected and reported
            with lock:
                out.errors.append(f"{type(exc).__name__}: {str(exc)[:120]}")

    threads = [threading.Thread(target=work, args=(w,), daemon=True) for w in range(workers)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout)
    out.hung = sum(t.is_alive() for t in threads)
    for res in results:
        for i, value in res:
            out.queries += 1
            err = abs(value - reference[i])
            if not err <= tol * (1 + abs(reference[i])):
                out.wrong += 1
                out.worst = max(out.worst, float(err) if np.isfinite(err) else np.inf)
    return out


_PROBE = r"""
import os, sys, threading
import setsmooth as ss
out = open(sys.argv[1], "w", buffering=1)
outcome = []
def attempt():
    try:
        ss.montecarlo.run(lambda rng: float(rng.random()), n_runs=8, seed=0, progress=False, workers=2)
        outcome.append("returned")
    except BaseException as exc:
        outcome.append("raised " + type(exc).__name__)
for i in range({attempts}):
    t = threading.Thread(target=attempt, daemon=True)
    t.start()
    t.join({timeout})
    if t.is_alive():
        out.write("hung\n")
        os._exit(0)
    out.write(outcome[-1] + "\n")
os._exit(0)
"""


def montecarlo_lambda_probe(attempts: int = 5, timeout: float = 20.0) -> list[str]:
    """Outcomes ('raised <Type>', 'returned', 'hung') of ``attempts`` runs with a lambda trial."""
    code = _PROBE.format(attempts=attempts, timeout=timeout)
    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.abspath(ss.__file__)))
    env["PYTHONPATH"] = os.pathsep.join([root, env.get("PYTHONPATH", "")])
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "outcomes.txt")
        # Results go to a file, not a pipe: stuck pool workers would hold a pipe open.
        proc = subprocess.Popen([sys.executable, "-c", code, report], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, start_new_session=True, env=env)
        try:
            proc.wait(timeout=attempts * timeout + 60)
        except subprocess.TimeoutExpired:
            pass
        finally:
            try:
                os.killpg(proc.pid, signal.SIGKILL)  # the probe's own group, stuck pool workers included
            except ProcessLookupError:
                pass
            proc.wait()
        with open(report) as fh:
            lines = [line.strip() for line in fh if line.strip()]
    return lines if len(lines) == attempts or (lines and lines[-1] == "hung") else lines + ["hung"]
