"""Monte Carlo runs on a Dask cluster (the optional ``setsmooth[dask]`` extra).

`setsmooth.runs.montecarlo.run` sends its runs here when it is given a ``dask.distributed.Client``. Nothing
else in the package imports this module, and this module imports ``distributed`` only when it is
called, so the core works without Dask installed.

The runs are grouped into chunks; one chunk is one Dask task, identified by its chunk index. A chunk
computes its runs from their `numpy.random.SeedSequence` children alone, so a task recomputed after a
worker was lost returns exactly what the first attempt would have: the scheduler re-runs the tasks
that were in flight on a dead worker (up to its ``allowed-failures``), and each chunk's result is
collected once, by index. Results are therefore bit-identical to a serial run and no run is lost or
counted twice.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

import numpy as np


def run_chunks(client: Any, call: Callable[[np.random.SeedSequence], Any],
               seeds: list[np.random.SeedSequence], bar: Callable, chunksize: int) -> list:
    """Run ``call(seed)`` for every seed on ``client``'s cluster; results in seed order.

    Parameters
    ----------
    client : distributed.Client
        A connected client; it is used as is and left open.
    call : callable
        Picklable function of one seed sequence (it is shipped to the workers with each task).
    seeds : list of numpy.random.SeedSequence
        One per run.
    bar : callable
        ``bar()`` returns a tqdm-like progress bar with ``update(n)`` and ``close()``; it advances by
        the number of runs of each finished chunk.
    chunksize : int
        Runs per task.

    Returns
    -------
    list
        ``results[i] = call(seeds[i])``.

    Raises
    ------
    Exception
        The first exception raised by a run, re-raised here (the other tasks are cancelled).
    """
    from distributed import as_completed

    chunks = [seeds[start:start + chunksize] for start in range(0, len(seeds), chunksize)]
    # pure=False: two chunks with equal seeds would still be distinct runs; keys carry the index.
    futures = [client.submit(_run_chunk, call, chunk, pure=False) for chunk in chunks]
    index = {future.key: i for i, future in enumerate(futures)}
    results: list[list | None] = [None] * len(chunks)
    progress = bar()
    try:
        for future in as_completed(futures):
            i = index[future.key]
            results[i] = future.result()   # re-raises a run's exception here
            progress.update(len(chunks[i]))
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        progress.close()
    return [result for chunk in results for result in chunk]


def _run_chunk(call: Callable[[np.random.SeedSequence], Any], chunk: list) -> list:
    return [call(seed) for seed in chunk]


def connect(address: str) -> Any:
    """A ``distributed.Client`` connected to the scheduler at ``address``.

    Raises
    ------
    ImportError
        When Dask is not installed, saying which extra provides it.
    """
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover  (the CI installs the extra)
        raise ImportError("running on a Dask scheduler needs dask.distributed: "
                          "pip install 'setsmooth[dask]'") from exc
    return Client(address)


def scheduler_client(address: str | None, command: str) -> tuple[Any, int]:
    """The command line's door to a scheduler: (a client of the scheduler at ``address``, or None
    without an address, and exit status 0), or (None, 2) after telling standard error, in the name
    of ``command``, why the scheduler could not be reached."""
    if address is None:
        return None, 0
    try:
        return connect(address), 0
    except (ImportError, OSError) as exc:
        print(f"{command}: --scheduler {address}: {exc}", file=sys.stderr)
        return None, 2
