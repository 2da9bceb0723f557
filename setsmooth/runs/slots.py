"""CPU slots shared by the processes of one ``setsmooth figures`` call: a job server, like make's ``-j``.

`setsmooth.runs.figure_processes` runs several figure scripts at once, each in its own process, and each
script may start a pool of Monte Carlo workers. With W slots at most W of all these processes compute at
any time: a script process holds a slot for its own work and lends it back while it waits for its
workers (`lent`), and a worker holds one for each run it computes (`held`, in
`setsmooth.runs.montecarlo`). So two scripts on two cores share them one process per core, as one
script's process pool did alone, and the runs of a script with few long runs (stability Table 1) can
use a core another script has left idle. Timed runs keep one core each.

Without `install` (a plain ``montecarlo.run``, a script run on its own) both context managers do
nothing. The semaphore reaches pool workers by inheritance (fork, the default on Linux); workers
started otherwise run without slots, which only oversubscribes the cores.
"""

from __future__ import annotations

import os
from contextlib import contextmanager

_semaphore = None
#: The process that holds a slot for its own work (a script process); its workers are the others.
_owner: int | None = None


def install(semaphore) -> None:
    """Make this process the owner of one of ``semaphore``'s slots (it must hold it when it computes)."""
    global _semaphore, _owner
    _semaphore, _owner = semaphore, os.getpid()


def installed() -> bool:
    return _semaphore is not None


@contextmanager
def held():
    """Hold a slot for the block, in a worker of the owner; nothing in the owner or without slots."""
    if _semaphore is None or os.getpid() == _owner:
        yield
        return
    _semaphore.acquire()
    try:
        yield
    finally:
        _semaphore.release()


@contextmanager
def lent():
    """In the owner: give its slot back while it waits for its workers, take one again after."""
    if _semaphore is None or os.getpid() != _owner:
        yield
        return
    _semaphore.release()
    try:
        yield
    finally:
        _semaphore.acquire()
