"""What filters and smoothers return: the list of sets, plus the tubes everyone computes from it.

`SetEstimates` is a `list` subclass, so ``posteriors[k]``, ``len``, iteration and slicing behave as
before; it adds the interval-hull tubes as (T+1, n) arrays, their diameters, the first empty step,
containment of a true trajectory and a tube plot, and it remembers the data it was computed from
(system, X0, measurements), so that a smoother given the posteriors of other data raises.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from ._validation import real_array
from .sets.base import ConvexSet

__all__ = ["SetEstimates"]


class SetEstimates(list):
    """The sets ⟦x_k | ·⟧ for k = 0..T of one estimator run, as a list with tubes and provenance.

    Parameters
    ----------
    sets : iterable of ConvexSet
        The estimates, one per step.
    system : LinearSystem, optional
        The system they were computed for.
    X0 : ConvexSet, optional
        The initial prior range.
    ys : array_like, shape (T+1, m), optional
        The measurements (kept as a read-only copy).
    kind : str
        What the sets are, for labels: ``'filtered'`` (⟦x_k | y_{0:k}⟧) or ``'smoothed'``
        (⟦x_k | y_{0:T}⟧).
    outer : bool
        True when the sets are outer bounds of those ranges (a reduced filter, or a smoother run on
        its output) rather than the ranges themselves.

    Attributes
    ----------
    lo, hi, centers : ndarray, shape (T+1, n)
        Interval-hull tubes (certified where available, `ConvexSet.interval_hull`) and their
        midpoints; rows of NaN at empty steps.
    first_empty : int or None
        The first step whose set is empty (data inconsistent with the model from there), or None.

    Notes
    -----
    The hulls are computed once, on first use, and kept while the list holds the same set objects
    (replacing an entry recomputes them).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], [[1.0]], [[1.0]], [[1.0]], W=box, V=box)
    >>> smoothed = ss.optimal_smoother(system, ss.Box([-5.0], [5.0]), [[0.0], [3.0]])
    >>> smoothed.hi.round(6).tolist(), smoothed.diameters().round(6).tolist()
    ([[1.0], [2.0]], [0.0, 0.0])
    >>> smoothed.contains_trajectory([[1.0], [2.0]]).tolist()
    [True, True]
    """

    def __init__(self, sets: Iterable[ConvexSet] = (), *, system: Any = None, X0: ConvexSet | None = None,
                 ys: Any = None, kind: str = "", outer: bool = False):
        super().__init__(sets)
        self.system, self.X0, self.kind, self.outer = system, X0, kind, bool(outer)
        self.ys = None
        if ys is not None:
            self.ys = np.array(real_array(ys, "ys"), dtype=float, copy=True)
            self.ys.flags.writeable = False
        self._hull_cache: tuple[tuple[int, ...], list[ConvexSet], np.ndarray, np.ndarray] | None = None

    # -- tubes ---------------------------------------------------------------------------------------
    def interval_hulls(self, *, certified: bool | None = None, workers: int = 1,
                       progress: bool | None = None) -> list[ConvexSet]:
        """The interval hull of every set, each computed once and kept on its set.

        Parameters
        ----------
        certified : bool or None
            As in `ConvexSet.interval_hull` (default: certified where available).
        workers : int
            Threads that split the sets between them (default 1: in order, in this thread). Clarabel
            and HiGHS release the GIL while they solve, and every thread builds its own solver
            instances (`setsmooth.solvers.instances`), so the projections of one trajectory set are
            solved side by side: 46.5 s → 26.6 s (1.75×) on 2 cores for a 3-state smoother at
            T = 600 (``benchmarks/bench_long_horizon.py --cases smoother3,smoother3x2``). Keep 1
            inside process pools that already use every core.
        progress : bool or None
            A tqdm progress bar on standard error, one tick per set: the estimators build their
            sets quickly and the hulls are where the time goes. None (default): shown when standard
            error is a terminal.

        Returns
        -------
        list of ConvexSet
            Boxes (an `EmptySet` for an empty set), in the order of the sets.

        Examples
        --------
        >>> import setsmooth as ss
        >>> box = ss.Box([-1.0], [1.0])
        >>> system = ss.LinearSystem([[1.0]], [[1.0]], [[1.0]], [[1.0]], W=box, V=box)
        >>> smoothed = ss.optimal_smoother(system, ss.Box([-5.0], [5.0]), [[0.0], [3.0]])
        >>> [h.hi.round(6).tolist() for h in smoothed.interval_hulls(workers=2)]
        [[1.0], [2.0]]
        """
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
            raise ValueError(f"workers must be a positive integer, got {workers!r}")
        if certified not in (None, True, False):
            raise ValueError(f"certified must be None, True or False, got {certified!r}")

        from tqdm.auto import tqdm

        show = sys.stderr.isatty() if progress is None else bool(progress)
        with tqdm(total=len(self), desc="interval hulls", unit="set", disable=not show,
                  leave=False) as bar:
            def hull(S: ConvexSet) -> ConvexSet:
                out = S.interval_hull(certified=certified)
                bar.update(1)
                return out

            if workers == 1 or len(self) < 2:
                return [hull(S) for S in self]
            from concurrent.futures import ThreadPoolExecutor

            with ThreadPoolExecutor(max_workers=int(workers)) as pool:
                return list(pool.map(hull, self))

    def _tubes(self) -> tuple[np.ndarray, np.ndarray]:
        key = tuple(id(S) for S in self)
        cache = self._hull_cache
        if cache is None or cache[0] != key:
            n = self[0].dim if len(self) else 0
            lo, hi = np.full((len(self), n), np.nan), np.full((len(self), n), np.nan)
            for k, hull in enumerate(self.interval_hulls()):
                if not hull.is_empty():
                    lo[k], hi[k] = hull.lo, hull.hi
            for arr in (lo, hi):
                arr.flags.writeable = False
            # the sets are kept with their ids, so an id cannot be reused while the cache lives
            cache = self._hull_cache = (key, list(self), lo, hi)
        return cache[2], cache[3]

    @property
    def lo(self) -> np.ndarray:
        """Lower edges of the interval hulls, shape (T+1, n); NaN rows where the set is empty."""
        return self._tubes()[0]

    @property
    def hi(self) -> np.ndarray:
        """Upper edges of the interval hulls, shape (T+1, n); NaN rows where the set is empty."""
        return self._tubes()[1]

    @property
    def centers(self) -> np.ndarray:
        """Interval-hull centres (the ∞-norm Chebyshev centres), shape (T+1, n)."""
        lo, hi = self._tubes()
        return (lo + hi) / 2.0

    def diameters(self, norm: float | str = np.inf) -> np.ndarray:
        """Diameters of the interval hulls, shape (T+1,); NaN where the set is empty.

        Parameters
        ----------
        norm : {inf, 'inf', 2}
            inf (default): the widest edge, which is exactly the set's ∞-norm diameter (smoothing
            paper Fig. 3(b)). 2: the hull's diagonal, an upper bound of the set's 2-norm diameter
            (within a factor √n).

        Returns
        -------
        ndarray, shape (T+1,)
        """
        lo, hi = self._tubes()
        if norm in (np.inf, "inf"):
            return (hi - lo).max(axis=1, initial=-np.inf) if len(self) else np.zeros(0)
        if norm == 2:
            return np.linalg.norm(hi - lo, axis=1)
        raise ValueError(f"norm must be inf or 2, got {norm!r}")

    @property
    def first_empty(self) -> int | None:
        empty = np.flatnonzero(np.isnan(self._tubes()[0]).any(axis=1))
        return int(empty[0]) if empty.size else None

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray:
        """Whether each true state x_k lies in the k-th set (an exact membership program per step).

        Parameters
        ----------
        xs : array_like, shape (T+1, n)
            The true trajectory, e.g. from `simulate`.
        tol : float, optional
            Membership margin, as in `ConvexSet.contains`.

        Returns
        -------
        ndarray of bool, shape (T+1,)
        """
        n = self[0].dim if len(self) else 0
        states = real_array(xs, "xs", f"an array of shape ({len(self)}, {n})")
        if states.shape != (len(self), n):
            raise ValueError(f"xs must have shape ({len(self)}, {n}), one state per set, got {states.shape}")
        return np.array([S.contains(x, tol) for S, x in zip(self, states)], dtype=bool)

    # -- plotting ------------------------------------------------------------------------------------
    def plot_tubes(self, ax: Any = None, dims: Sequence[int] | None = None, *, truth: Any = None,
                   times: Any = None, label: str | None = None, **kwargs) -> list:
        """Shade the interval-hull tube lo[k, i]..hi[k, i] against k for each coordinate i in ``dims``.

        Call it on the filtered and on the smoothed result with the same axes to compare them:
        ``axes = filtered.plot_tubes(); smoothed.plot_tubes(axes, truth=xs)``.

        Parameters
        ----------
        ax : matplotlib Axes or sequence of Axes, optional
            One axes per coordinate of ``dims``; new subplots stacked vertically when None.
        dims : sequence of int, optional
            Coordinates to plot; all by default.
        truth : array_like, shape (T+1, n), optional
            A true trajectory, drawn as a black line.
        times : array_like, shape (T+1,), optional
            The horizontal axis; k·dt when the system has a sampling time ``dt``, else k.
        label : str, optional
            Legend label of the tube; ``kind`` by default.
        **kwargs
            Passed to ``Axes.fill_between`` (e.g. ``color``, ``alpha``).

        Returns
        -------
        list of matplotlib.axes.Axes
            The axes drawn on, one per coordinate of ``dims`` (pass them back as ``ax``); each tube is
            the last of its axes' ``collections``.

        Raises
        ------
        TypeError
            When ``ax`` holds something other than matplotlib Axes.
        """
        import matplotlib.pyplot as plt

        n = self[0].dim if len(self) else 0
        dims = list(range(n)) if dims is None else [int(i) for i in dims]
        if not dims or min(dims) < 0 or max(dims) >= n:
            raise ValueError(f"dims must be coordinates in [0, {n}), got {dims}")
        if ax is None:
            _, ax = plt.subplots(len(dims), 1, sharex=True, squeeze=False,
                                 figsize=(6.4, 1.0 + 1.8 * len(dims)))
            ax = ax[:, 0]
        axes = list(np.atleast_1d(np.asarray(ax, dtype=object)).ravel())
        wrong = next((a for a in axes if not hasattr(a, "fill_between")), None)
        if wrong is not None:
            raise TypeError(f"ax must be a matplotlib Axes or a sequence of them (one per coordinate of "
                            f"dims), got {type(wrong).__name__}")
        if len(axes) != len(dims):
            raise ValueError(f"ax must hold one Axes per coordinate of dims ({len(dims)}), got {len(axes)}")
        if times is None:
            dt = getattr(self.system, "dt", None)
            times = np.arange(len(self)) * (dt if dt is not None else 1.0)
        times = real_array(times, "times").reshape(-1)
        if times.shape != (len(self),):
            raise ValueError(f"times must have shape ({len(self)},), got {times.shape}")
        xs = None if truth is None else real_array(truth, "truth").reshape(len(self), n)
        kwargs.setdefault("alpha", 0.35)
        for a, i in zip(axes, dims):
            a.fill_between(times, self.lo[:, i], self.hi[:, i],
                           label=label if label is not None else (self.kind or None), **kwargs)
            if xs is not None:
                a.plot(times, xs[:, i], color="black", linewidth=1.0, label="true state")
            a.set_ylabel(f"$x_{{{i}}}$")
        axes[-1].set_xlabel("t" if getattr(self.system, "dt", None) is not None else "k")
        return axes

    # -- provenance ----------------------------------------------------------------------------------
    def check_same_data(self, system: Any, X0: ConvexSet, ys: np.ndarray) -> None:
        """Raise unless these estimates were computed from ``system``, ``X0`` and ``ys``.

        The system must be the same object, the measurements equal, and X0 the same object or a set
        with the same interval hull. Estimates that did not record their data are not checked.

        Raises
        ------
        ValueError
            Naming what differs.
        """
        if self.system is not None and self.system is not system:
            raise ValueError(f"these {self.kind or 'estimates'} were computed for another system object")
        if self.ys is not None and (self.ys.shape != np.shape(ys) or not np.array_equal(self.ys, ys)):
            first = _first_difference(self.ys, np.asarray(ys))
            raise ValueError(f"these {self.kind or 'estimates'} were computed from other measurements "
                             f"({first})")
        if self.X0 is not None and self.X0 is not X0 and not _same_hull(self.X0, X0):
            raise ValueError(f"these {self.kind or 'estimates'} were computed from another X0")

    def __reduce__(self):
        # list subclasses pickle their items and __dict__; the hull cache is recomputed on demand
        state = dict(self.__dict__, _hull_cache=None)
        return (_rebuild, (list(self), state))

    def __repr__(self) -> str:
        return f"SetEstimates({self.kind or 'sets'}, T={len(self) - 1}, {list.__repr__(self)})"


def _rebuild(items: list, state: dict) -> SetEstimates:
    result = SetEstimates(items)
    result.__dict__.update(state)
    return result


def _first_difference(a: np.ndarray, b: np.ndarray) -> str:
    if a.shape != b.shape:
        return f"shape {b.shape}, recorded {a.shape}"
    k = int(np.flatnonzero(~np.all(a == b, axis=tuple(range(1, a.ndim))))[0])
    return f"first at k = {k}"


def _same_hull(A: ConvexSet, B: ConvexSet) -> bool:
    if not isinstance(B, ConvexSet) or A.dim != B.dim:
        return False
    ha, hb = A.interval_hull(), B.interval_hull()
    if ha.is_empty() or hb.is_empty():
        return ha.is_empty() and hb.is_empty()
    return bool(np.array_equal(ha.lo, hb.lo) and np.array_equal(ha.hi, hb.hi))
