"""A linear system with bounded noises: `LinearSystem`.

Linear systems in python-control's and CORA's names (`setsmooth.models.matrices`):

    x_{k+1} = A_k x_k + B_k u_k + E_k w_k,      w_k ∈ ⟦w⟧ = W,
    y_k     = C_k x_k + D_k u_k + F_k v_k,      v_k ∈ ⟦v⟧ = V,

with u_k a known input; the smoothing paper (13)–(14) (stability paper (1)–(2)) has no known input
and names Φ_k = A_k, Γ_k = E_k, Ξ_k = C_k, Ψ_k = F_k.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from .._validation import given_instead_of_set, real_number
from ..sets.algebra import linear_map
from ..sets.base import ConvexSet
from .matrices import MatrixSpec, TimeVarying, check_state_dimension, known_input, noise_matrix
from .statespace import from_statespace


class LinearSystem:
    """x_{k+1} = A_k x_k + B_k u_k + E_k w_k,  y_k = C_k x_k + D_k u_k + F_k v_k, w_k ∈ W, v_k ∈ V.

    A, B, C, D mean what they mean in python-control (B the known-input matrix, D the
    feedthrough); E and F are the noise matrices, named as in CORA's ``linearSysDT``. In the
    smoothing paper (13)–(14) (stability paper (1)–(2)) they are Φ_k = A_k, Γ_k = E_k, Ξ_k = C_k,
    Ψ_k = F_k, without the known input (``docs/migration.md`` maps the names).

    Arrays over time are time-first throughout setsmooth: the input ``u`` has shape (T+1, n_u), the
    measurements ``ys`` (T+1, m), the states ``xs`` (T+1, n), one row per step k = 0..T (without a
    feedthrough u_T is not used, and T rows of ``u`` suffice). python-control's (signals × time)
    arrays are refused with a message saying so, never transposed by guessing.

    Parameters
    ----------
    A : array_like, sequence of arrays, or callable k -> array
        A_k (n×n). Every matrix may be constant, a sequence indexed by k, or a callable of k whose
        value is checked at every call (real, finite, the shape of its value at k = 0).
    B : array_like, sequence, callable, or None
        B_k (n×n_u), the known-input matrix; None: no input enters the state. Requires ``u``.
    C : array_like, sequence, or callable
        C_k (m×n).
    D : array_like, sequence, callable, or None
        D_k (m×n_u), the feedthrough of the known input; None or 0: none. A nonzero D requires ``u``.
    E : array_like, sequence, callable, or None, keyword-only
        E_k (n×p), the process-noise matrix; None: the identity (then W.dim must be n).
    F : array_like, sequence, callable, or None, keyword-only
        F_k (m×q), the measurement-noise matrix; None: the identity (then V.dim must be m).
    W, V : ConvexSet, keyword-only
        Ranges of the process noise (dim p) and the measurement noise (dim q).
    u : array_like of shape (T+1, n_u), or callable k -> (n_u,), optional, keyword-only
        The known input u_0..u_T (time first), a row per measurement y_0..y_T: it enters x_{k+1}
        through B and y_k through D, so y_T = C_T x_T + D_T u_T reads u_T. Without a feedthrough
        u_T is not used and T rows suffice; more rows than the data need are not used. The
        estimators and `simulate` check the rows against their T. Requires B or D.
    dt : float, optional, keyword-only
        Sampling time in seconds, when the steps sample a continuous-time plant (`from_statespace`
        sets it); kept for time axes, not used by the estimators. None: unspecified.

    Attributes
    ----------
    A, B, C, D, E, F : ndarray
        The matrices of a constant system, read-only (B is n×0 and D m×0 without input, E and F
        the identity when not given). For a time-varying matrix reading the attribute raises,
        naming the per-step accessor: `A_at` (k), `B_at`, `C_at`, `D_at`, `E_at`, `F_at`.
    n, m, n_u, p, q : int
        Dimensions of the state, the measurement, the known input, W and V.

    Raises
    ------
    TypeError
        When a matrix or input is complex or not numeric, or W/V is not a `ConvexSet`.
    ValueError
        When B, or a nonzero D, is given without ``u`` (the message says that B is python-control's
        known-input matrix and that the noise matrices go in ``E=`` and ``F=``), ``u`` without B or
        D, ``u`` in python-control's (n_u, T+1) orientation; when E or F is None and W or V is not of
        dimension n or m; when dimensions of matrices and noise sets disagree, or a value is NaN or
        infinite; the message names it as given (``A``, ``A[2]`` for a sequence, ``A(0)`` for a
        callable, ``u[3]``).

    Notes
    -----
    The system is picklable whenever its callables are (module-level functions or
    `functools.partial` objects, not lambdas), so it can be sent to a process pool.

    The estimators subtract the feedthrough D_k u_k from the measurements once, at their door
    (`without_feedthrough`); their results then record that system and those measurements.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> sys = ss.LinearSystem(np.eye(2), None, [[1.0, 0.0]], W=ss.Box([-1, -1], [1, 1]),
    ...                       V=ss.Box([-1], [1]))
    >>> sys.n, sys.m, sys.E.tolist()
    (2, 1, [[1.0, 0.0], [0.0, 1.0]])
    >>> sys = ss.LinearSystem(np.eye(2), [[0.0], [1.0]], [[1.0, 0.0]], 0, E=[[1.0], [0.5]],
    ...                       W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), u=np.ones((11, 1)))
    >>> sys.n_u, sys.B_at(3).shape
    (1, (2, 1))
    """

    def __init__(self, A: MatrixSpec, B: MatrixSpec, C: MatrixSpec, D: MatrixSpec = None, *,
                 E: MatrixSpec = None, F: MatrixSpec = None, W: ConvexSet, V: ConvexSet,
                 u: Any = None, dt: float | None = None):
        for name, S in (("W", W), ("V", V)):
            if not isinstance(S, ConvexSet):
                raise TypeError(f"{name} must be a ConvexSet, {given_instead_of_set(S, name)}")
        self._A = TimeVarying(A, "A", None, None)
        n = self._A.shape[0]
        if self._A.shape != (n, n):
            raise ValueError(f"{self._A.label} must be square, got shape {self._A.shape}")
        check_state_dimension(self._A, E, C)
        self._C = TimeVarying(C, "C", None, n)
        m = self._C.shape[0]
        self._B, self._D, self._u = known_input(B, D, u, n, m)  # first: Γ or Ψ given as B or D
        self._E = noise_matrix(E, "E", "W", W, n)
        self._F = noise_matrix(F, "F", "V", V, m)
        self.W, self.V = W, V
        self.n, self.m, self.n_u, self.p, self.q = n, m, self._B.shape[1], W.dim, V.dim
        self.dt = None if dt is None else real_number(dt, "dt")
        if self.dt is not None and not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be a positive finite sampling time or None, got {dt!r}")
        self._images: dict[str, ConvexSet] = {}
        self._no_feedthrough: LinearSystem | None = None

    # -- the matrices: arrays when constant, per step always ----------------------------------------
    A = property(lambda self: self._A.constant(), doc="A (n×n) of a constant system; else see `A_at`.")
    B = property(lambda self: self._B.constant(), doc="B (n×n_u), the known-input matrix; see `B_at`.")
    C = property(lambda self: self._C.constant(), doc="C (m×n) of a constant system; else see `C_at`.")
    D = property(lambda self: self._D.constant(), doc="D (m×n_u), the feedthrough; see `D_at`.")
    E = property(lambda self: self._E.constant(), doc="E (n×p), the process-noise matrix; see `E_at`.")
    F = property(lambda self: self._F.constant(), doc="F (m×q), the measurement-noise matrix; see `F_at`.")

    def A_at(self, k: int) -> np.ndarray:
        """A_k (Φ_k of the smoothing paper)."""
        return self._A(k)

    def B_at(self, k: int) -> np.ndarray:
        """B_k, the known-input matrix."""
        return self._B(k)

    def C_at(self, k: int) -> np.ndarray:
        """C_k (Ξ_k of the smoothing paper)."""
        return self._C(k)

    def D_at(self, k: int) -> np.ndarray:
        """D_k, the feedthrough of the known input."""
        return self._D(k)

    def E_at(self, k: int) -> np.ndarray:
        """E_k, the process-noise matrix (Γ_k of the smoothing paper)."""
        return self._E(k)

    def F_at(self, k: int) -> np.ndarray:
        """F_k, the measurement-noise matrix (Ψ_k of the smoothing paper)."""
        return self._F(k)

    def _matrices(self):
        return (self._A, self._B, self._C, self._D, self._E, self._F)

    def __repr__(self) -> str:
        varying = [f"{M.name}: {M.kind}" for M in self._matrices() if not M.is_constant]
        parts = [f"n={self.n}", f"m={self.m}"]
        if self._u is not None:
            parts.append(f"n_u={self.n_u}")
        parts += [f"W={self.W!r}", f"V={self.V!r}"]
        parts.append("time-varying " + ", ".join(varying) if varying else "constant matrices")
        if self._u is not None:
            parts.append(f"input u: {self._u.kind}" + ("" if self.has_feedthrough else ", no feedthrough"))
        if self.dt is not None:
            parts.append(f"dt={self.dt:g}")
        return f"LinearSystem({', '.join(parts)})"

    # -- pickling: the cached noise images and feedthrough-free twin are recomputed on demand --------
    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_images"], state["_no_feedthrough"] = {}, None
        return state

    def _with_noises(self, W: ConvexSet, V: ConvexSet) -> "LinearSystem":
        """The same matrices with noise ranges W, V (trusted: of this system's p and q) and no input.

        The deviation form about a nominal trajectory (`setsmooth.trajectories.nominal`).
        """
        other = copy.copy(self)
        other.W, other.V, other._u, other._images, other._no_feedthrough = W, V, None, {}, None
        return other

    @property
    def time_varying(self) -> tuple[str, ...]:
        """The names of the matrices given as sequences or callables of k (empty when all are constant)."""
        return tuple(M.name for M in self._matrices() if not M.is_constant)

    @property
    def is_time_invariant(self) -> bool:
        return all(M.is_constant for M in self._matrices()) and self._u is None

    @property
    def has_input(self) -> bool:
        """Whether a known input u was given."""
        return self._u is not None

    @property
    def has_feedthrough(self) -> bool:
        """Whether the known input reaches the measurements (D given and not a constant zero)."""
        return self._u is not None and not self._D.is_zero

    def check_input(self, T: int) -> None:
        """Raise unless the known input covers the measurements y_0..y_T: u_0..u_T with a feedthrough
        (y_T reads D_T u_T), u_0..u_{T−1} without; checked once at the estimators' door and in
        `simulate`, so a short ``u`` is named there with the shape expected and the shape given.

        Parameters
        ----------
        T : int
            The last step of the data (measurements y_0..y_T).

        Raises
        ------
        ValueError
            Naming ``u``, the shape (T+1, n_u) and the shape given.
        """
        if self._u is not None:
            self._u.check_steps(T, self.has_feedthrough)

    def input_term(self, k: int) -> np.ndarray:
        """B_k u_k, the known term of x_{k+1} (zeros without input)."""
        return np.zeros(self.n) if self._u is None else self._B(k) @ self._u(k)

    def nonzero_input(self, k: int) -> np.ndarray | None:
        """B_k u_k, or None when there is no input or it is 0: a zero term is no translation to make."""
        if self._u is None:
            return None
        term = self.input_term(k)
        return term if term.any() else None

    def feedthrough_term(self, k: int) -> np.ndarray:
        """D_k u_k, the known term of y_k (zeros without a feedthrough)."""
        return self._D(k) @ self._u(k) if self.has_feedthrough else np.zeros(self.m)

    def without_feedthrough(self, ys: Any) -> tuple["LinearSystem", np.ndarray]:
        """This system without D and the measurements ys − D_k u_k: the same sets for every estimator.

        The estimators' door (`setsmooth._validation.measured`) calls it once, so inside them y_k
        = C_k x_k + F_k v_k. The returned system is one object per system (their results can be
        checked against each other) and has no feedthrough, so a second call changes nothing.

        Parameters
        ----------
        ys : ndarray, shape (T+1, m)
            Measurements, already checked (time first).
        """
        if not self.has_feedthrough:
            return self, ys
        offsets = np.array([self.feedthrough_term(k) for k in range(len(ys))])
        if self._no_feedthrough is None:
            other = copy.copy(self)
            other._D, other._no_feedthrough = TimeVarying.zeros("D", self.m, self.n_u), None
            self._no_feedthrough = other
        return self._no_feedthrough, ys - offsets

    def process_noise_image(self, k: int, *, negated: bool = False) -> ConvexSet:
        """E_k W (or E_k(−W), the smoother's term in smoothing (15)), computed once when E is constant.

        Parameters
        ----------
        k : int
        negated : bool
            Return E_k(−W) instead of E_k W.

        Returns
        -------
        ConvexSet
            Built by the trusted set algebra from matrices this system validated: the same set
            ``E_at(k) @ W`` (``E_at(k) @ -W``) gives, shared by every step when E is constant.
        """
        key = "-EW" if negated else "EW"
        image = self._images.get(key)
        if image is None:
            W = linear_map(-np.eye(self.p), self.W) if negated else self.W
            image = linear_map(self._E(k), W)
            if self._E.is_constant:
                self._images[key] = image
        return image

    def measurement_noise_image(self, k: int) -> ConvexSet:
        """F_k(−V), the set y_k − C_k x_k must lie in (stability (4)), computed once when F is constant."""
        image = self._images.get("-FV")
        if image is None:
            image = linear_map(self._F(k), linear_map(-np.eye(self.q), self.V))
            if self._F.is_constant:
                self._images["-FV"] = image
        return image

    def step(self, k: int, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """x_{k+1} = A_k x_k + B_k u_k + E_k w_k for a realized process noise w_k."""
        return self._A(k) @ x + self.input_term(k) + self._E(k) @ w

    def measure(self, k: int, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """y_k = C_k x_k + D_k u_k + F_k v_k for a realized measurement noise v_k."""
        return self._C(k) @ x + self.feedthrough_term(k) + self._F(k) @ v

    # Build from a `control.StateSpace`: written, with its documentation, where the conversion from
    # python-control lives (`setsmooth.models.statespace`).
    from_statespace = classmethod(from_statespace)
