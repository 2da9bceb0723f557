"""Solver instances as a bounded, per-thread cache, never part of a set's identity.

A set-up solver (a Clarabel instance with its factorization, a compiled CVXPY problem) is expensive
to build and cheap to re-solve, so it is worth keeping while its set is being queried. But it is
mutable state: two threads re-solving one instance with different objectives corrupt each other's
answers, it cannot be pickled, and keeping one per set ever queried makes a long filter run's
memory grow without bound. So instances live here, not on the sets:

* **per thread**: each thread has its own cache, so an instance is only ever used by one thread;
* **bounded**: each thread keeps the ``MAX_INSTANCES`` most recently used instances (LRU);
* **weak**: an entry is keyed by its owner's identity and dies with it (a dead owner's entry is never
  returned, even if Python reuses its ``id``).

A set that is pickled or copied to another process simply builds its instances again on first use.
"""

from __future__ import annotations

import threading
import weakref
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import TypeVar

__all__ = ["MAX_INSTANCES", "cached_instance", "clear", "kept_instance"]

T = TypeVar("T")

#: Solver instances kept per thread. An estimator queries the newest set of its loop, so a few
#: suffice; each can hold a factorization of a large sparse KKT system.
MAX_INSTANCES = 16

_local = threading.local()


def _cache() -> OrderedDict:
    cache = getattr(_local, "cache", None)
    if cache is None:
        cache = _local.cache = OrderedDict()
    return cache


def cached_instance(owner: object, key: Hashable, build: Callable[[], T]) -> T:
    """This thread's instance for ``(owner, key)``, built by ``build()`` on first use.

    Parameters
    ----------
    owner : object
        The object the instance serves (must support weak references).
    key : hashable
        Which of the owner's instances (an owner may keep several programs).
    build : callable () -> instance
        Builds the instance when this thread has none for ``(owner, key)``.

    Returns
    -------
    object
        The cached or newly built instance. It must only be used by the calling thread.
    """
    cache = _cache()
    slot = (id(owner), key)
    entry = cache.get(slot)
    if entry is not None:
        ref, instance = entry
        if ref() is owner:
            cache.move_to_end(slot)
            return instance
        del cache[slot]
    instance = build()
    cache[slot] = (weakref.ref(owner), instance)
    while len(cache) > MAX_INSTANCES:
        cache.popitem(last=False)
    return instance


def kept_instance(owner: object, key: Hashable) -> object | None:
    """This thread's instance for ``(owner, key)`` if it keeps one, else None (nothing is built,
    and the cache's order is left as it is)."""
    entry = _cache().get((id(owner), key))
    if entry is None or entry[0]() is not owner:
        return None
    return entry[1]


def clear() -> None:
    """Drop every instance this thread keeps."""
    _cache().clear()
