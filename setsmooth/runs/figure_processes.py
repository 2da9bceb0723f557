"""``setsmooth figures`` with several workers: every script in its own process, W computing at once.

The scripts start in the order of `setsmooth.runs.schedule.plan` (the longest first, each after the
scripts whose outputs it reads), at most W at a time, each in a fresh process forked from a server that
has imported the library once (the ``forkserver`` start method; ``spawn`` where there is none). Each
script runs its Monte Carlo in a pool of W worker processes, and the W slots of
`setsmooth.runs.slots` keep the computing processes of all scripts to W: a script with few long runs
uses the cores another has left idle, and timed runs still have a core each. Results do not depend on
which process runs what (run i always uses the i-th seed child), so they are those of the scripts run
one after the other in the planned order.

Progress: one bar in this process counts tasks, a script or one Monte Carlo run of it, and moves as
they finish; the script processes forward their runs to it (`ForwardedBar`, passed to the scripts as
their ``progress`` and so to `setsmooth.runs.montecarlo.run`). The bar is off when standard error is not
a terminal or with ``--no-progress``.
"""

from __future__ import annotations

import functools
import importlib
import multiprocessing
import os
import queue
import sys
import time
import traceback
from pathlib import Path

from tqdm import tqdm

from . import slots
from .environment import blas_limit
from .schedule import plan, prerequisites

#: Imported once by the fork server, so a script process starts without importing the library.
PRELOAD = ["numpy", "scipy.sparse", "scipy.linalg", "scipy.optimize", "scipy.spatial", "cvxpy", "setsmooth",
           "setsmooth.sets", "setsmooth.filters", "setsmooth.smoothers", "matplotlib.pyplot"]
#: Seconds between checks that every running script process is still alive.
POLL = 1.0


def run_scheduled(names: list[str], figures_dir: Path, out: Path, runs: int | None, seed: int, workers: int,
                  progress: bool, costs: dict[str, float], after: dict[str, tuple[str, ...]],
                  environment: dict[str, str], blas_threads: int | None, echo=print) -> dict:
    """Run the scripts ``names`` in processes, W = ``workers`` at a time; return {name: wall seconds or
    'failed'} in the order they were started.

    ``environment``: variables every script process sets first (the figure formats, the BLAS threads);
    ``blas_threads``: the BLAS limit each script process applies to its loaded libraries. ``echo``
    prints a finished script's lines (through the bar while it is shown).
    """
    order = plan(names, costs, after)
    waits = prerequisites(names, after)
    context = _context()
    semaphore = context.Semaphore(workers)
    messages = context.Queue()
    bar = Progress(len(names), show=progress)
    pending, running, exited = list(order), {}, {}
    outcome: dict[str, float | str] = {}
    try:
        while pending or running:
            while len(running) < workers:
                finished = {name for name, value in outcome.items() if value != "running"}
                ready = [name for name in pending if waits[name] <= finished]
                if not ready:
                    break
                name = ready[0]
                pending.remove(name)
                process = context.Process(
                    target=_script_process, name=f"setsmooth figures: {name}",
                    args=(name, str(figures_dir), str(out), runs, seed, workers, environment, blas_threads,
                          semaphore, messages))
                process.start()
                running[name] = process
                outcome[name] = "running"
                bar.started(name)
            try:
                message = messages.get(timeout=POLL)
            except queue.Empty:
                for name, process in list(running.items()):
                    # A process that exited without saying so (killed, crashed): give its last message
                    # one more poll to arrive, then count the script as failed.
                    if process.exitcode is not None and exited.setdefault(name, time.monotonic()) < \
                            time.monotonic() - POLL:
                        echo(f"== {name}: its process ended with exit code {process.exitcode}")
                        message = ("failed", name, None)
                        _finish(message, running, outcome, bar, echo)
                continue
            _finish(message, running, outcome, bar, echo)
    finally:
        for process in running.values():
            process.terminate()
        for process in running.values():
            process.join()
        bar.close()
    return outcome


