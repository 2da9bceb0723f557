"""BLAS threads of the timed figure scripts: limited before any solve, read back from the libraries.

An environment variable such as ``OPENBLAS_NUM_THREADS`` only acts when OpenBLAS loads; under
``setsmooth figures`` every script runs in one process, so after the first script NumPy is loaded and a
script's own ``os.environ`` pin does nothing (stability Table 1 was timed with two threads while its JSON
said one). `limited` sets the limit in the loaded libraries themselves (threadpoolctl, through
`setsmooth.runs.environment.blas_limit`) and returns what they report back, which is what a script records beside
its timings.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

from threadpoolctl import threadpool_info

from setsmooth.runs.environment import blas_limit


def in_force() -> list[dict]:
    """Every BLAS library loaded in this process with the threads it will use, as the library reports it."""
    return [{"library": f"{i['internal_api']} {i.get('version') or ''}".strip(),
             "file": Path(i["filepath"]).name, "threads": int(i["num_threads"])}
            for i in threadpool_info() if i["user_api"] == "blas"]


def thread_counts(libraries: list[dict]) -> list[int]:
    """The distinct thread counts of `in_force` records (one number when all libraries agree)."""
    return sorted({lib["threads"] for lib in libraries})


@contextmanager
def limited(threads: int = 1):
    """Limit every loaded BLAS library (and those loaded or started later) to ``threads``; yield `in_force`.

    Enter it after the imports and before the first solve; the limit is undone on leaving.
    """
    with blas_limit(threads):
        yield in_force()


def describe(libraries: list[dict]) -> str:
    """One line for a report: the threads in force and the libraries that reported them."""
    counts = thread_counts(libraries)
    shown = ", ".join(f"{lib['library']} ({lib['file']}): {lib['threads']}" for lib in libraries)
    return f"{'/'.join(map(str, counts)) or '?'} (read back: {shown or 'no BLAS library loaded'})"
