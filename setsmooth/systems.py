"""Dynamical systems with bounded noises, and their simulation.

Linear systems follow the smoothing paper (13)–(14) (stability paper (1)–(2)):

    x_{k+1} = A_k x_k + B_k w_k + u_k,      w_k ∈ ⟦w⟧ = W,
    y_k     = C_k x_k + D_k v_k,            v_k ∈ ⟦v⟧ = V,

with A_k = Φ_k, B_k = Γ_k, C_k = Ξ_k, D_k = Ψ_k, and an optional known input term u_k = B_u u_k.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ._validation import as_matrix, as_vector
from .sets.base import ConvexSet

MatrixSpec = Any  # an array, a sequence of arrays indexed by k, or a callable k -> array


class _TimeVarying:
    """A matrix that is constant, a sequence indexed by k, or a callable of k; validated once."""

    def __init__(self, spec: MatrixSpec, name: str, rows: int | None, cols: int | None):
        self.name = name
        if callable(spec):
            first = as_matrix(spec(0), f"{name}(0)", rows, cols)
            self.shape = first.shape
            self._call = spec
            self._const = None
            self._seq = None
        elif _is_sequence_of_matrices(spec):
            seq = [as_matrix(m, f"{name}[{k}]", rows, cols) for k, m in enumerate(spec)]
            shapes = {m.shape for m in seq}
            if len(shapes) != 1:
                raise ValueError(f"{name}: every matrix of the sequence must have one shape, got {shapes}")
            self.shape = seq[0].shape
            self._seq, self._const, self._call = seq, None, None
        else:
            self._const = as_matrix(spec, name, rows, cols)
            self.shape = self._const.shape
            self._seq = self._call = None

    def __call__(self, k: int) -> np.ndarray:
        if self._const is not None:
            return self._const
        if self._seq is not None:
            if not 0 <= k < len(self._seq):
                raise IndexError(f"{self.name} is given for k in [0, {len(self._seq)}), asked for k = {k}")
            return self._seq[k]
        out = np.asarray(self._call(k), dtype=float).reshape(self.shape)
        return out

    @property
    def is_constant(self) -> bool:
        return self._const is not None


def _is_sequence_of_matrices(spec: Any) -> bool:
    if isinstance(spec, np.ndarray):
        return spec.ndim == 3
    if isinstance(spec, Sequence) and len(spec) and not isinstance(spec, str):
        return np.ndim(spec[0]) == 2 and np.ndim(spec) == 3
    return False


class LinearSystem:
    """x_{k+1} = A_k x_k + B_k w_k + u_k,  y_k = C_k x_k + D_k v_k, with w_k ∈ W, v_k ∈ V.

    Parameters
    ----------
    A, B, C, D : array_like, sequence of arrays, or callable k -> array
        Φ_k (n×n), Γ_k (n×p), Ξ_k (m×n), Ψ_k (m×q) of smoothing paper (13)–(14). A sequence is indexed
        by k; a callable is called with k.
    W, V : ConvexSet
        Ranges of the process noise (dim p) and the measurement noise (dim q).
    u : array_like of shape (T, n), or callable k -> (n,), optional
        Known input term added to x_{k+1} (B_u u_k already multiplied out). None means no input.

    Raises
    ------
    ValueError
        When dimensions of matrices and noise sets disagree.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> sys = ss.LinearSystem(np.eye(2), np.eye(2), [[1.0, 0.0]], [[1.0]],
    ...                       W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-1], [1]))
    >>> sys.n, sys.m
    (2, 1)
    """

    def __init__(self, A: MatrixSpec, B: MatrixSpec, C: MatrixSpec, D: MatrixSpec,
                 W: ConvexSet, V: ConvexSet, u: Any = None):
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
        self.A = _TimeVarying(A, "A", None, None)
        n = self.A.shape[0]
        if self.A.shape != (n, n):
            raise ValueError(f"A must be square, got shape {self.A.shape}")
        self.B = _TimeVarying(B, "B", n, W.dim)
        self.C = _TimeVarying(C, "C", None, n)
        m = self.C.shape[0]
        self.D = _TimeVarying(D, "D", m, V.dim)
        self.W, self.V = W, V
        self.n, self.m, self.p, self.q = n, m, W.dim, V.dim
        self._u = self._input(u)

    def _input(self, u: Any) -> Callable[[int], np.ndarray] | None:
        if u is None:
            return None
        if callable(u):
            return lambda k: as_vector(u(k), f"u({k})", self.n)
        arr = np.asarray(u, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != self.n:
            raise ValueError(f"u must have shape (T, n={self.n}) (the term added to x_(k+1)), "
                             f"got {arr.shape}")
        return lambda k: arr[k]

    @property
    def is_time_invariant(self) -> bool:
        return all(M.is_constant for M in (self.A, self.B, self.C, self.D)) and self._u is None

    def input_term(self, k: int) -> np.ndarray:
        """The known term u_k added to x_{k+1} (zeros without input)."""
        return np.zeros(self.n) if self._u is None else self._u(k)

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} for a realized process noise w_k."""
        return self.A(k) @ x + self.B(k) @ w + self.input_term(k)

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k for a realized measurement noise v_k."""
        return self.C(k) @ x + self.D(k) @ v

    @classmethod
    def from_statespace(cls, statespace, W: ConvexSet, V: ConvexSet, *, D: Any = None,
                        dt: float | None = None, method: str = "zoh") -> "LinearSystem":
        """Build from a `control.StateSpace` whose input is the process noise.

        Parameters
        ----------
        statespace : control.StateSpace
            x⁺ = A x + B w, y = C x. Its feedthrough must be zero (a w → y path would couple the two
            noises, which the set-membership model treats as unrelated). A continuous-time model is
            discretized with `control.c2d`.
        W, V : ConvexSet
            Ranges of the process noise (dim = number of inputs) and of the measurement noise.
        D : array_like, optional
            Measurement-noise matrix Ψ (m × V.dim); the identity by default.
        dt : float, optional
            Sampling time for a continuous model (required then).
        method : str
            Discretization method passed to `control.c2d` ('zoh', 'foh', 'tustin', ...).
        """
        import control

        if not isinstance(statespace, control.StateSpace):
            raise TypeError(f"statespace must be a control.StateSpace, got {type(statespace).__name__}")
        sys_d = statespace
        if statespace.isctime():
            if dt is None or not dt > 0:
                raise ValueError("dt must be a positive sampling time to discretize a continuous model")
            sys_d = control.c2d(statespace, dt, method=method)
        if np.any(np.asarray(sys_d.D) != 0):
            raise ValueError("statespace must have zero feedthrough D (noise w must not reach y directly)")
        m = np.asarray(sys_d.C).shape[0]
        Psi = np.eye(m) if D is None else D
        return cls(np.asarray(sys_d.A), np.asarray(sys_d.B), np.asarray(sys_d.C), Psi, W, V)


class NonlinearSystem:
    """x_{k+1} = f(k, x_k, w_k),  y_k = g(k, x_k, v_k), with w_k ∈ W, v_k ∈ V.

    Parameters
    ----------
    f, g : callable
        Transition and measurement functions of (k, x, noise), acting on 1-D arrays.
    W, V : ConvexSet
        Noise ranges.
    n : int
        State dimension.
    """

    def __init__(self, f: Callable, g: Callable, W: ConvexSet, V: ConvexSet, n: int):
        if not callable(f) or not callable(g):
            raise TypeError("f and g must be callables of (k, x, noise)")
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
        self.f, self.g, self.W, self.V, self.n = f, g, W, V, int(n)

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} = f(k, x_k, w_k) for a realized process noise (smoothing paper (4))."""
        return np.asarray(self.f(k, x, w), dtype=float).reshape(self.n)

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k = g(k, x_k, v_k) for a realized measurement noise (smoothing paper (5))."""
        return np.atleast_1d(np.asarray(self.g(k, x, v), dtype=float))


def simulate(system, x0_set: ConvexSet, T: int, rng: np.random.Generator,
             x0: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """Simulate a trajectory with noises drawn uniformly from their ranges.

    Parameters
    ----------
    system : LinearSystem or NonlinearSystem
    x0_set : ConvexSet
        ⟦x_0⟧; the initial state is drawn uniformly from it unless ``x0`` is given.
    T : int
        Final time step; states and measurements are returned for k = 0..T.
    rng : numpy.random.Generator
        The only source of randomness.
    x0 : array_like, optional
        A fixed initial state (must lie in ``x0_set``).

    Returns
    -------
    xs : ndarray, shape (T+1, n)
        True states x_0..x_T.
    ys : ndarray, shape (T+1, m)
        Measurements y_0..y_T.

    Notes
    -----
    Uniform draws use each set's ``sample``: direct for boxes and ellipsoids, rejection from the
    interval hull (one membership LP per proposal) otherwise. All draws are made up front in a fixed
    order (x_0, then w_0..w_{T-1}, then v_0..v_T), so a seed fixes the whole trajectory.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if isinstance(T, bool) or not isinstance(T, (int, np.integer)) or T < 0:
        raise ValueError(f"T must be a non-negative integer, got {T!r}")
    if not isinstance(x0_set, ConvexSet) or x0_set.dim != system.n:
        raise ValueError(f"x0_set must be a ConvexSet of dimension n = {system.n}")
    x = x0_set.sample(rng, 1)[0] if x0 is None else as_vector(x0, "x0", system.n)
    ws = system.W.sample(rng, T) if T > 0 else np.zeros((0, system.W.dim))
    vs = system.V.sample(rng, T + 1)
    xs = [x]
    for k in range(T):
        xs.append(system.step(k, xs[-1], ws[k]))
    ys = [system.measure(k, xs[k], vs[k]) for k in range(T + 1)]
    return np.array(xs), np.array(ys)
