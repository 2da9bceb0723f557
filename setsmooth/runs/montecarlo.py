"""Reproducible Monte Carlo runs: one independent, seeded random generator per run.

Run i always receives ``numpy.random.default_rng(SeedSequence(seed).spawn(n_runs)[i])``, whichever
process executes it and in whatever order runs complete, so results are bit-identical between serial
and parallel execution and a run can be replayed on its own (a run that raises says which it was and
how to rebuild its generator). The smoothing paper's figures average 5000 such runs (Figs. 3, 5, 6).
"""

from __future__ import annotations

import functools
import os
import pickle
from collections.abc import Callable
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any, TypeVar

import numpy as np
from tqdm import tqdm

from . import slots
from .dask_cluster import run_chunks

R = TypeVar("R")

#: Runs sent to a worker per task: large enough to amortize pickling, small enough for the progress
#: bar to move and for the work to spread evenly over the workers.
_MAX_CHUNK = 64


def run(trial: Callable[[np.random.Generator], R], n_runs: int, seed: int | np.random.Generator | None,
        executor: Executor | str | None = None, progress: bool | Callable = True,
        workers: int | None = None) -> list[R]:
    """Call ``trial(rng)`` for ``n_runs`` independent generators and return the results in run order.

    Parameters
    ----------
    trial : callable numpy.random.Generator -> object
        One Monte Carlo run; all of its randomness must come from the generator it is given. For a
        process pool it (and its result) must be picklable: a module-level function or a
        `functools.partial` of one.
    n_runs : int
        Number of runs, at least 1.
    seed : int, numpy.random.Generator or None
        Non-negative root seed: run i uses the i-th child of ``numpy.random.SeedSequence(seed)``. Or a
        Generator: the runs use children spawned from its seed sequence (as `Generator.spawn` does),
        so two calls with one Generator give different, independent runs. Or None, as
        ``numpy.random.default_rng(None)`` takes it: a root drawn from fresh operating-system entropy,
        so every call gives new runs (a failing run's note still prints the entropy that replays it).
    executor : concurrent.futures.Executor, distributed.Client, 'serial' or None
        None: a `ProcessPoolExecutor` with ``workers`` processes, created and shut down here (a single
        run is executed in-process). 'serial': every run in this process, in order. An `Executor`
        instance is used as is and left running. A ``dask.distributed.Client`` (the ``setsmooth[dask]``
        extra) sends chunks of runs to its cluster as tasks (`setsmooth.runs.dask_cluster`); a worker lost
        mid-run has its tasks recomputed, with the same results, and the client is left open.
    progress : bool or callable
        Show a tqdm progress bar. Or a tqdm-like class to report the runs to instead, called as tqdm
        is (an optional iterable, keywords ``total``, ``desc``, ``unit``; ``update(n)``, ``close()``):
        ``setsmooth figures`` passes one that forwards them to its own bar
        (`setsmooth.runs.figure_processes`).
    workers : int, optional
        Number of processes of the default pool; ``min(2, os.cpu_count())`` by default. Ignored
        otherwise.

    Returns
    -------
    list
        ``results[i]`` is the output of run i.

    Raises
    ------
    Exception
        Whatever a run raised, with a note naming the run index and its generator: the first failing
        run in run order (with a Dask client, the first to fail).
    TypeError
        When ``trial`` is not callable, ``n_runs``/``workers`` are not integers, ``seed`` is neither
        an integer, None nor a Generator with a seed sequence, ``executor`` is neither None, 'serial', an
        Executor nor a Dask client, or a process pool would run a ``trial`` that cannot be pickled
        (a lambda, a local function, a partial of one): checked before the pool starts.
    ValueError
        When ``n_runs < 1``, ``seed < 0`` or ``workers < 1``.
    """
    if not callable(trial):
        raise TypeError("trial must be a callable taking a numpy.random.Generator, got "
                        f"{type(trial).__name__}")
    n_runs = _integer(n_runs, "n_runs", minimum=1)
    root = _root_seed_sequence(seed)
    if workers is not None:
        workers = _integer(workers, "workers", minimum=1)
    serial = isinstance(executor, str) and executor == "serial"
    dask_client = _is_dask_client(executor)
    if not (executor is None or serial or isinstance(executor, Executor) or dask_client):
        raise TypeError("executor must be None, 'serial', a concurrent.futures.Executor or a "
                        f"dask.distributed.Client, got {executor!r}")

    seeds = root.spawn(n_runs)  # last, so that a refused call leaves a Generator's spawn count as it was
    # Children are numbered on from the parent's earlier spawns: run i has the key first + i.
    call = functools.partial(_call_trial, trial, seeds[0].spawn_key[-1])
    if callable(progress):
        bar = functools.partial(progress, total=n_runs, desc="Monte Carlo", unit="run")
    else:
        bar = functools.partial(tqdm, total=n_runs, disable=not progress, desc="Monte Carlo", unit="run")

    if serial or (executor is None and n_runs == 1):
        return [result for result in bar(map(call, seeds))]
    if dask_client:
        n_workers = max(1, len(executor.scheduler_info().get("workers", {})))
        with slots.lent():
            return run_chunks(executor, call, seeds, bar, _chunksize(n_runs, n_workers))
    if executor is None or isinstance(executor, ProcessPoolExecutor):
        # A pool that fails to pickle a task can hang in shutdown (2 runs in 10 with a lambda), so an
        # unpicklable trial is refused here, before any process starts.
        _check_picklable(trial)
    if isinstance(executor, Executor):
        with slots.lent():   # under `setsmooth figures`, this process computes nothing while it waits
            return _mapped(executor, call, seeds, bar, _chunksize(n_runs, workers or os.cpu_count() or 1))
    n_workers = workers or min(2, os.cpu_count() or 1)
    pool = ProcessPoolExecutor(max_workers=n_workers)
    try:
        with slots.lent():
            return _mapped(pool, call, seeds, bar, _chunksize(n_runs, n_workers))
    finally:
        # On an error (or Ctrl-C) do not wait for thousands of queued runs.
        pool.shutdown(wait=True, cancel_futures=True)


