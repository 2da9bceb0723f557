"""Observation-information sets O_{k,i} and the Observation-Information Tower (stability Definitions 5–6).

O_{k,i} is what the single measurement y_i says about x_k when every other measurement is ignored:
the set X_i(C, y_i, ⟦v_i⟧) = {x : y_i − C_i x ∈ D_i V} carried forward by the prediction step alone,

    O_{k,i} = A^{k−i} X_i(C, y_i, ⟦v_i⟧) ⊕ Σ_{r=i}^{k−1} A^{k−1−r} B ⟦w_r⟧                 (12)

(with the known inputs u_r added, and A_r, B_r for time-varying systems). The OIT at time k is
∩_{i=k−δ}^{k} O_{k,i} (Definition 6); it outer-bounds the classical filter's posterior for every
initial condition (Proposition 1 with (15)). X_i is unbounded unless C has full column rank, so these
are extended constrained zonotopes with h = ∞ factors, built exactly by the set algebra from ℝⁿ.
"""

from __future__ import annotations

from typing import Any

from .._validation import measured
from ..sets.base import ConvexSet
from ..sets.reals import Reals

__all__ = ["observation_set", "observation_information_set", "observation_information_tower"]


def _check_time(value: Any, name: str, lo: int, hi: int, what: str) -> int:
    if isinstance(value, bool) or not hasattr(value, "__index__"):
        raise TypeError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must satisfy {what}, got {name} = {value}")
    return value


def observation_set(system, y_i: Any, i: int) -> ConvexSet:
    """X_i(C, y_i, ⟦v_i⟧) = {x : y_i − C_i x ∈ F_i V}, the states consistent with y_i alone (stability (4)).

    ``y_i`` without the feedthrough (y_i − D_i u_i, as the door `setsmooth._validation.measured` gives it).
    """
    return Reals(system.n).intersect_preimage(system.C_at(i), y_i + system.measurement_noise_image(i))


def _carry(system, S: ConvexSet, i: int, k: int) -> ConvexSet:
    """The prediction step alone from time i to k: S ↦ A_r S ⊕ E_r W ⊕ {B_r u_r}, r = i..k−1 (stability (3))."""
    for r in range(i, k):
        S = system.A_at(r) @ S + system.process_noise_image(r)
        u = system.nonzero_input(r)
        if u is not None:
            S = S + u
    return S


def observation_information_set(system, ys: Any, k: int, i: int) -> ConvexSet:
    """O_{k,i} of stability paper (12): the information y_i carries about x_k, for 0 ≤ i ≤ k.

    Parameters
    ----------
    system : LinearSystem
    ys : array_like, shape (T+1, m)
        Measurements indexed by absolute time (``ys[l]`` = y_l); only ``ys[i]`` is used.
    k, i : int
        Times with 0 ≤ i ≤ k (k may exceed T: only the prediction runs past y_i).

    Returns
    -------
    ConvexSet
        An extended constrained zonotope (h = ∞ where C leaves directions unobserved) when W and V
        flatten to CZs; a lazy set otherwise.

    Examples
    --------
    >>> import setsmooth as ss
    >>> unit = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[2.0]], None, [[1.0]], W=unit, V=unit)
    >>> hull = ss.observation_information_set(system, [[0.5]], 2, 0).interval_hull()
    >>> hull.lo.round(9).tolist(), hull.hi.round(9).tolist()     # 4·[−0.5, 1.5] ⊕ (2 + 1)·[−1, 1]
    ([-5.0], [9.0])
    """
    system, ys = measured(system, ys)
    i = _check_time(i, "i", 0, len(ys) - 1, f"0 ≤ i ≤ T = {len(ys) - 1}")
    k = _check_time(k, "k", i, 2**62, f"k ≥ i = {i}")
    return _carry(system, observation_set(system, ys[i], i), i, k)


def observation_information_tower(system, ys: Any, k: int, delta: int) -> ConvexSet:
    """The OIT ∩_{i=k−δ}^{k} O_{k,i} of stability paper Definition 6, exactly.

    For any initial condition the classical filter's posterior lies in it (Proposition 1 and (15));
    for observable (A, C) with nonsingular A and k ≥ δ ≥ μ − 1 it is bounded, with 2-norm diameter at
    most (16) (`setsmooth.analysis.oit_diameter_bound`).

    Parameters
    ----------
    system : LinearSystem
    ys : array_like, shape (T+1, m)
        Measurements y_0..y_T (absolute time).
    k : int
        Time of the tower, 0 ≤ k ≤ T.
    delta : int
        Number of past measurements beyond y_k, 0 ≤ δ ≤ k.

    Returns
    -------
    ConvexSet
        The intersection of the δ + 1 sets O_{k,i}, i = k − δ..k, as one (extended) constrained
        zonotope when W and V flatten to CZs.

    Raises
    ------
    ValueError
        When k or δ is out of range (the message names which).

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> unit = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]],
    ...                          W=unit, V=unit)
    >>> ys = np.array([[0.0], [1.0], [2.0]])
    >>> tower = ss.observation_information_tower(system, ys, 2, 1)   # bounded: δ = 1 ≥ μ − 1
    >>> bool(np.all(np.isfinite(tower.interval_hull().hi)))
    True
    """
    system, ys = measured(system, ys)
    T = len(ys) - 1
    k = _check_time(k, "k", 0, T, f"0 ≤ k ≤ T = {T}")
    delta = _check_time(delta, "delta", 0, k, f"0 ≤ delta ≤ k = {k}")
    tower = None
    for i in range(k - delta, k + 1):
        O = _carry(system, observation_set(system, ys[i], i), i, k)
        tower = O if tower is None else tower & O
    return tower
