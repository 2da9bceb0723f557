"""Argument checks made once, at the public door (internal ``_op`` variants trust their inputs).

Every check names the argument as the user passed it (``A(2)`` for a callable evaluated at k = 2,
``A[2]`` for an entry of a sequence, ``u[3]``). Complex input is a `TypeError` everywhere: NumPy's
``asarray(x, dtype=float)`` would keep the real part of a complex array with only a warning, so an
Hermitian matrix would silently become a different, real one. The dtype is checked before any cast.
Booleans are not numbers here either (a mask passed where bounds or measurements were meant), and
nothing is reshaped but a scalar: a vector is 1-D, a matrix 2-D, as the message of each check says.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sp

#: dtype kinds that are real numbers: signed and unsigned integers, floats.
_REAL_KINDS = "iuf"
#: Scalar types taken as they are by `real_number` (the values callbacks return at every step).
_FLOATS = (float, np.float64)


def real_array(value: Any, name: str, what: str = "array-like of numbers") -> np.ndarray:
    """``value`` as a float array, refusing complex, strings and non-numeric objects (TypeError).

    Parameters
    ----------
    value : array_like
    name : str
        The argument's name as the user knows it, used in the message.
    what : str
        What was expected, for the message ("a 2-D array of numbers", ...).
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        return value  # what the checks below return for it (astype without a copy): the per-step case
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise TypeError(f"{name} must be {what}, got {type(value).__name__} that is not a "
                        "rectangular array") from exc
    kind = arr.dtype.kind
    if kind == "b" or (kind == "O" and any(isinstance(x, (bool, np.bool_)) for x in arr.flat)):
        raise TypeError(f"{name} must be {what}, got booleans (True/False are not numbers here; "
                        "convert with .astype(float) if 0 and 1 are meant)")
    if kind == "c" or (kind == "O" and any(isinstance(x, (complex, np.complexfloating)) for x in arr.flat)):
        raise TypeError(f"{name} must be real, got complex values (their imaginary part would be dropped)")
    if kind in _REAL_KINDS:
        return arr.astype(float, copy=False)
    if kind == "O":
        try:
            return arr.astype(float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{name} must be {what}, got {type(value).__name__}") from exc
    raise TypeError(f"{name} must be {what}, got {type(value).__name__} of dtype {arr.dtype}")


def real_number(value: Any, name: str) -> float:
    """A real scalar as a float (TypeError for complex, strings, arrays); the caller checks its range.

    A one-element array counts as its element, as ``float()`` takes it.
    """
    if type(value) in _FLOATS:
        return float(value)
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    arr = real_array(value, name, "a real number")
    if arr.size != 1:
        raise TypeError(f"{name} must be a real number, got an array of shape {arr.shape}")
    return float(arr.reshape(()))


def as_vector(value: Any, name: str, dim: int | None = None, allow_inf: bool = False) -> np.ndarray:
    """Return ``value`` as a 1-D float array, or raise naming ``name`` and the expected shape.

    A scalar is a vector of length 1; a row or column matrix is refused, not flattened (``[[0, 0]]``
    for a vector of ℝ² is more often a slip than a choice, and a slip elsewhere would go unseen).
    """
    arr = real_array(value, name, "array-like of numbers")
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a vector of shape ({'n' if dim is None else dim},), got an "
                         f"array of shape {arr.shape}")
    if dim is not None and arr.shape[0] != dim:
        raise ValueError(f"{name} must have length {dim}, got length {arr.shape[0]}")
    if not _all_finite(arr):  # one pass when all is well, the message's own test otherwise
        if np.isnan(arr).any():
            raise ValueError(f"{name} contains NaN")
        if not allow_inf:
            raise ValueError(f"{name} contains inf; expected finite values")
    return arr


def _all_finite(arr: np.ndarray) -> bool:
    """Whether every entry of a 1-D float array is finite: Python's test for the few entries of a
    state or a measurement (a tenth of a ufunc reduction's overhead), NumPy's for longer vectors."""
    if arr.size <= 8:
        return all(map(math.isfinite, arr.tolist()))
    return bool(np.isfinite(arr).all())


def as_matrix(value: Any, name: str, rows: int | None = None, cols: int | None = None,
              allow_sparse: bool = False, layout: str | None = None) -> np.ndarray | sp.csc_matrix:
    """Return ``value`` as a finite 2-D float array (or CSC matrix when ``allow_sparse``).

    ``layout`` (e.g. ``"(n, ng), one generator per column"``): the input must be 2-D already, and the
    message says what its axes are; without it a scalar or a vector is read as below.
    """
    if sp.issparse(value):
        if value.dtype.kind not in _REAL_KINDS:
            raise TypeError(f"{name} must be real, got a sparse matrix of dtype {value.dtype}")
        if not allow_sparse:
            value = value.toarray()
        else:
            mat = sp.csc_matrix(value, dtype=float, copy=True)  # the caller keeps theirs
            _check_shape(mat.shape, name, rows, cols)
            if not np.isfinite(mat.data).all():
                raise ValueError(f"{name} contains NaN or inf; expected finite entries")
            return mat
    arr = real_array(value, name, "a 2-D array of numbers")
    if layout is not None and arr.ndim != 2:
        why = " (a vector does not say which axis it is)" if arr.ndim < 2 else ""
        raise ValueError(f"{name} must be a 2-D matrix of shape {layout}; got an array of shape "
                         f"{arr.shape}{why}")
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    elif arr.ndim == 1:
        # A vector is a single column when the row count is pinned, else a single row.
        arr = arr.reshape(-1, 1) if (rows is not None and arr.shape[0] == rows and cols in (None, 1)) \
            else arr.reshape(1, -1)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D matrix, got an array of shape {arr.shape}")
    _check_shape(arr.shape, name, rows, cols)
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} contains NaN or inf; expected finite entries")
    return arr