def _root_seed_sequence(seed: Any) -> np.random.SeedSequence:
    """The sequence the runs' generators are spawned from: SeedSequence(seed), or a Generator's own."""
    if seed is None:
        return np.random.SeedSequence()   # fresh entropy, kept in its .entropy for a replay
    if isinstance(seed, np.random.Generator):
        root = seed.bit_generator.seed_seq
        if not isinstance(root, np.random.SeedSequence):  # a bit generator seeded the legacy way
            raise TypeError("seed is a numpy.random.Generator without a SeedSequence to spawn runs "
                            "from; pass numpy.random.default_rng(...), an int seed or None")
        return root
    return np.random.SeedSequence(_integer(seed, "seed", minimum=0,
                                           what="an integer or a numpy.random.Generator (or None for "
                                                "fresh entropy)"))


def _is_dask_client(obj: Any) -> bool:
    # By type name, so that the core never imports Dask.
    return any(cls.__name__ == "Client" and cls.__module__.startswith("distributed")
               for cls in type(obj).__mro__)


def _mapped(executor: Executor, call: Callable, seeds: list, bar: Callable, chunksize: int) -> list:
    # Executor.map yields in submission order, which is run order, whatever the completion order.
    return [result for result in bar(executor.map(call, seeds, chunksize=chunksize))]


def _check_picklable(trial: Callable) -> None:
    """Raise a TypeError naming what in ``trial`` cannot be sent to a worker process."""
    try:
        pickle.dumps(trial)
    except Exception as exc:  # pickling raises PicklingError, TypeError, AttributeError, ...
        what = "trial"
        if isinstance(trial, functools.partial):
            parts = [("trial's function", trial.func)]
            parts += [(f"trial's positional argument {i}", a) for i, a in enumerate(trial.args)]
            parts += [(f"trial's keyword argument {k!r}", v) for k, v in trial.keywords.items()]
            what = next((name for name, part in parts if not _picklable(part)), what)
        raise TypeError(
            f"{what} cannot be pickled, so it cannot run in a process pool ({exc}). Use a "
            "module-level function (or a functools.partial of one with picklable arguments), or "
            "run with executor='serial' or a ThreadPoolExecutor") from exc


def _picklable(obj: Any) -> bool:
    try:
        pickle.dumps(obj)
    except Exception:
        return False
    return True


def _call_trial(trial: Callable[[np.random.Generator], Any], first_key: int,
                seed_seq: np.random.SeedSequence) -> Any:
    try:
        with slots.held():   # a worker of a `setsmooth figures` script computes in one of its slots
            return trial(np.random.default_rng(seed_seq))
    except Exception as exc:
        _add_note(exc, f"in Monte Carlo run {seed_seq.spawn_key[-1] - first_key}; replay it with "
                       f"trial(numpy.random.default_rng(numpy.random.SeedSequence({seed_seq.entropy}, "
                       f"spawn_key={seed_seq.spawn_key})))")
        raise


def _add_note(exc: Exception, note: str) -> None:
    """PEP 678's note (Python 3.11+; on 3.10 kept in ``__notes__``, where tracebacks do not show it).

    The exception keeps its type and message, so a caller's ``except`` still catches it; the note
    pickles with it back from a worker process.
    """
    if hasattr(exc, "add_note"):
        exc.add_note(note)
    else:  # pragma: no cover - Python 3.10
        exc.__notes__ = [*getattr(exc, "__notes__", []), note]


def _chunksize(n_runs: int, n_workers: int) -> int:
    return max(1, min(_MAX_CHUNK, n_runs // (4 * n_workers)))


def _integer(value: Any, name: str, minimum: int, what: str = "an integer") -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be {what}, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)
