"""Environment and BLAS thread limits for timed runs (the figure runner and the scripts it starts)."""

from __future__ import annotations

import contextlib
import os

__all__ = ["BLAS_ENV", "blas_limit", "temporary_environment"]


#: The variables BLAS libraries read when they load (in this process later, or in a worker process).
BLAS_ENV = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


@contextlib.contextmanager
def blas_limit(threads: int | None):
    """Limit the loaded BLAS libraries (threadpoolctl) and those loaded later (environment) to ``threads``.

    An environment variable alone acts only where a library has not loaded yet: after NumPy's import
    it changes nothing in this process, which is how Table 1 was once timed on two threads.
    """
    if threads is None:
        yield
        return
    from threadpoolctl import threadpool_limits

    with temporary_environment(dict.fromkeys(BLAS_ENV, str(threads))), \
            threadpool_limits(limits=threads, user_api="blas"):
        yield


@contextlib.contextmanager
def temporary_environment(values: dict[str, str]):
    """Set environment variables for the duration of the block, then restore them."""
    saved = {name: os.environ.get(name) for name in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