def _check_shape(shape: tuple[int, int], name: str, rows: int | None, cols: int | None) -> None:
    want_rows = "any" if rows is None else rows
    want_cols = "any" if cols is None else cols
    if (rows is not None and shape[0] != rows) or (cols is not None and shape[1] != cols):
        raise ValueError(f"{name} must have shape ({want_rows}, {want_cols}), got {tuple(shape)}")


def as_directions(value: Any, dim: int, name: str = "D") -> np.ndarray:
    """Return directions as a ``(k, dim)`` array; a single vector becomes one row."""
    arr = real_array(value, name, "an array of directions")
    if arr.ndim == 1:
        arr = arr.reshape(1, -1)
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise ValueError(f"{name} must have shape (k, {dim}) (one direction per row), "
                         f"got {np.shape(value)}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} contains NaN or inf; expected finite directions")
    return arr


def check_rng(rng: Any) -> np.random.Generator:
    """Return ``rng`` if it is a `numpy.random.Generator` (randomness enters only through one)."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    return rng


def as_generator(rng: Any, name: str = "rng") -> np.random.Generator:
    """A `numpy.random.Generator` as given, or ``numpy.random.default_rng(rng)`` for an int seed ≥ 0 or
    None (fresh entropy from the operating system), as NumPy's own ``default_rng`` takes them."""
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None:
        return np.random.default_rng()
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, (bool, np.bool_)):
        if rng < 0:
            raise ValueError(f"{name} must be a non-negative int seed or a numpy.random.Generator, got {rng}")
        return np.random.default_rng(int(rng))
    raise TypeError(f"{name} must be an int seed or a numpy.random.Generator (or None for fresh entropy), "
                    f"got {type(rng).__name__}")


def check_count(value: Any, name: str = "size") -> int:
    """A number of draws: an integer ≥ 0."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be a non-negative integer (a number of points), got {value!r}")
    if value < 0:
        raise ValueError(f"{name} must be a non-negative integer (a number of points), got {value}")
    return int(value)


def check_system(system: Any, name: str = "system") -> Any:
    """Return ``system`` if it is a setsmooth system; a python-control model is led to `from_statespace`.

    Checked by module name, so that the core never imports python-control.
    """
    cls = type(system)
    if cls.__module__.split(".")[0] == "control":
        convert = "" if cls.__name__ == "StateSpace" else "control.ss(...) of it, then "
        raise TypeError(f"{name} is a control.{cls.__name__}, which has no noise ranges: use "
                        f"{convert}setsmooth.LinearSystem.from_statespace(plant, W=..., V=..., u=...) to "
                        "build a LinearSystem (W, V the ranges of the noises, u the known inputs that "
                        "the plant's B and D act on; dt= samples a continuous plant)")
    if not hasattr(system, "n") or not hasattr(system, "W"):
        raise TypeError(f"{name} must be a setsmooth system (LinearSystem, NonlinearSystem), got "
                        f"{cls.__name__}")
    return system


def given_instead_of_set(value: Any, name: str) -> str:
    """What was given where the set ``name`` was expected, for a message: its type, and for a pair of
    bounds (NumPy's habit) the `Box` to write instead.

    The callers test ``isinstance(value, ConvexSet)`` themselves: this module is below the sets.
    """
    hint = f"; for {name} given by its bounds lo ≤ · ≤ hi use ss.Box(lo, hi)" \
        if isinstance(value, (tuple, list)) and len(value) == 2 else ""
    return f"got {type(value).__name__}{hint}"


def check_dim(value: Any, name: str) -> int:
    """Return a validated positive integer dimension."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be a positive integer, got {value!r}")
    if value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value}")
    return int(value)


def as_measurements(ys: Any, m: int) -> np.ndarray:
    """Measurements y_0..y_T as a finite (T+1, m) array (time first); a 1-D array is accepted when m = 1.

    python-control's (m, T+1) orientation is refused with a message saying so (never transposed by
    guessing; when m = T+1 the rows are read as steps).
    """
    arr = real_array(ys, "ys", "an array of measurements")
    if arr.ndim == 1 and m == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim == 2 and arr.shape[1] != m and arr.shape[0] == m:
        raise ValueError(f"ys has shape {arr.shape}, python-control's orientation (outputs × time); "
                         f"setsmooth's arrays are time-first, shape (T+1, m={m}), one row y_k per "
                         "step: pass ys.T")
    if arr.ndim != 2 or arr.shape[1] != m or arr.shape[0] < 1:
        raise ValueError(f"ys must have shape (T+1, m={m}), got {np.shape(ys)}")
    if not np.isfinite(arr).all():
        raise ValueError("ys contains NaN or inf")
    return arr


def measured(system: Any, ys: Any) -> tuple[Any, np.ndarray]:
    """The estimators' door: the checked system and measurements, without the known feedthrough.

    ``check_system``, then ``as_measurements``, then the known input's rows against T
    (`LinearSystem.check_input`, which names ``u`` with the shape expected and the shape given), then
    y_k − D_k u_k for a `LinearSystem` with a feedthrough (`LinearSystem.without_feedthrough`: the
    system returned has none, so an estimator calling another through its door subtracts nothing
    twice). Inside, y_k = C_k x_k + F_k v_k.
    """
    ys = as_measurements(ys, check_system(system).m)
    check_input = getattr(system, "check_input", None)
    if check_input is not None:
        check_input(len(ys) - 1)
    if getattr(system, "has_feedthrough", False):
        system, ys = system.without_feedthrough(ys)
    return system, ys
