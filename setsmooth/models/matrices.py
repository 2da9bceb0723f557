"""The matrices and the known input of a `LinearSystem`, checked once at its door.

x_{k+1} = A_k x_k + B_k u_k + E_k w_k,   y_k = C_k x_k + D_k u_k + F_k v_k: A, B, C, D as python-control
names them (B the known-input matrix, D the feedthrough), E, F the noise matrices as CORA's
``linearSysDT`` names them. Each matrix may be constant, a sequence indexed by k or a callable of k
(`TimeVarying`); the known input u is time-first, shape (T+1, n_u) like the measurements (y_T reads
u_T through D; without a feedthrough u_T is unused and T rows suffice), or a callable k -> (n_u,)
(`InputSequence`). The smoothing paper's Φ, Γ, Ξ, Ψ are A, E, C, F.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_matrix, as_vector, real_array, real_number
from ..sets.base import ConvexSet

MatrixSpec = Any  # an array, a sequence of arrays indexed by k, or a callable k -> array


class TimeVarying:
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
        elif is_sequence_of_matrices(spec):
            seq = [frozen(as_matrix(M, f"{name}[{k}]", rows, cols)) for k, M in enumerate(spec)]
            for k, M in enumerate(seq):
                if M.shape != seq[0].shape:
                    raise ValueError(f"{name}[{k}] has shape {M.shape} but {name}[0] has shape "
                                     f"{seq[0].shape}: every matrix of the sequence must have one shape")
            self._seq = seq
            self.shape = seq[0].shape
            self.label, self.kind = f"{name}[0]", f"sequence of {len(seq)}"
        else:
            self._const = frozen(as_matrix(spec, name, rows, cols))
            self.shape = self._const.shape
            self.label, self.kind = name, "constant"

    @classmethod
    def zeros(cls, name: str, rows: int, cols: int) -> "TimeVarying":
        """The constant zero matrix: B without a known input, D without a feedthrough."""
        return cls(np.zeros((rows, cols)), name, rows, cols)

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

    @property
    def is_zero(self) -> bool:
        """A constant zero matrix (an empty one included)."""
        return self._const is not None and not self._const.any()

    def constant(self) -> np.ndarray:
        """The matrix of a constant system; a time-varying one names the per-step accessor."""
        if self._const is None:
            raise ValueError(f"{self.name} is time-varying (a {self.kind}), so it is no single array: "
                             f"read {self.name}_k with system.{self.name}_at(k)")
        return self._const


def frozen(arr: np.ndarray) -> np.ndarray:
    """A read-only private copy: the system (and the noise images it caches) cannot change under us."""
    arr = np.array(arr, dtype=float, copy=True)
    arr.flags.writeable = False
    return arr


def is_sequence_of_matrices(spec: Any) -> bool:
    """A 3-D array, or a list/tuple whose first entry is 2-D (its entries are validated one by one)."""
    if isinstance(spec, np.ndarray):
        return spec.ndim == 3
    if isinstance(spec, (list, tuple)) and len(spec) and not isinstance(spec[0], str):
        try:
            return np.ndim(spec[0]) == 2
        except ValueError:  # a ragged first entry: as_matrix names it
            return False
    return False


class InputSequence:
    """The known input u_k: rows u[k] (time first) validated once, or a callable validated per call."""

    def __init__(self, u: Any, n_u: int):
        self.n_u = n_u
        self._rows = self._call = None
        if callable(u):
            as_vector(u(0), "u(0)", n_u)
            self._call = u
            return
        rows = real_array(u, "u", f"an array of shape (T+1, n_u={n_u})")
        if rows.ndim == 1 and n_u == 1:
            rows = rows[:, None]
        if rows.ndim == 2 and rows.shape[1] != n_u and rows.shape[0] == n_u:
            raise ValueError(f"u has shape {rows.shape}, python-control's orientation (inputs × time); "
                             f"setsmooth's arrays are time-first, shape (T+1, n_u={n_u}): pass u.T")
        if rows.ndim != 2 or rows.shape[1] != n_u:
            raise ValueError(f"u must have shape (T+1, n_u={n_u}), one row u_k per step k = 0..T (time "
                             f"first), got {rows.shape}")
        bad = np.flatnonzero(~np.isfinite(rows).all(axis=1))
        if bad.size:
            as_vector(rows[bad[0]], f"u[{bad[0]}]", n_u)  # raises, naming the first bad row
        self._rows = frozen(rows)

    def __call__(self, k: int) -> np.ndarray:
        if self._rows is not None:
            if not 0 <= k < len(self._rows):
                raise IndexError(f"u is given for k in [0, {len(self._rows)}), asked for k = {k}")
            return self._rows[k]
        return as_vector(self._call(k), f"u({k})", self.n_u)

    @property
    def kind(self) -> str:
        return "callable of k" if self._call is not None else f"{len(self._rows)} steps"

    def check_steps(self, T: int, feedthrough: bool) -> None:
        """Raise unless the rows cover steps 0..T: u_0..u_T with a feedthrough (y_T = C_T x_T + D_T u_T),
        u_0..u_{T−1} without (x_T = A x_{T−1} + B u_{T−1}); more rows are not used. A callable is
        checked at each call instead."""
        if self._rows is None:
            return
        needed = T + 1 if feedthrough else T
        if len(self._rows) >= needed:
            return
        shape = f"(T+1, n_u) = ({T + 1}, {self.n_u})"
        why = (f"the feedthrough D u_k enters every measurement, y_{T} included" if feedthrough else
               f"B u_k enters x_{{k+1}} for k = 0..{T - 1}; without a feedthrough u_{T} is not used, so "
               f"{T} rows suffice")
        raise ValueError(f"u must have shape {shape} for the measurements y_0..y_{T} ({why}), got "
                         f"{self._rows.shape}")


def known_input(B: MatrixSpec, D: MatrixSpec, u: Any, n: int,
                m: int) -> tuple[TimeVarying, TimeVarying, InputSequence | None]:
    """B, D and u checked together: both matrices act on u, so neither means anything without it.

    A B, or a nonzero D, without u is refused: it is most often the smoothing paper's Γ (Ψ) written
    where python-control's B (D) stands, which would otherwise be read silently as something else.
    """
    no_feedthrough = D is None or _is_zero_scalar(D)
    if u is None:
        if B is not None:
            raise ValueError("B is python-control's known-input matrix (x_{k+1} = A x_k + B u_k + E w_k) "
                             "and was given without the input sequence u= (shape (T+1, n_u), time first). "
                             "Pass u=, or B=None for no known input. A process-noise matrix (the "
                             "smoothing paper's Γ) goes in E=, a measurement-noise matrix (Ψ) in F=")
        if not no_feedthrough and not _is_zero_constant(D):
            raise ValueError("D is python-control's feedthrough (y_k = C x_k + D u_k + F v_k) and was "
                             "given nonzero without the input sequence u=. Pass u=, or D=None (or 0) "
                             "for no feedthrough. A measurement-noise matrix (the smoothing paper's Ψ) "
                             "goes in F=, a process-noise matrix (Γ) in E=")
        return TimeVarying.zeros("B", n, 0), TimeVarying.zeros("D", m, 0), None
    if B is None and no_feedthrough:
        raise ValueError("u= was given without B or D: u is the known input sequence, entering "
                         "x_{k+1} through B (n × n_u) and y_k through the feedthrough D (m × n_u). "
                         "Give B (B=np.eye(n) for an input term added to the state as it is)")
    if B is not None:
        B = TimeVarying(B, "B", n, None)
        n_u = B.shape[1]
        D = TimeVarying.zeros("D", m, n_u) if no_feedthrough else TimeVarying(D, "D", m, n_u)
    else:
        D = TimeVarying(D, "D", m, None)
        n_u = D.shape[1]
        B = TimeVarying.zeros("B", n, n_u)
    return B, D, InputSequence(u, n_u)


def _is_zero_scalar(spec: MatrixSpec) -> bool:
    """D = 0, python-control's "no feedthrough" (any size)."""
    if callable(spec) or np.ndim(spec) != 0 or isinstance(spec, (str, bytes)):
        return False
    return real_number(spec, "D") == 0.0


