"""What filters and smoothers return: one protocol of tubes, checks and a plot, over k = 0..T.

`Estimates` is the protocol every estimator's result follows: ``lo``, ``hi``, ``centers``,
``diameters()``, ``first_empty``, ``contains_trajectory(xs)``, ``plot_tubes(ax, dims)`` and ``len``.
`Tubes` derives all but ``lo`` and ``hi`` from those two, so a result class states its bounds and
inherits the rest. `SetEstimates` is a `list` subclass, so ``posteriors[k]``, ``len``, iteration and
slicing behave as lists do (a slice or ``copy()`` is again a `SetEstimates` with the same data); its
tubes are the sets' interval hulls, its membership test is exact, and it remembers the data it was
computed from (system, X0, measurements), so that a smoother given the posteriors of other data
raises. `IntervalEstimates` holds the interval ranges of scalar monotone systems.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ._validation import real_array
from .sets.base import ConvexSet
from .sets.shared_hulls import shared_interval_hulls
from .tolerances import MEMBERSHIP_TOL

__all__ = ["Estimates", "Tubes", "SetEstimates", "IntervalEstimates"]


class Estimates(Protocol):
    """What every estimator returns, whatever else it carries.

    `SetEstimates` (the exact and reduced filters, the smoothers, the OIT-inspired and the optimal
    filters), `OITResult`, `LSUResult`, `IntervalEstimates`, `SampledRanges` and `KalmanResult` (whose
    tubes are σ-boxes about its means, never empty) follow it; their own fields stay. ``lo`` and
    ``hi`` have shape (T+1, n) with NaN rows at empty steps; (T+1,) for the scalar
    `IntervalEstimates`, and `SampledRanges`, a batch of runs, puts a runs axis first in every
    member. Results holding sets also give the set at step k as ``result[k]``.

    A static protocol (for type checkers): an ``isinstance`` check of a runtime protocol would read
    ``lo`` and ``hi`` before Python 3.12, computing every hull.
    """

    @property
    def lo(self) -> np.ndarray: ...

    @property
    def hi(self) -> np.ndarray: ...

    @property
    def centers(self) -> np.ndarray: ...

    @property
    def first_empty(self) -> Any: ...

    def diameters(self, norm: float | str = np.inf) -> np.ndarray: ...

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray: ...

    def plot_tubes(self, ax: Any = None, dims: Sequence[int] | None = None, **kwargs) -> list: ...

    def __len__(self) -> int: ...


class Tubes:
    """The `Estimates` protocol derived from ``lo`` and ``hi``.

    A result class defines ``lo`` and ``hi`` (shape (T+1, n), or (T+1,) for a scalar state; NaN rows
    where the estimate is empty) and ``__len__``, and inherits ``centers``, ``diameters``,
    ``first_empty``, ``contains_trajectory`` (interval membership; a result holding sets overrides it
    with exact membership) and ``plot_tubes``. ``kind`` labels the tube; a ``system`` with a sampling
    time ``dt`` scales the time axis.
    """

    kind: str = ""
    system: Any = None

    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """lo and hi as (T+1, n) arrays (a scalar state's (T+1,) as a column)."""
        lo, hi = np.asarray(self.lo), np.asarray(self.hi)
        return lo.reshape(len(lo), -1), hi.reshape(len(hi), -1)

    def _step_indices(self) -> np.ndarray:
        """The step k of each entry (0..T unless the result is a slice)."""
        return np.arange(len(self))

    @property
    def centers(self) -> np.ndarray:
        """Interval-hull centres (the ∞-norm Chebyshev centres), shaped like ``lo``."""
        return (self.lo + self.hi) / 2.0

    def diameters(self, norm: float | str = np.inf) -> np.ndarray:
        """Diameters of the interval hulls, shape (T+1,); NaN where the estimate is empty.

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
        lo, hi = self._bounds()
        if norm in (np.inf, "inf"):
            return (hi - lo).max(axis=1, initial=-np.inf) if len(lo) else np.zeros(0)
        if norm == 2:
            return np.linalg.norm(hi - lo, axis=1)
        raise ValueError(f"norm must be inf or 2, got {norm!r}")

    @property
    def first_empty(self) -> int | None:
        """The first step whose estimate is empty (the data contradict the model there), or None."""
        empty = np.flatnonzero(np.isnan(self._bounds()[0]).any(axis=1))
        return int(empty[0]) if empty.size else None

    def _states(self, xs: Any, name: str = "xs") -> np.ndarray:
        """``xs`` as a (T+1, n) array, one state per step (a scalar state's (T+1,) accepted)."""
        steps, n = self._bounds()[0].shape
        states = real_array(xs, name, f"an array of shape ({steps}, {n})")
        if states.shape != (steps, n) and not (n == 1 and states.shape == (steps,)):
            raise ValueError(f"{name} must have shape ({steps}, {n}), one state per step, got {states.shape}")
        return states.reshape(steps, n)

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray:
        """Whether each true state x_k lies in the k-th interval hull.

        Parameters
        ----------
        xs : array_like, shape (T+1, n)
            The true trajectory ((T+1,) for a scalar state).
        tol : float, optional
            Absolute margin; by default ``MEMBERSHIP_TOL`` relative to max(1, |x|).

        Returns
        -------
        ndarray of bool, shape (T+1,)
            False at empty steps.
        """
        lo, hi = self._bounds()
        states = self._states(xs)
        margin = MEMBERSHIP_TOL * np.maximum(1.0, np.abs(states)) if tol is None else float(tol)
        with np.errstate(invalid="ignore"):
            inside = (lo - margin <= states) & (states <= hi + margin)
        return inside.all(axis=1)

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

        lo, hi = self._bounds()
        steps, n = lo.shape
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
        dt = getattr(self.system, "dt", None)
        if times is None:
            times = self._step_indices() * (dt if dt is not None else 1.0)
        times = real_array(times, "times").reshape(-1)
        if times.shape != (steps,):
            raise ValueError(f"times must have shape ({steps},), got {times.shape}")
        xs = None if truth is None else self._states(truth, "truth")
        kwargs.setdefault("alpha", 0.35)
        for a, i in zip(axes, dims):
            a.fill_between(times, lo[:, i], hi[:, i],
                           label=label if label is not None else (self.kind or None), **kwargs)
            if xs is not None:
                a.plot(times, xs[:, i], color="black", linewidth=1.0, label="true state")
            a.set_ylabel(f"$x_{{{i}}}$")
        axes[-1].set_xlabel("t" if dt is not None else "k")
        return axes


class SetEstimates(Tubes, list):
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
    (replacing an entry recomputes them). A slice (``posteriors[10:20]``) and ``copy()`` are
    `SetEstimates` with the same data and ``kind``; a slice's tube plot keeps the steps' own k.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
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
        self._steps: np.ndarray | None = None  # the steps k of a slice's sets (None: 0..T)

    def __getitem__(self, index):
        if not isinstance(index, slice):
            return list.__getitem__(self, index)
        return self._like(list.__getitem__(self, index), self._step_indices()[index])

    def copy(self) -> SetEstimates:
        """A shallow copy: the same sets, data and kind, still a `SetEstimates`."""
        return self._like(list(self), self._steps)

    def _like(self, sets: list, steps: np.ndarray | None) -> SetEstimates:
        out = SetEstimates(sets)
        out.__dict__.update(self.__dict__)
        out._steps = steps
        return out

    def _step_indices(self) -> np.ndarray:
        steps = getattr(self, "_steps", None)
        return np.arange(len(self)) if steps is None else steps

    # -- tubes ---------------------------------------------------------------------------------------
    def interval_hulls(self, *, certified: bool | None = None, workers: int = 1,
                       progress: bool | None = None) -> list[ConvexSet]:
        """The interval hull of every set, each computed once and kept.

        The exact filter's posteriors (`classical_filter` with CZ noises) are done along time
        (`setsmooth.filters.hulls_along_time`): each hull from a window of the last steps, bracketed
        between an inner and a certified outer bound, at a cost per step that does not grow with k;
        they agree with each set's own `ConvexSet.interval_hull` to 1e-7 of the width (both
        certified ones enclose the set). Those hulls are kept on this result; all others on their
        sets.

        Parameters
        ----------
        certified : bool or None
            As in `ConvexSet.interval_hull` (default: certified where available).
        workers : int
            Threads (default 1: everything in order, in this thread, and the filter's hulls along
            time, which only run there). Sets over one factor set — a smoother's projections — are
            solved a direction at a time across the sets (`setsmooth.sets.shared_hulls`), each
            set's directions split between the threads, with the same hulls for every count; other
            sets are split between the threads, each solved alone. Clarabel and HiGHS release the
            GIL while they solve, and every thread builds its own solver instances
            (`setsmooth.solvers.instances`). Keep 1 inside process pools that already use every
            core.
        progress : bool or None
            A tqdm progress bar on standard error, one tick per set (per LP for sets solved a
            direction at a time): the estimators build their
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
        >>> system = ss.LinearSystem([[1.0]], None, [[1.0]], W=box, V=box)
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
        along = self._hulls_along_time(certified, workers, show)
        if along is not None:
            return along
        # Sets over one factor set (a smoother's projections): a chain of LPs per direction across
        # the sets (`setsmooth.sets.shared_hulls`), the chains split between the threads.
        shared = shared_interval_hulls(list(self), certified, progress=show, workers=int(workers))
        if shared is not None:
            return shared
        with tqdm(total=len(self), desc="interval hulls", unit="set", disable=not show,
                  leave=False) as bar:
            def hull(S: ConvexSet) -> ConvexSet:
                out = S.interval_hull(certified=certified)
                bar.update(1)
                return out

            if workers == 1 or len(self) < 2:
                return [hull(S) for S in self]
            with ThreadPoolExecutor(max_workers=int(workers)) as pool:
                return list(pool.map(hull, self))

    def _hulls_along_time(self, certified: bool | None, workers: int, show: bool) -> list | None:
        """The hulls along time, when the estimator offered them (``_along_time``: a callable of
        ``certified`` and ``progress`` with the estimator's ``sets``) and this result still holds
        those very sets in order; else None."""
        along = self.__dict__.get("_along_time")
        if along is None or workers != 1 or self._steps is not None:
            return None
        if len(self) != len(along.sets) or any(S is not T for S, T in zip(self, along.sets)):
            return None  # entries replaced or reordered: the sets' own hulls
        kept = self.__dict__.setdefault("_along_hulls", {})
        flag = certified is not False  # None: certified where available, and here it always is
        if flag not in kept:
            kept[flag] = along(certified=flag, progress=show)
        return list(kept[flag])

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


@dataclass(frozen=True)
class IntervalEstimates(Tubes):
    """Interval ranges [lo[k], hi[k]] of a scalar state for k = 0..T; both NaN where the range is empty.

    What `interval_filter`, `interval_smoother` and `classical_interval_filter` return (smoothing paper
    (27)–(30): for a scalar monotone system every range is an interval). It follows the `Estimates`
    protocol with ``lo`` and ``hi`` of shape (T+1,), the state being scalar.

    Attributes
    ----------
    lo, hi : ndarray, shape (T+1,)
        Lower and upper endpoints (read-only copies; ±inf allowed for unbounded ranges).

    Raises
    ------
    ValueError
        When shapes differ, NaN appears in only one endpoint, or lo > hi somewhere.

    Examples
    --------
    >>> ranges = IntervalEstimates([0.0, 0.5, float("nan")], [1.0, 0.75, float("nan")])
    >>> ranges.diameters().tolist()[:2], ranges.first_empty, ranges.contains_trajectory([0.5, 0.6, 0.0]).tolist()
    ([1.0, 0.25], 2, [True, True, False])
    """

    lo: np.ndarray
    hi: np.ndarray

    def __post_init__(self) -> None:
        lo = real_array(self.lo, "lo").reshape(-1).copy() if np.ndim(self.lo) <= 1 else None
        hi = real_array(self.hi, "hi").reshape(-1).copy() if np.ndim(self.hi) <= 1 else None
        if lo is None or hi is None or lo.shape != hi.shape:
            raise ValueError(f"lo and hi must be 1-D arrays of one length (T+1,), got shapes "
                             f"{np.shape(self.lo)} and {np.shape(self.hi)}")
        if not np.array_equal(np.isnan(lo), np.isnan(hi)):
            raise ValueError("lo and hi must be NaN at the same steps (NaN marks an empty range)")
        with np.errstate(invalid="ignore"):
            if np.any(lo > hi):
                raise ValueError(f"lo must not exceed hi; first violation at k = {int(np.argmax(lo > hi))}")
        lo.setflags(write=False)
        hi.setflags(write=False)
        # Frozen dataclass: assign the validated copies through object.__setattr__.
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)

    @property
    def empty(self) -> np.ndarray:
        """Boolean array, True where the range is empty."""
        return np.isnan(self.lo)

    def __len__(self) -> int:
        return self.lo.shape[0]
