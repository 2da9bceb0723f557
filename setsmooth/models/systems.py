"""Dynamical systems with bounded noises, and their simulation.

Linear systems follow the smoothing paper (13)–(14) (stability paper (1)–(2)):

    x_{k+1} = A_k x_k + B_k w_k + u_k,      w_k ∈ ⟦w⟧ = W,
    y_k     = C_k x_k + D_k v_k,            v_k ∈ ⟦v⟧ = V,

with A_k = Φ_k, B_k = Γ_k, C_k = Ξ_k, D_k = Ψ_k, and an optional known input term u_k = B_u u_k.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import (as_generator, as_matrix, as_vector, check_dim, check_system, real_array,
                           real_number)
from ..sets.algebra import linear_map
from ..sets.base import ConvexSet

MatrixSpec = Any  # an array, a sequence of arrays indexed by k, or a callable k -> array


class _TimeVarying:
    """A matrix that is constant, a sequence indexed by k, or a callable of k.

    Constants and sequences are validated once, here. A callable is validated at every call (real,
    finite, exactly the shape of its value at k = 0; never reshaped): cheap next to the set algebra
    the value feeds, and the only way to name the step, ``A(2)``, at which a value goes bad. The
    object holds nothing but the user's data, so it pickles whenever that data does (a module-level
    callable, a `functools.partial` of one, arrays).
    """

    def __init__(self, spec: MatrixSpec, name: str, rows: int | None, cols: int | None):
        self.name = name
        self._const = self._seq = self._call = None
        if callable(spec):
            self.shape = as_matrix(spec(0), f"{name}(0)", rows, cols).shape
            self._call = spec
            self.label, self.kind = f"{name}(0)", "callable of k"
        elif _is_sequence_of_matrices(spec):
            seq = [_frozen(as_matrix(M, f"{name}[{k}]", rows, cols)) for k, M in enumerate(spec)]
            for k, M in enumerate(seq):
                if M.shape != seq[0].shape:
                    raise ValueError(f"{name}[{k}] has shape {M.shape} but {name}[0] has shape "
                                     f"{seq[0].shape}: every matrix of the sequence must have one shape")
            self._seq = seq
            self.shape = seq[0].shape
            self.label, self.kind = f"{name}[0]", f"sequence of {len(seq)}"
        else:
            self._const = _frozen(as_matrix(spec, name, rows, cols))
            self.shape = self._const.shape
            self.label, self.kind = name, "constant"

    def __call__(self, k: int) -> np.ndarray:
        if self._const is not None:
            return self._const
        if self._seq is not None:
            if not 0 <= k < len(self._seq):
                raise IndexError(f"{self.name} is given for k in [0, {len(self._seq)}), asked for k = {k}")
            return self._seq[k]
        return as_matrix(self._call(k), f"{self.name}({k})", *self.shape)

    @property
    def is_constant(self) -> bool:
        return self._const is not None


def _frozen(arr: np.ndarray) -> np.ndarray:
    """A read-only private copy: the system (and the noise images it caches) cannot change under us."""
    arr = np.array(arr, dtype=float, copy=True)
    arr.flags.writeable = False
    return arr


def _is_sequence_of_matrices(spec: Any) -> bool:
    """A 3-D array, or a list/tuple whose first entry is 2-D (its entries are validated one by one)."""
    if isinstance(spec, np.ndarray):
        return spec.ndim == 3
    if isinstance(spec, (list, tuple)) and len(spec) and not isinstance(spec[0], str):
        try:
            return np.ndim(spec[0]) == 2
        except ValueError:  # a ragged first entry: as_matrix names it
            return False
    return False


class _InputTerm:
    """The known term u_k: an array of rows u[k] validated once, or a callable validated per call."""

    def __init__(self, u: Any, n: int):
        self.n = n
        self._rows = self._call = None
        if callable(u):
            as_vector(u(0), "u(0)", n)
            self._call = u
            return
        rows = real_array(u, "u", f"an array of shape (T, n={n})")
        if rows.ndim != 2 or rows.shape[1] != n:
            raise ValueError(f"u must have shape (T, n={n}) (the term added to x_(k+1)), got {rows.shape}")
        bad = np.flatnonzero(~np.isfinite(rows).all(axis=1))
        if bad.size:
            as_vector(rows[bad[0]], f"u[{bad[0]}]", n)  # raises, naming the first bad row
        self._rows = _frozen(rows)

    def __call__(self, k: int) -> np.ndarray:
        if self._rows is not None:
            if not 0 <= k < len(self._rows):
                raise IndexError(f"u is given for k in [0, {len(self._rows)}), asked for k = {k}")
            return self._rows[k]
        return as_vector(self._call(k), f"u({k})", self.n)


def _check_state_dimension(A: _TimeVarying, B: MatrixSpec, C: MatrixSpec) -> None:
    """Blame A when B and C, given as constant matrices, agree with each other on n and not with A.

    Otherwise B's and C's own checks name them: n is read from A, so without this a wrong A (say a
    callable of the wrong size) would be reported as a wrong B.
    """
    rows_B, cols_C = _constant_shape(B), _constant_shape(C)
    if rows_B is None or cols_C is None:
        return
    n = rows_B[0]
    if cols_C[1] == n != A.shape[0]:
        raise ValueError(f"{A.label} has shape {A.shape}, but B has {n} rows and C has {n} columns: "
                         f"A must be {n}×{n} (n = {n} states); check A")


def _constant_shape(spec: MatrixSpec) -> tuple[int, ...] | None:
    """The shape of a matrix given as a constant 2-D array, or None (callables, sequences, others)."""
    if callable(spec) or _is_sequence_of_matrices(spec):
        return None
    try:
        shape = np.shape(spec)
    except ValueError:  # ragged: its own check names it
        return None
    return shape if len(shape) == 2 else None


def _check_noise_columns(M: _TimeVarying, set_name: str, S: ConvexSet) -> None:
    """Γ must have one column per coordinate of W (Ψ: of V); the message names both."""
    if M.shape[1] != S.dim:
        raise ValueError(f"{M.name} must have {set_name}.dim = {S.dim} columns (one per coordinate of the "
                         f"noise), got shape {M.shape}; check {M.name} and {set_name}")


class LinearSystem:
    """x_{k+1} = A_k x_k + B_k w_k + u_k,  y_k = C_k x_k + D_k v_k, with w_k ∈ W, v_k ∈ V.

    Parameters
    ----------
    A, B, C, D : array_like, sequence of arrays, or callable k -> array
        Φ_k (n×n), Γ_k (n×p), Ξ_k (m×n), Ψ_k (m×q) of smoothing paper (13)–(14). A sequence is indexed
        by k; a callable is called with k, and its value is checked at every call (real, finite, the
        shape of its value at k = 0).
    W, V : ConvexSet
        Ranges of the process noise (dim p) and the measurement noise (dim q).
    u : array_like of shape (T, n), or callable k -> (n,), optional
        Known input term added to x_{k+1} (B_u u_k already multiplied out). None means no input.
    dt : float, optional
        Sampling time in seconds, when the steps sample a continuous-time plant (`from_statespace`
        sets it); kept for time axes, not used by the estimators. None: unspecified.

    Raises
    ------
    TypeError
        When a matrix or input is complex or not numeric, or W/V is not a `ConvexSet`.
    ValueError
        When dimensions of matrices and noise sets disagree, or a value is NaN or infinite; the
        message names it as given (``A``, ``A[2]`` for a sequence, ``A(0)`` for a callable, ``u[3]``).

    Notes
    -----
    The system is picklable whenever its callables are (module-level functions or
    `functools.partial` objects, not lambdas), so it can be sent to a process pool.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> sys = ss.LinearSystem(np.eye(2), np.eye(2), [[1.0, 0.0]], [[1.0]],
    ...                       W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-1], [1]))
    >>> sys.n, sys.m
    (2, 1)
    """

    def __init__(self, A: MatrixSpec, B: MatrixSpec, C: MatrixSpec, D: MatrixSpec,
                 W: ConvexSet, V: ConvexSet, u: Any = None, dt: float | None = None):
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
        self.A = _TimeVarying(A, "A", None, None)
        n = self.A.shape[0]
        if self.A.shape != (n, n):
            raise ValueError(f"{self.A.label} must be square, got shape {self.A.shape}")
        _check_state_dimension(self.A, B, C)
        self.B = _TimeVarying(B, "B", n, None)
        _check_noise_columns(self.B, "W", W)
        self.C = _TimeVarying(C, "C", None, n)
        m = self.C.shape[0]
        self.D = _TimeVarying(D, "D", m, None)
        _check_noise_columns(self.D, "V", V)
        self.W, self.V = W, V
        self.n, self.m, self.p, self.q = n, m, W.dim, V.dim
        self._u = None if u is None else _InputTerm(u, n)
        self.dt = None if dt is None else real_number(dt, "dt")
        if self.dt is not None and not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be a positive finite sampling time or None, got {dt!r}")
        self._images: dict[str, ConvexSet] = {}

    def __repr__(self) -> str:
        varying = [f"{M.name}: {M.kind}" for M in (self.A, self.B, self.C, self.D) if not M.is_constant]
        parts = [f"n={self.n}", f"m={self.m}", f"W={self.W!r}", f"V={self.V!r}"]
        parts.append("time-varying " + ", ".join(varying) if varying else "constant A, B, C, D")
        if self._u is not None:
            parts.append("input u: " + ("callable of k" if self._u._call is not None
                                        else f"{len(self._u._rows)} steps"))
        if self.dt is not None:
            parts.append(f"dt={self.dt:g}")
        return f"LinearSystem({', '.join(parts)})"

    # -- pickling: the cached noise images are recomputed on demand ------------------------------
    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_images"] = {}
        return state

    def _with_noises(self, W: ConvexSet, V: ConvexSet) -> "LinearSystem":
        """The same matrices with noise ranges W, V (trusted: of this system's p and q) and no input.

        The deviation form about a nominal trajectory (`setsmooth.trajectories.nominal`).
        """
        other = copy.copy(self)
        other.W, other.V, other._u, other._images = W, V, None, {}
        return other

    @property
    def is_time_invariant(self) -> bool:
        return all(M.is_constant for M in (self.A, self.B, self.C, self.D)) and self._u is None

    @property
    def has_input(self) -> bool:
        """Whether a known input term u was given."""
        return self._u is not None

    def input_term(self, k: int) -> np.ndarray:
        """The known term u_k added to x_{k+1} (zeros without input)."""
        return np.zeros(self.n) if self._u is None else self._u(k)

    def nonzero_input(self, k: int) -> np.ndarray | None:
        """u_k, or None when there is no input or u_k = 0: a zero term is no translation to make."""
        if self._u is None:
            return None
        u = self._u(k)
        return u if u.any() else None

    def process_noise_image(self, k: int, *, negated: bool = False) -> ConvexSet:
        """Γ_k W (or Γ_k(−W), the smoother's term in smoothing (15)), computed once when Γ is constant.

        Parameters
        ----------
        k : int
        negated : bool
            Return Γ_k(−W) instead of Γ_k W.

        Returns
        -------
        ConvexSet
            Built by the trusted set algebra from matrices this system validated: the same set
            ``B(k) @ W`` (``B(k) @ -W``) gives, shared by every step when B is constant.
        """
        key = "-BW" if negated else "BW"
        image = self._images.get(key)
        if image is None:
            W = linear_map(-np.eye(self.p), self.W) if negated else self.W
            image = linear_map(self.B(k), W)
            if self.B.is_constant:
                self._images[key] = image
        return image

    def measurement_noise_image(self, k: int) -> ConvexSet:
        """Ψ_k(−V), the set y_k − C_k x_k must lie in (stability (4)), computed once when Ψ is constant."""
        image = self._images.get("-DV")
        if image is None:
            image = linear_map(self.D(k), linear_map(-np.eye(self.q), self.V))
            if self.D.is_constant:
                self._images["-DV"] = image
        return image

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} for a realized process noise w_k."""
        return self.A(k) @ x + self.B(k) @ w + self.input_term(k)

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k for a realized measurement noise v_k."""
        return self.C(k) @ x + self.D(k) @ v

    @classmethod
    def from_statespace(cls, statespace, W: ConvexSet, V: ConvexSet, *, noise_inputs: Any = None,
                        inputs: Any = None, Psi: Any = None, dt: float | None = None,
                        method: str | None = None, partition: int = 32) -> "LinearSystem":
        """Build from a `control.StateSpace` whose inputs are noises w and, optionally, known inputs.

        The plant is ẋ = A x + B_w w + B_u u (continuous) or x⁺ = A x + B_w w + B_u u (discrete),
        y = C x, with B_w, B_u the columns of ``statespace.B`` selected by ``noise_inputs`` and the
        others. The measurement is y_k = C x_k + Ψ v_k with v_k ∈ V.

        A continuous model is sampled with period ``dt``; each ``method`` states what it assumes of
        the noise and gives an enclosure exactly under that assumption:

        * ``'bounded'`` (the default): w(t) ∈ W at every instant, any measurable signal (it may switch
          sign inside a sample interval). The system is x_{k+1} = e^{AΔ} x_k + r_k + Γ_u u_k with
          r_k in a sound outer bound of ∫_0^Δ e^{Aτ} B_w W dτ (`setsmooth.models.discretization.
          bounded_noise_set`: a zonotope from ``partition`` pieces of the interval plus a certified
          remainder box). Its B is the identity and its W that n-dimensional set.
        * ``'zoh'``: w is constant on every sample interval, equal to w_k ∈ W there (a noise that
          is itself sampled and held). B is ∫_0^Δ e^{Aτ} dτ B_w and W is unchanged. A noise that
          varies inside an interval can leave this model: the filter may then lose the true state.

        Known inputs are held constant over each sample interval (zero-order hold, a digital
        controller's convention) in both modes. 'foh' and 'tustin' are not offered: Tustin's
        rule is exact for no class of signals, so its sets would not enclose the increments, and a
        first-order-hold noise stays in W at every instant, which 'bounded' covers.

        Parameters
        ----------
        statespace : control.StateSpace
            Continuous or discrete. Its feedthrough D must be zero: from a noise input it would couple
            w and v, which the set-membership model treats as unrelated; from a known input, subtract
            D u_k from the measurements first.
        W : ConvexSet
            Range of the noise inputs (dim = len(noise_inputs)); bounded for 'bounded'.
        V : ConvexSet
            Range of the measurement noise v.
        noise_inputs : sequence of int, optional
            Indices of the statespace inputs that are noises w; the others are known inputs. None
            (default): every input is a noise.
        inputs : array_like of shape (T, number of known inputs), or callable k -> array, optional
            Samples u_k of the known inputs (required when there are known inputs). The system's
            known term is Γ_u u_k (`LinearSystem`'s ``u``).
        Psi : array_like, optional
            Measurement-noise matrix Ψ (m × V.dim) of y_k = C x_k + Ψ v_k; the identity by default.
            (It is the system's ``D``, smoothing paper (14); ``statespace.D`` is the feedthrough.)
        dt : float, optional
            Sampling time Δ: required for a continuous model; for a discrete one it must agree with
            ``statespace.dt`` (or supply it when that is ``True``, unspecified).
        method : {'bounded', 'zoh'}, optional
            Noise model of a continuous plant (above); must be None for a discrete one.
        partition : int
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
            For a nonzero feedthrough, a missing or disagreeing ``dt``, an unknown ``method`` (or
            one given with a discrete model), bad ``noise_inputs``, ``W`` of the wrong dimension,
            missing or superfluous ``inputs``.

        Examples
        --------
        >>> import control, numpy as np, setsmooth as ss
        >>> plant = control.ss([[0.0, 1.0], [-4.0, -0.4]], [[0.0, 0.0], [1.0, 1.0]], [[1.0, 0.0]], 0)
        >>> system = ss.LinearSystem.from_statespace(plant, ss.Box([-0.5], [0.5]), ss.Box([-0.1], [0.1]),
        ...                                          noise_inputs=[1], inputs=np.ones((20, 1)), dt=0.1)
        >>> system.n, system.W.dim, system.dt, system.has_input
        (2, 2, 0.1, True)
        """
        from .statespace import linear_system_from_statespace

        return linear_system_from_statespace(cls, statespace, W, V, noise_inputs=noise_inputs,
                                             inputs=inputs, Psi=Psi, dt=dt, method=method,
                                             partition=partition)


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

    Raises
    ------
    TypeError
        When f or g is not callable, W or V is not a `ConvexSet`, or n is not an integer.
    ValueError
        When n < 1. `step` and `measure` raise naming ``f(k, x, w)``/``g(k, x, v)`` when a value is
        complex (TypeError), NaN/inf or of the wrong length (ValueError).
    """

    def __init__(self, f: Callable, g: Callable, W: ConvexSet, V: ConvexSet, n: int):
        if not callable(f) or not callable(g):
            raise TypeError("f and g must be callables of (k, x, noise)")
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, got {type(S).__name__}")
        self.f, self.g, self.W, self.V, self.n = f, g, W, V, check_dim(n, "n")

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} = f(k, x_k, w_k) for a realized process noise (smoothing paper (4))."""
        return as_vector(self.f(k, x, w), f"f({k}, x, w)", self.n)

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k = g(k, x_k, v_k) for a realized measurement noise (smoothing paper (5))."""
        return as_vector(self.g(k, x, v), f"g({k}, x, v)")


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
        The only source of randomness: a Generator, or an int seed of ``numpy.random.default_rng``;
        may be None when ``x0``, ``ws`` and ``vs`` are all given.
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
        `LinearSystem.from_statespace`), ``rng`` is neither a Generator nor an int seed, ``T`` not an
        integer, or ``x0`` complex or not numeric.
    ValueError
        When ``T < 0``, ``x0_set`` has the wrong dimension, or ``x0`` is NaN/inf, of the wrong length
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
    if not isinstance(x0_set, ConvexSet) or x0_set.dim != system.n:
        raise ValueError(f"x0_set must be a ConvexSet of dimension n = {system.n}")
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