def _is_zero_constant(spec: MatrixSpec) -> bool:
    """A constant matrix of zeros (a sequence or a callable is not inspected)."""
    if _constant_shape(spec) is None:
        return False
    return not real_array(spec, "D").any()


def noise_matrix(spec: MatrixSpec, name: str, set_name: str, S: ConvexSet, rows: int) -> TimeVarying:
    """E (F): one column per coordinate of W (V); None is the identity, which needs dim W = n (dim V = m)."""
    if spec is None:
        if S.dim != rows:
            state = "n" if name == "E" else "m"
            noise = "process" if name == "E" else "measurement"
            raise ValueError(f"{name}=None means {name} = I, which needs {set_name}.dim = {state} = {rows}, "
                             f"got {set_name}.dim = {S.dim}: give the {noise}-noise matrix {name}= "
                             f"({rows} × {S.dim})")
        return TimeVarying(np.eye(rows), name, rows, rows)
    M = TimeVarying(spec, name, rows, None)
    if M.shape[1] != S.dim:
        raise ValueError(f"{name} must have {set_name}.dim = {S.dim} columns (one per coordinate of the "
                         f"noise), got shape {M.shape}; check {name} and {set_name}")
    return M


def check_state_dimension(A: TimeVarying, E: MatrixSpec, C: MatrixSpec) -> None:
    """Blame A when E and C, given as constant matrices, agree with each other on n and not with A.

    Otherwise E's and C's own checks name them: n is read from A, so without this a wrong A (say a
    callable of the wrong size) would be reported as a wrong E.
    """
    rows_E, cols_C = _constant_shape(E), _constant_shape(C)
    if rows_E is None or cols_C is None:
        return
    n = rows_E[0]
    if cols_C[1] == n != A.shape[0]:
        raise ValueError(f"{A.label} has shape {A.shape}, but E has {n} rows and C has {n} columns: "
                         f"A must be {n}×{n} (n = {n} states); check A")


def _constant_shape(spec: MatrixSpec) -> tuple[int, ...] | None:
    """The shape of a matrix given as a constant 2-D array, or None (callables, sequences, others)."""
    if spec is None or callable(spec) or is_sequence_of_matrices(spec):
        return None
    try:
        shape = np.shape(spec)
    except ValueError:  # ragged: its own check names it
        return None
    return shape if len(shape) == 2 else None
