"""Simulated trajectories of a system: `simulate`, with noises drawn uniformly from their ranges or given."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_generator, as_vector, check_system, given_instead_of_set, real_array
from ..sets.base import ConvexSet
from .linear_system import LinearSystem


def simulate(system, x0_set: ConvexSet, T: int, rng: np.random.Generator | int | None,
             x0: Any = None, *, ws: Any = None, vs: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """Simulate a trajectory with given noises, or noises drawn uniformly from their ranges.

    Parameters
    ----------
    system : LinearSystem or NonlinearSystem
    x0_set : ConvexSet
        ⟦x_0⟧; the initial state is drawn uniformly from it unless ``x0`` is given.
    T : int
        Final time step; states and measurements are returned for k = 0..T.
    rng : numpy.random.Generator, int or None
        The only source of randomness, taken as ``numpy.random.default_rng`` takes it: a Generator
        (used as is), an int seed, or None for fresh entropy from the operating system (a trajectory
        that cannot be replayed; nothing is drawn when ``x0``, ``ws`` and ``vs`` are all given).
    x0 : array_like, optional
        A fixed initial state; it must lie in ``x0_set`` (membership up to the default margin).
    ws : array_like, shape (T, p), optional
        Given process noises w_0..w_{T-1} (e.g. a worst case, or a recorded disturbance), used as
        given: they are not checked against W, so a test can also drive an estimator off its model.
        A given sequence is not drawn (the draws of the others keep their order).
    vs : array_like, shape (T+1, q), optional
        Given measurement noises v_0..v_T, likewise.

    Returns
    -------
    xs : ndarray, shape (T+1, n)
        True states x_0..x_T.
    ys : ndarray, shape (T+1, m)
        Measurements y_0..y_T.

    Raises
    ------
    TypeError
        When ``system`` is not a setsmooth system (a `control.StateSpace` is led to
        `LinearSystem.from_statespace`), ``rng`` is neither a Generator, an int seed nor None, ``T`` not an
        integer, or ``x0`` complex or not numeric.
    ValueError
        When ``T < 0``, ``u`` has fewer rows than steps 0..T read (`LinearSystem.check_input`),
        ``x0_set`` has the wrong dimension, or ``x0`` is NaN/inf, of the wrong length
        or outside ``x0_set``; when W or V cannot be sampled uniformly (flat, unbounded: the message
        says that ``ws=``/``vs=`` avoid the draw); or a matrix, input or transition value at some
        step is bad (named as ``A(k)``, ``u(k)``, ``f(k, x, w)``).

    Notes
    -----
    Uniform draws use each set's ``sample``: direct for boxes and ellipsoids, exact from the vertex
    hull for small low-dimensional CZs, hit-and-run otherwise (`setsmooth.sets.sampling`). All draws are made up front in a fixed
    order (x_0, then w_0..w_{T-1}, then v_0..v_T), so a seed fixes the whole trajectory.
    """
    check_system(system)
    if isinstance(T, bool) or not isinstance(T, (int, np.integer)):
        raise TypeError(f"T must be a non-negative integer, got {T!r}")
    if T < 0:
        raise ValueError(f"T must be a non-negative integer, got {T!r}")
    if not isinstance(x0_set, ConvexSet):
        raise ValueError(f"x0_set must be a ConvexSet of dimension n = {system.n}, "
                         f"{given_instead_of_set(x0_set, 'x0_set')}")
    if x0_set.dim != system.n:
        raise ValueError(f"x0_set must be a ConvexSet of dimension n = {system.n}, got one of dimension "
                         f"{x0_set.dim}")
    if isinstance(system, LinearSystem):
        system.check_input(T)
    if x0 is None or ws is None or vs is None:
        rng = as_generator(rng)
    ws = None if ws is None else _given_noises(ws, "ws", T, system.W.dim)
    vs = None if vs is None else _given_noises(vs, "vs", T + 1, system.V.dim)
    if x0 is None:
        x = x0_set.sample(rng, 1)[0]
    else:
        x = as_vector(x0, "x0", system.n)
        if not x0_set.contains(x):
            raise ValueError(f"x0 = {x.tolist()} does not lie in x0_set")
    if ws is None:
        ws = _drawn_noises(system.W, "W", "ws", rng, T)
    if vs is None:
        vs = _drawn_noises(system.V, "V", "vs", rng, T + 1)
    xs = [x]
    for k in range(T):
        xs.append(system.step(k, xs[-1], ws[k]))
    ys = [system.measure(k, xs[k], vs[k]) for k in range(T + 1)]
    return np.array(xs), np.array(ys)


def _drawn_noises(S: ConvexSet, set_name: str, given: str, rng: np.random.Generator,
                  rows: int) -> np.ndarray:
    """``rows`` uniform draws from the noise range S; a set that cannot be sampled (flat, unbounded)
    is a reason to give the noises, which the message says."""
    if rows == 0:
        return np.zeros((0, S.dim))
    try:
        return S.sample(rng, rows)
    except ValueError as exc:
        raise ValueError(f"cannot draw the noises uniformly from {set_name}: {exc}. Pass them as "
                         f"{given}= (shape ({rows}, {S.dim}), one row per step) to avoid the draw"
                         ) from exc


def _given_noises(values: Any, name: str, rows: int, dim: int) -> np.ndarray:
    """A given noise sequence as a finite (rows, dim) array; the message names the argument."""
    arr = real_array(values, name, f"an array of shape ({rows}, {dim})")
    if arr.ndim == 1 and dim == 1:
        arr = arr[:, None]
    if arr.shape != (rows, dim):
        raise ValueError(f"{name} must have shape ({rows}, {dim}), one row per step, got {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {arr[bad[0]].tolist()} is not finite")
    return arr
