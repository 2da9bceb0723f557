"""A `LinearSystem` from a python-control `StateSpace`: its inputs split into known inputs and noises.

`from_statespace`, which `LinearSystem` binds as its class method `LinearSystem.from_statespace`
(its docstring states the modes and their assumptions): validate the model and the index split into
known inputs (python-control's B and D) and noise inputs (E), and sample a continuous model soundly.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_matrix, given_instead_of_set, real_array, real_number
from .discretization import bounded_noise_set, zoh_matrices
from ..sets.base import ConvexSet

_METHODS = ("zoh", "bounded")


def from_statespace(cls, statespace, *, W: ConvexSet, V: ConvexSet, E: Any = None, F: Any = None,
                    u: Any = None, noise_inputs: Any = None, dt: float | None = None,
                    method: str | None = None, partition: int = 32):
    """Build from a `control.StateSpace`: its B and D are the known-input matrix and feedthrough.

    The plant is ẋ = A x + B u + E w (continuous) or x⁺ = A x + B u + E w (discrete),
    y = C x + D u + F v, with w ∈ W, v ∈ V. ``statespace.B`` and ``statespace.D`` act on the
    known input u as in python-control, except the columns that ``noise_inputs`` selects: those
    inputs are the noise w, and their columns of ``statespace.B`` are E (then ``E`` is not given).

    A continuous model is sampled with period ``dt``; each ``method`` states what it assumes of
    the noise and gives an enclosure exactly under that assumption:

    * ``'bounded'`` (the default): w(t) ∈ W at every instant, any measurable signal (it may switch
      sign inside a sample interval). The system is x_{k+1} = e^{AΔ} x_k + B_d u_k + r_k with
      r_k in a sound outer bound of ∫_0^Δ e^{Aτ} E W dτ (`setsmooth.models.discretization.
      bounded_noise_set`: a zonotope from ``partition`` pieces of the interval plus a certified
      remainder box). Its E is the identity and its W that n-dimensional set.
    * ``'zoh'``: w is constant on every sample interval, equal to w_k ∈ W there (a noise that
      is itself sampled and held). E is ∫_0^Δ e^{Aτ} dτ E and W is unchanged. A noise that
      varies inside an interval can leave this model: the filter may then lose the true state.

    Known inputs are held constant over each sample interval (zero-order hold, a digital
    controller's convention, python-control's ``sample_system`` default) in both modes. 'foh'
    and 'tustin' are not offered: Tustin's rule is exact for no class of signals, so its sets
    would not enclose the increments, and a first-order-hold noise stays in W at every instant,
    which 'bounded' covers.

    Parameters
    ----------
    statespace : control.StateSpace
        Continuous or discrete. Its feedthrough D from a noise input must be zero (it would
        couple w and v, which the set-membership model treats as unrelated); from a known input
        it is the system's D.
    W : ConvexSet, keyword-only
        Range of the process noise w; bounded for 'bounded'.
    V : ConvexSet, keyword-only
        Range of the measurement noise v.
    E : array_like, optional, keyword-only
        Process-noise matrix (n × W.dim) of the plant as given (continuous or discrete); the
        identity by default (W.dim = n). Not with ``noise_inputs``, which selects it from B.
    F : array_like, optional, keyword-only
        Measurement-noise matrix (m × V.dim); the identity by default (V.dim = m).
    u : array_like of shape (T+1, n_u), or callable k -> (n_u,), optional, keyword-only
        Samples u_0..u_T of the known inputs, time first (required when the plant has known
        inputs); as in `LinearSystem`, T rows suffice without a feedthrough.
    noise_inputs : sequence of int, optional, keyword-only
        Indices of the statespace inputs that are noises w; the others are known inputs. None
        (default): every input is a known input.
    dt : float, optional, keyword-only
        Sampling time Δ: required for a continuous model; for a discrete one it must agree with
        ``statespace.dt`` (or supply it when that is ``True``, unspecified).
    method : {'bounded', 'zoh'}, optional, keyword-only
        Noise model of a continuous plant (above); must be None for a discrete one.
    partition : int, keyword-only
        Pieces of [0, Δ] for 'bounded': more is tighter, with more generators (the noise set has
        ``partition`` copies of W's generators plus n; 32 by default).

    Returns
    -------
    LinearSystem
        With ``dt`` set to the sampling time.

    Raises
    ------
    TypeError
        When ``statespace`` is not a `control.StateSpace`, or W/V not `ConvexSet`s.
    ValueError
        For a feedthrough from a noise input, a missing or disagreeing ``dt``, an unknown
        ``method`` (or one given with a discrete model), bad ``noise_inputs`` (or given with
        ``E``), ``W`` of the wrong dimension, missing or superfluous ``u``.

    Examples
    --------
    >>> import control, numpy as np, setsmooth as ss
    >>> plant = control.ss([[0.0, 1.0], [-4.0, -0.4]], [[0.0, 0.0], [1.0, 1.0]], [[1.0, 0.0]], 0)
    >>> system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-0.5], [0.5]), V=ss.Box([-0.1], [0.1]),
    ...                                          noise_inputs=[1], u=np.ones((21, 1)), dt=0.1)
    >>> system.n, system.n_u, system.W.dim, system.dt, system.has_input
    (2, 1, 2, 0.1, True)
    """
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
