"""The LSU model: a linear state-space model with uniform, bounded noises (LSU paper (4)–(6)).

    y_t     = C x_t + v_t,                 f(v_t) = U(−v, v)
    x_{t+1} = A x_t + B u_t + w_{t+1},     f(w_t) = U(−ω, ω)
    x_1     ~ U(x̲_1, x̄_1)                                         (5)

with a known input u_t, t = 1..t̄. Arrays here are 0-based: ``xs[i]`` is x_{i+1}, ``ys[i]`` is y_{i+1},
``us[i]`` is u_{i+1}, so ``xs[i+1] = A xs[i] + B us[i] + w`` with the paper's w_{i+2} (its index of w
is the step it enters). The input of the last step, u_t̄, moves nothing the filters report.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..._validation import as_matrix, as_vector, check_rng, real_array
from ...sets import rounding
from ...sets.box import Box
from ...sets.constrained_zonotope import ConstrainedZonotope

__all__ = ["LSUModel"]


@dataclass(frozen=True, init=False, eq=False)
class LSUModel:
    """A linear model with uniform noises on boxes and a uniform prior on a box (LSU paper (4)–(6)).

    Parameters
    ----------
    A : array_like, shape (n, n)
    B : array_like, shape (n, ℓ_u)
        Input matrix of the known input u_t.
    C : array_like, shape (m, n)
    omega : array_like, shape (n,)
        Half-widths ω > 0 of the state noise box: w_t ~ U(−ω, ω).
    v : array_like, shape (m,)
        Half-widths v > 0 of the observation noise box: v_t ~ U(−v, v).
    x1_lo, x1_hi : array_like, shape (n,)
        The prior box [x̲_1, x̄_1] of (5).

    Raises
    ------
    ValueError
        When a matrix or vector has the wrong shape, a half-width is not positive and finite, or
        x1_lo > x1_hi, naming the argument.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> model = ss.LSUModel(A=[[0.9]], B=[[1.0]], C=[[1.0]], omega=[0.1], v=[0.2],
    ...                     x1_lo=[-1.0], x1_hi=[1.0])
    >>> xs, ys = model.simulate(np.zeros((5, 1)), np.random.default_rng(0))
    >>> xs.shape, ys.shape
    ((5, 1), (5, 1))
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    omega: np.ndarray
    v: np.ndarray
    x1_lo: np.ndarray
    x1_hi: np.ndarray

    def __init__(self, A: Any, B: Any, C: Any, omega: Any, v: Any, x1_lo: Any, x1_hi: Any):
        A = as_matrix(A, "A")
        n = A.shape[0]
        if A.shape != (n, n):
            raise ValueError(f"A must be square, got shape {A.shape}")
        B = as_matrix(B, "B", rows=n)
        C = as_matrix(C, "C", cols=n)
        omega = as_vector(omega, "omega", n)
        v = as_vector(v, "v", C.shape[0])
        for name, half in (("omega", omega), ("v", v)):
            if np.any(half <= 0):
                raise ValueError(f"{name} must hold positive half-widths of the noise box, got {half.tolist()}")
        lo, hi = as_vector(x1_lo, "x1_lo", n), as_vector(x1_hi, "x1_hi", n)
        if np.any(lo > hi):
            raise ValueError(f"x1_lo must not exceed x1_hi, got {lo.tolist()} and {hi.tolist()}")
        for name, value in (("A", A), ("B", B), ("C", C), ("omega", omega), ("v", v), ("x1_lo", lo),
                            ("x1_hi", hi)):
            value = np.array(value, dtype=float)
            value.flags.writeable = False
            object.__setattr__(self, name, value)

    @property
    def n(self) -> int:
        """ℓ_x, the state dimension."""
        return self.A.shape[0]

    @property
    def m(self) -> int:
        """ℓ_y, the output dimension."""
        return self.C.shape[0]

    @property
    def W(self) -> Box:
        """𝕎, the support of f(w_t): the box [−ω, ω]."""
        return Box(-self.omega, self.omega)

    @property
    def V(self) -> Box:
        """𝕍, the support of f(v_t): the box [−v, v]."""
        return Box(-self.v, self.v)

    @property
    def prior(self) -> Box:
        """𝕏_1, the support of the prior f(x_1) (5)."""
        return Box(self.x1_lo, self.x1_hi)

    def strip(self, y: np.ndarray) -> Box:
        """y_t − 𝕍: the box C x_t must lie in (the strip of the data update (15)), its bounds y ∓ v
        rounded outward (a strip one ulp narrower than the exact one could cut the true state)."""
        return Box(rounding.sum_down(y, -self.v), rounding.sum_up(y, self.v))

    def strip_sets(self, ys: np.ndarray, by_component: bool = False) -> list:
        """The strips of a whole data sequence as the CZ forms of ``strip(y)`` (``ys`` checked), built
        at once: ``[strip(y)._flat_cz for y in ys]``, bit for bit (the same elementwise `rounding.
        box_center_radius` on all rows together, each row's pad kept or dropped as it would be alone),
        without a Box, its validation and its conversion per step. With ``by_component``: per step, the
        list of its m one-dimensional strips (as ``Box(strip.lo[j:j+1], strip.hi[j:j+1])._flat_cz``).
        Boxes are returned (the per-step path) if a bound is not finite."""
        lo, hi = rounding.sum_down(ys, -self.v), rounding.sum_up(ys, self.v)
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            strips = [self.strip(y) for y in ys]
            return [[Box._trusted(S.lo[j:j + 1], S.hi[j:j + 1]) for j in range(self.m)] for S in strips] \
                if by_component else strips
        center, radius, pad = rounding.box_center_radius(lo, hi)
        if by_component:
            one, empty_A, empty_b = np.ones(1), np.zeros((0, 1)), np.zeros(0)
            return [[ConstrainedZonotope._trusted(
                radius[t, j:j + 1].reshape(1, 1), center[t, j:j + 1], empty_A, empty_b, one,
                pad=None if pad is None or pad[t, j] == 0.0 else pad[t, j:j + 1])
                for j in range(self.m)] for t in range(len(ys))]
        ones, empty_A, empty_b = np.ones(self.m), np.zeros((0, self.m)), np.zeros(0)
        return [ConstrainedZonotope._trusted(np.diag(radius[t]), center[t], empty_A, empty_b, ones,
                                             pad=None if pad is None or not np.any(pad[t]) else pad[t])
                for t in range(len(ys))]

    def check_data(self, ys: Any, us: Any) -> tuple[np.ndarray, np.ndarray]:
        """Validate outputs (t̄, m) and inputs (t̄, ℓ_u) of one data sequence; return them as arrays."""
        ys = real_array(ys, "ys", f"an array of shape (t̄, m={self.m})")
        us = real_array(us, "us", f"an array of shape (t̄, ℓ_u={self.B.shape[1]})")
        if ys.ndim != 2 or ys.shape[1] != self.m or ys.shape[0] < 1:
            raise ValueError(f"ys must have shape (t̄, m={self.m}) with t̄ ≥ 1, got {ys.shape}")
        if us.ndim != 2 or us.shape != (ys.shape[0], self.B.shape[1]):
            raise ValueError(f"us must have shape (t̄={ys.shape[0]}, ℓ_u={self.B.shape[1]}) like ys, "
                             f"got {us.shape}")
        if not (np.all(np.isfinite(ys)) and np.all(np.isfinite(us))):
            raise ValueError("ys and us must be finite")
        return ys, us

    def simulate(self, us: Any, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """A trajectory of (4) with x_1 ~ U(x̲_1, x̄_1), w ~ U(−ω, ω), v ~ U(−v, v).

        Parameters
        ----------
        us : array_like, shape (t̄, ℓ_u)
            The known inputs u_1..u_t̄.
        rng : numpy.random.Generator
            The only source of randomness: x_1, then w_2..w_t̄, then v_1..v_t̄.

        Returns
        -------
        xs : ndarray, shape (t̄, n)
            True states x_1..x_t̄.
        ys : ndarray, shape (t̄, m)
            Outputs y_1..y_t̄.
        """
        check_rng(rng)
        us = real_array(us, "us", f"an array of shape (t̄, ℓ_u={self.B.shape[1]})")
        if us.ndim != 2 or us.shape[1] != self.B.shape[1] or us.shape[0] < 1:
            raise ValueError(f"us must have shape (t̄, ℓ_u={self.B.shape[1]}) with t̄ ≥ 1, got {us.shape}")
        T = us.shape[0]
        x = rng.uniform(self.x1_lo, self.x1_hi)
        ws = rng.uniform(-self.omega, self.omega, size=(T - 1, self.n))
        vs = rng.uniform(-self.v, self.v, size=(T, self.m))
        xs = [x]
        for t in range(T - 1):
            xs.append(self.A @ xs[-1] + self.B @ us[t] + ws[t])
        xs = np.array(xs)
        return xs, xs @ self.C.T + vs
