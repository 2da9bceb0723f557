"""A `LinearSystem` from a python-control `StateSpace`: inputs split into known inputs and noises.

The work behind `LinearSystem.from_statespace` (whose docstring states the modes and their
assumptions): validate the model and the index split, sample it, and multiply out the known input.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_matrix, real_array, real_number
from .discretization import bounded_noise_set, zoh_matrices
from ..sets.base import ConvexSet

_METHODS = ("zoh", "bounded")


def linear_system_from_statespace(cls, statespace, W: ConvexSet, V: ConvexSet, *, noise_inputs: Any,
                                  inputs: Any, Psi: Any, dt: Any, method: str | None,
                                  partition: int):
    """The implementation of `LinearSystem.from_statespace` (see there)."""
    import control

    if not isinstance(statespace, control.StateSpace):
        raise TypeError(f"statespace must be a control.StateSpace, got {type(statespace).__name__}")
    for name, S in (("W", W), ("V", V)):
        if not isinstance(S, ConvexSet):
            raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
    A, B, C, F = (np.asarray(M, dtype=float) for M in
                  (statespace.A, statespace.B, statespace.C, statespace.D))
    noise, known = _split_inputs(noise_inputs, B.shape[1])
    if W.dim != len(noise):
        raise ValueError(f"W must have one coordinate per noise input: noise_inputs selects "
                         f"{len(noise)} of the statespace's {B.shape[1]} inputs, W.dim = {W.dim}")
    _check_feedthrough(F, noise, known)
    if known.size and inputs is None:
        raise ValueError(f"the statespace's inputs {known.tolist()} are not noise inputs, so they are "
                         f"known inputs: pass their samples as inputs=, shape (T, {known.size})")
    if not known.size and inputs is not None:
        raise ValueError("inputs= was given but every statespace input is a noise input; select the "
                         "noise inputs with noise_inputs=")

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
        Phi, Gamma = zoh_matrices(A, B, sample_time)
        Gamma_u = Gamma[:, known]
        if method == "zoh":
            B_d, W_d = Gamma[:, noise], W
        else:
            Phi, W_d = bounded_noise_set(A, B[:, noise], W, sample_time, partition=partition)
            B_d = np.eye(A.shape[0])
    else:
        if method is not None:
            raise ValueError(f"method={method!r} applies to continuous models; statespace is already "
                             f"discrete (dt = {statespace.dt}), its noise a sequence w_k ∈ W")
        sample_time = _discrete_sample_time(statespace.dt, dt)
        Phi, B_d, Gamma_u, W_d = A, B[:, noise], B[:, known], W

    m = C.shape[0]
    Psi = np.eye(m) if Psi is None else as_matrix(Psi, "Psi", m, None)
    u_term = None if not known.size else _input_term(Gamma_u, inputs)
    return cls(Phi, B_d, C, Psi, W_d, V, u=u_term, dt=sample_time)


def _split_inputs(noise_inputs: Any, n_inputs: int) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the noise inputs and of the known inputs (the others), in the statespace's order."""
    if noise_inputs is None:
        return np.arange(n_inputs), np.arange(0)
    idx = real_array(noise_inputs, "noise_inputs", "a sequence of input indices").reshape(-1)
    if idx.size == 0 or not np.all(idx == np.round(idx)) or idx.min() < 0 or idx.max() >= n_inputs:
        raise ValueError(f"noise_inputs must be a non-empty sequence of input indices in "
                         f"[0, {n_inputs}), got {np.asarray(noise_inputs).tolist()}")
    idx = idx.astype(int)
    if len(set(idx.tolist())) != idx.size:
        raise ValueError(f"noise_inputs must not repeat an index, got {idx.tolist()}")
    return idx, np.setdiff1d(np.arange(n_inputs), idx)


def _check_feedthrough(F: np.ndarray, noise: np.ndarray, known: np.ndarray) -> None:
    if np.any(F[:, noise] != 0):
        raise ValueError("statespace must have zero feedthrough D from the noise inputs: a noise "
                         "reaching y directly would couple w and v, which the model treats as "
                         "unrelated")
    if np.any(F[:, known] != 0):
        raise ValueError("statespace has a feedthrough D from the known inputs: subtract D u_k from "
                         "the measurements and pass the model with that feedthrough set to zero")


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


def _input_term(Gamma_u: np.ndarray, inputs: Any):
    """u_k = Γ_u · inputs[k], the term `LinearSystem` adds to x_{k+1} (rows, or a callable of k)."""
    if callable(inputs):
        return _KnownInput(Gamma_u, inputs)
    values = real_array(inputs, "inputs", f"an array of shape (T, {Gamma_u.shape[1]})")
    if values.ndim == 1 and Gamma_u.shape[1] == 1:
        values = values[:, None]
    if values.ndim != 2 or values.shape[1] != Gamma_u.shape[1]:
        raise ValueError(f"inputs must have shape (T, {Gamma_u.shape[1]}) (one column per known "
                         f"input), got {np.shape(inputs)}")
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        raise ValueError(f"inputs[{bad[0]}] = {values[bad[0]].tolist()} is not finite")
    return values @ Gamma_u.T


class _KnownInput:
    """k -> Γ_u inputs(k): picklable whenever the user's callable is."""

    def __init__(self, Gamma_u: np.ndarray, inputs):
        self.Gamma_u, self.inputs = Gamma_u, inputs

    def __call__(self, k: int) -> np.ndarray:
        value = np.asarray(self.inputs(k), dtype=float).reshape(-1)
        if value.shape != (self.Gamma_u.shape[1],):
            raise ValueError(f"inputs({k}) must have {self.Gamma_u.shape[1]} entries, got {value.shape}")
        return self.Gamma_u @ value
