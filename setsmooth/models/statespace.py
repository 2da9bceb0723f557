"""A `LinearSystem` from a python-control `StateSpace`: its inputs split into known inputs and noises.

The work behind `LinearSystem.from_statespace` (whose docstring states the modes and their
assumptions): validate the model and the index split into known inputs (python-control's B and D)
and noise inputs (E), and sample a continuous model soundly.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_matrix, given_instead_of_set, real_array, real_number
from .discretization import bounded_noise_set, zoh_matrices
from ..sets.base import ConvexSet

_METHODS = ("zoh", "bounded")


def linear_system_from_statespace(cls, statespace, *, W: ConvexSet, V: ConvexSet, E: Any, F: Any,
                                  u: Any, noise_inputs: Any, dt: Any, method: str | None,
                                  partition: int):
    """The implementation of `LinearSystem.from_statespace` (see there)."""
    import control

    if not isinstance(statespace, control.StateSpace):
        raise TypeError(f"statespace must be a control.StateSpace, got {type(statespace).__name__}")
    for name, S in (("W", W), ("V", V)):
        if not isinstance(S, ConvexSet):
            raise TypeError(f"{name} must be a ConvexSet, {given_instead_of_set(S, name)}")
    A, B, C, D = (np.asarray(M, dtype=float) for M in
                  (statespace.A, statespace.B, statespace.C, statespace.D))
    n = A.shape[0]
    noise, known = _split_inputs(noise_inputs, B.shape[1])
    if known.size and u is None:
        raise ValueError(f"the statespace's inputs {known.tolist()} are known inputs (its B and D act "
                         f"on them, as in python-control): pass their samples as u=, shape "
                         f"(T+1, {known.size}), time first; or select the noise inputs with noise_inputs=")
    if not known.size and u is not None:
        raise ValueError("u= was given but every statespace input is a noise input (noise_inputs=), "
                         "or the statespace has no input")
    if noise.size:
        if E is not None:
            raise ValueError("E= and noise_inputs= both give the process-noise matrix: noise_inputs "
                             "selects it from the statespace's B; pass one of them")
        E_c = B[:, noise]
        if W.dim != len(noise):
            raise ValueError(f"W must have one coordinate per noise input: noise_inputs selects "
                             f"{len(noise)} of the statespace's {B.shape[1]} inputs, W.dim = {W.dim}")
    elif E is None:
        if W.dim != n:
            raise ValueError(f"E=None means E = I, which needs W.dim = n = {n}, got W.dim = {W.dim}: "
                             f"give the process-noise matrix E= ({n} × {W.dim}), or select noise "
                             "inputs of the statespace with noise_inputs=")
        E_c = np.eye(n)
    else:
        E_c = as_matrix(E, "E", n, W.dim)
    if np.any(D[:, noise] != 0):
        raise ValueError("statespace must have zero feedthrough D from the noise inputs: a noise "
                         "reaching y directly would couple w and v, which the model treats as "
                         "unrelated")

    if statespace.isctime():
        if method is None:
            method = "bounded"
        if method not in _METHODS:
            raise ValueError(f"method must be one of {_METHODS}, got {method!r}. 'tustin' is not "
                             "offered: it is exact for no class of noise signals, so its noise sets "
                             "would not enclose the increments; a first-order-hold (piecewise-linear) "
                             "noise stays in W at every instant, so 'bounded' encloses it")
        if dt is None:
            raise ValueError("dt must be a positive sampling time to discretize a continuous model, "
                             "got None")
        sample_time = _positive_time(dt, "dt")
        Phi, Gamma = zoh_matrices(A, np.hstack([B[:, known], E_c]), sample_time)
        B_d = Gamma[:, :known.size]
        if method == "zoh":
            E_d, W_d = Gamma[:, known.size:], W
        else:
            Phi, W_d = bounded_noise_set(A, E_c, W, sample_time, partition=partition)
            E_d = np.eye(n)
    else:
        if method is not None:
            raise ValueError(f"method={method!r} applies to continuous models; statespace is already "
                             f"discrete (dt = {statespace.dt}), its noise a sequence w_k ∈ W")
        sample_time = _discrete_sample_time(statespace.dt, dt)
        Phi, B_d, E_d, W_d = A, B[:, known], E_c, W

    if not known.size:
        return cls(Phi, None, C, E=E_d, F=F, W=W_d, V=V, dt=sample_time)
    return cls(Phi, B_d, C, D[:, known], E=E_d, F=F, W=W_d, V=V, u=u, dt=sample_time)


def _split_inputs(noise_inputs: Any, n_inputs: int) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the noise inputs and of the known inputs (the others), in the statespace's order."""
    if noise_inputs is None:
        return np.arange(0), np.arange(n_inputs)
    idx = real_array(noise_inputs, "noise_inputs", "a sequence of input indices").reshape(-1)
    if idx.size == 0 or not np.all(idx == np.round(idx)) or idx.min() < 0 or idx.max() >= n_inputs:
        raise ValueError(f"noise_inputs must be a non-empty sequence of input indices in "
                         f"[0, {n_inputs}), got {np.asarray(noise_inputs).tolist()}")
    idx = idx.astype(int)
    if len(set(idx.tolist())) != idx.size:
        raise ValueError(f"noise_inputs must not repeat an index, got {idx.tolist()}")
    return idx, np.setdiff1d(np.arange(n_inputs), idx)


def _positive_time(value: Any, name: str) -> float:
    t = real_number(value, name)
    if not (np.isfinite(t) and t > 0):
        raise ValueError(f"{name} must be a positive finite sampling time, got {value!r}")
    return t


def _discrete_sample_time(model_dt: Any, dt: Any) -> float | None:
    """The sampling time of a discrete model (``dt=True`` there: unspecified), checked against dt."""
    if model_dt is True:
        return None if dt is None else _positive_time(dt, "dt")
    model = float(model_dt)
    if dt is not None and _positive_time(dt, "dt") != model:
        raise ValueError(f"dt = {dt!r} disagrees with the sampling time of the discrete statespace "
                         f"({model}); drop dt or resample the model")
    return model