def _finish(message: tuple, running: dict, outcome: dict, bar: "Progress", echo) -> None:
    kind, name, *rest = message
    if kind == "total":
        bar.announced(rest[0])
    elif kind == "update":
        bar.advanced(rest[0])
    elif kind in ("done", "failed"):
        process = running.pop(name, None)
        if process is not None:
            process.join()
        if kind == "done":
            seconds, rows = rest
            outcome[name] = seconds
            lines = [f"== {name}: {seconds:.1f} s"]
            lines += [f"   {r['quantity']}: paper {r['paper']} | ours {r['ours']}" for r in rows]
        else:
            outcome[name] = "failed"
            lines = [f"== {name}: failed"] + ([rest[0]] if rest and rest[0] else [])
        bar.finished(name)
        with bar.aside():
            echo("\n".join(lines))


def _context():
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(PRELOAD)
        return context
    return multiprocessing.get_context("spawn")


def _script_process(name, figures_dir, out, runs, seed, workers, environment, blas_threads, semaphore,
                    messages) -> None:
    """One figure script in this (fresh) process, computing in the slots of ``semaphore``."""
    os.environ.update(environment)
    if sys.platform.startswith("linux"):
        # This process's pools fork from it, as from a script run alone: their workers inherit the
        # slots and count in its CPU time. (A fork server's child defaults to the fork server, which
        # would start them outside both.)
        multiprocessing.set_start_method("fork", force=True)
    if figures_dir not in sys.path:
        # The scripts import their sibling helpers, and pool workers unpickle trials by module name.
        sys.path.insert(0, figures_dir)

    slots.install(semaphore)
    semaphore.acquire()
    start = time.perf_counter()
    try:
        kwargs = {"seed": seed, "out": Path(out), "workers": workers,
                  "progress": functools.partial(ForwardedBar, messages=messages, name=name)}
        if runs is not None:
            kwargs["runs"] = runs
        with blas_limit(blas_threads):
            result = importlib.import_module(name).main(**kwargs)
        messages.put(("done", name, time.perf_counter() - start, list(result.get("rows", []))))
    except BaseException:  # reported in the parent; one failing figure must not hide the others
        messages.put(("failed", name, traceback.format_exc()))
    finally:
        semaphore.release()
        messages.close()
        messages.join_thread()


class ForwardedBar:
    """A tqdm-like bar that forwards a script's Monte Carlo runs to the parent's `Progress`.

    Called as `setsmooth.runs.montecarlo.run` calls tqdm: ``ForwardedBar(iterable, total=...)`` or
    ``ForwardedBar(total=...)`` with ``update(n)``.
    """

    def __init__(self, iterable=None, total=None, desc=None, unit=None, *, messages, name: str):
        self._iterable, self._messages, self._name = iterable, messages, name
        if total:
            messages.put(("total", name, int(total)))

    def __iter__(self):
        for item in self._iterable:
            yield item
            self.update(1)

    def update(self, n: int = 1) -> None:
        self._messages.put(("update", self._name, int(n)))

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class Progress:
    """Tasks of one call: each script is one, and each Monte Carlo run a script announces.

    ``done`` and ``total`` count them (the total grows as the scripts announce their runs); the tqdm bar
    that shows them is off when ``show`` is false or standard error is not a terminal.
    """

    def __init__(self, scripts: int, show: bool = True):
        self.done, self.total = 0, scripts
        self.scripts, self.finished_scripts = scripts, 0
        self.running: list[str] = []
        self._bar = tqdm(total=scripts, desc=self._desc(), unit="task", disable=None if show else True,
                         dynamic_ncols=True)

    def _desc(self) -> str:
        return f"figures {self.finished_scripts}/{self.scripts}"

    def started(self, name: str) -> None:
        self.running.append(name)
        self._show()

    def announced(self, runs: int) -> None:
        self.total += runs
        self._bar.total = self.total
        self._show()

    def advanced(self, runs: int) -> None:
        self.done += runs
        self._bar.update(runs)

    def finished(self, name: str) -> None:
        if name in self.running:
            self.running.remove(name)
        self.finished_scripts += 1
        self.done += 1
        self._bar.set_description_str(self._desc(), refresh=False)
        self._bar.update(1)
        self._show()

    def _show(self) -> None:
        self._bar.set_postfix_str(", ".join(self.running), refresh=True)

    def aside(self):
        """A block whose printing goes above the bar."""
        return self._bar.external_write_mode() if not self._bar.disable else _nothing()

    def close(self) -> None:
        self._bar.close()


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        pass
