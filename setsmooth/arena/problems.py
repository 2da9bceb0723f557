"""The zoo: estimation problems with their noise sets, horizon and seeded data.

Every problem is a function ``(rng, horizon=None) -> Problem``: it draws whatever is random (the
system, for the random ones, then the true trajectory and its measurements) from the one
`numpy.random.Generator` it is given, so a seed fixes the whole problem. The data are simulated with
the noises drawn uniformly from their ranges (`setsmooth.simulate`; rethinking (30) draws one w for
every step), so the true states are consistent with the model and every sound estimator must contain
them.

Each problem declares the structures its system has (`STRUCTURES`: ``'linear'``, ``'scalar_monotone'``),
and the arena runs on it only the estimators that apply to one of them: the smoothing paper's nonlinear
example (33) only the interval filter and smoother, a scalar linear system with A > 0 both those and
the linear estimators.

Heavy problems (random20, random30, the long horizon) are left out of the default selection; name them
to run them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_generator
from ..analysis.random_systems import random_observable_system
from ..models.linear_system import LinearSystem
from ..models.nonlinear_system import NonlinearSystem
from ..models.simulation import simulate
from ..papers.rethinking_examples import rethinking_example_30, rethinking_example_30_x0
from ..papers.smoothing_examples import (SMOOTHING_33_X0, eta_33, eta_33_inverse, measurement_interval_34,
                                         smoothing_example_31, smoothing_example_31_x0, smoothing_example_33)
from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.constrained_zonotope import ConstrainedZonotope
from .estimators import STRUCTURES, chosen_names
from .scalar import MonotoneScalarSystem

__all__ = ["Problem", "ProblemSpec", "PROBLEMS", "make_problem", "problem_names", "check_problems"]


@dataclass(frozen=True, eq=False)
class Problem:
    """One problem instance: a system, its initial range, a true trajectory and its measurements.

    Attributes
    ----------
    name : str
    system : LinearSystem or NonlinearSystem
    X0 : ConvexSet
        ⟦x_0⟧, the initial range the estimators are given (the true x_0 is drawn from it).
    xs : ndarray, shape (T+1, n)
        True states x_0..x_T.
    ys : ndarray, shape (T+1, m)
        Measurements y_0..y_T.
    horizon : int
        T.
    structure : frozenset of str
        The structures the system has (`STRUCTURES`), which decide the estimators that apply.
    """

    name: str
    system: LinearSystem | NonlinearSystem
    X0: ConvexSet
    xs: np.ndarray
    ys: np.ndarray
    horizon: int
    structure: frozenset[str] = frozenset({"linear"})


@dataclass(frozen=True)
class ProblemSpec:
    """A zoo entry: the function drawing the problem, its default horizon, whether it is heavy, and
    the structures its system has (`STRUCTURES`)."""

    build: Callable[[np.random.Generator, int], tuple[LinearSystem | NonlinearSystem, ConvexSet]]
    horizon: int
    summary: str
    heavy: bool = False
    #: (system, X0, T, rng) -> (xs, ys) when the data are not `simulate`'s independent uniform draws.
    draw: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None
    structure: frozenset[str] = frozenset({"linear"})

    def __post_init__(self):
        if not self.structure or not self.structure <= set(STRUCTURES):
            raise ValueError(f"structure must name structures among {STRUCTURES}, got {sorted(self.structure)}")


def _example_31(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    return smoothing_example_31(), smoothing_example_31_x0()


def _thin_noise(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # Example (31)'s dynamics with noise ranges of half-width 1e-5: sets five orders of magnitude
    # thinner than the states, where rounding at the states' scale shows.
    base = smoothing_example_31()
    thin = 1e-5
    system = LinearSystem(base.A, None, base.C, E=base.E, F=base.F,
                          W=Box([-thin], [thin]), V=Box([-thin, -thin], [thin, thin]))
    return system, smoothing_example_31_x0()


def _mass_spring_damper(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    import control

    # 1 Hz, lightly damped, pushed by an unknown force |w(t)| <= 1; the position is measured every
    # 0.25 s to within 0.02. 'bounded' sampling: sound for any w(t) in W at every instant.
    omega, zeta = 2 * np.pi, 0.05
    plant = control.ss([[0.0, 1.0], [-omega ** 2, -2 * zeta * omega]], [[0.0], [1.0]], [[1.0, 0.0]], 0)
    system = LinearSystem.from_statespace(plant, W=Box([-1.0], [1.0]), V=Box([-0.02], [0.02]),
                                          noise_inputs=[0], dt=0.25, partition=8)
    return system, Box([-0.3, -1.0], [0.3, 1.0])


def _cz_noise(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # A random stable observable system (n = 3) whose process noise is a triangle, a CZ that is
    # neither a box nor a zonotope: ξ ∈ [−1, 1]³ with ξ₁ + ξ₂ + ξ₃ = 1, mapped by G.
    drawn = random_observable_system(rng, 3, 2, 2)
    W = ConstrainedZonotope(np.array([[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]]), np.zeros(2),
                            A=[[1.0, 1.0, 1.0]], b=[1.0])
    V = Box([-0.5, -0.5], [0.5, 0.5])
    return drawn.linear_system(W=W, V=V), Box(-5.0 * np.ones(3), 5.0 * np.ones(3))


def _stability_example(A: list, C: list) -> LinearSystem:
    # Stability paper (25)–(26): E = [0.5, 1]ᵀ, W = V = [−1, 1].
    unit = Box([-1.0], [1.0])
    return LinearSystem(A, None, C, E=[[0.5], [1.0]], W=unit, V=unit)


def _stability_25(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # Observable. ⟦x_0⟧ = [0, 4]², designer Alice's of Figs. 2–3 (it holds the true set [1, 3]²).
    return _stability_example([[1.0, 1.0], [0.0, 1.0]], [[1.0, 0.0]]), Box([0.0, 0.0], [4.0, 4.0])


def _stability_26(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # Detectable, not observable: x_1's range shrinks only through the stable part.
    return _stability_example([[0.5, 1.0], [0.0, 1.0]], [[0.0, 1.0]]), Box([0.0, 0.0], [4.0, 4.0])


def _stability_random(n: int) -> Callable[[np.random.Generator, int], tuple[LinearSystem, ConvexSet]]:
    def build(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
        # Stability paper Table 1's setting at n = p = m: W = [−1, 1]^p, V = [−1, 1]^m, ⟦x_0⟧ = [−10, 10]ⁿ.
        drawn = random_observable_system(rng, n, n, n)
        return drawn.linear_system(), Box(-10.0 * np.ones(n), 10.0 * np.ones(n))
    return build


def _lsu_section_41(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # LSU paper Section 4.1 as printed (A, B, C; ω = 1e−4), v = 0.1 (K = 1), u_k ~ N(0, 1) known,
    # and the prior box [−1, 1]³ of paper_figures/_lsu_examples.py.
    A = [[1.0, -0.5, 0.2], [0.5, 0.1, 0.0], [0.3, 0.0, -0.1]]
    B, C = [[0.1], [0.6], [0.3]], [[1.0, 0.0, 0.5], [0.0, 1.0, 0.5]]
    us = rng.standard_normal((max(T, 1), 1))
    system = LinearSystem(A, B, C, W=Box(-1e-4 * np.ones(3), 1e-4 * np.ones(3)),
                          V=Box([-0.1, -0.1], [0.1, 0.1]), u=us)
    return system, Box(-np.ones(3), np.ones(3))


def _rethinking_30(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    return rethinking_example_30(), rethinking_example_30_x0()


def _example_33(rng: np.random.Generator, T: int) -> tuple[MonotoneScalarSystem, ConvexSet]:
    # Smoothing paper (33)–(34): η(x) = ∛x + x, y = 2x + v, ⟦w⟧ = [−1, 1], ⟦v⟧ = [1, 3]; the paper's
    # measurement function and noise ranges, with η, η⁻¹ and (34) stated for the interval estimators.
    paper = smoothing_example_33()
    system = MonotoneScalarSystem(eta_33, paper.g, measurement_interval_34, paper.W, paper.V,
                                  eta_inverse=eta_33_inverse)
    return system, Box([SMOOTHING_33_X0[0]], [SMOOTHING_33_X0[1]])


def _scalar_linear(rng: np.random.Generator, T: int) -> tuple[LinearSystem, ConvexSet]:
    # Example (33)'s noises and measurement with a linear η(x) = 0.9 x: a linear system the interval
    # filter and smoother are exact for too, so they meet the exact filter and smoother here.
    system = LinearSystem([[0.9]], None, [[2.0]], W=Box([-1.0], [1.0]), V=Box([1.0], [3.0]))
    return system, Box([SMOOTHING_33_X0[0]], [SMOOTHING_33_X0[1]])


def _one_process_noise(system: LinearSystem, X0: ConvexSet, T: int, rng: np.random.Generator
                       ) -> tuple[np.ndarray, np.ndarray]:
    # Rethinking paper Section IV-B: one w for every step (w_k = w), which the classical model allows.
    w = system.W.sample(rng, 1)[0]
    return simulate(system, X0, T, rng, ws=np.tile(w, (T, 1)))


#: The zoo, by name. Default horizons keep one run of every estimator on every light problem to seconds.
PROBLEMS: dict[str, ProblemSpec] = {
    "example31": ProblemSpec(_example_31, 20, "smoothing paper example (31), ⟦x_0⟧ = [−5, 5]²"),
    "mass_spring_damper": ProblemSpec(
        _mass_spring_damper, 20, "python-control mass-spring-damper, sampled soundly (Δ = 0.25 s)"),
    "thin_noise": ProblemSpec(_thin_noise, 20, "example (31) with noise half-widths 1e-5"),
    "cz_noise": ProblemSpec(_cz_noise, 20, "random stable n = 3 system, triangle-CZ process noise"),
    "random10": ProblemSpec(_stability_random(10), 10,
                            "stability paper random observable system, n = p = m = 10"),
    "stability25": ProblemSpec(_stability_25, 20, "stability paper example (25), observable, ⟦x_0⟧ = [0, 4]²"),
    "stability26": ProblemSpec(_stability_26, 20, "stability paper example (26), detectable, ⟦x_0⟧ = [0, 4]²"),
    "rethinking30": ProblemSpec(_rethinking_30, 10, "rethinking paper example (30): one constant w",
                                draw=_one_process_noise),
    "lsu41": ProblemSpec(_lsu_section_41, 20, "LSU paper Section 4.1 (n = 3, known input, ω = 1e−4)"),
    "example33": ProblemSpec(_example_33, 50, "smoothing paper nonlinear example (33)–(34), ⟦x_0⟧ = [−5, 5]",
                             structure=frozenset({"scalar_monotone"})),
    "scalar_linear": ProblemSpec(_scalar_linear, 20, "x_{k+1} = 0.9 x_k + w_k, y_k = 2 x_k + v_k, example "
                                 "(33)'s noises", structure=frozenset({"linear", "scalar_monotone"})),
    "random20": ProblemSpec(_stability_random(20), 10, "as random10 at n = 20", heavy=True),
    "random30": ProblemSpec(_stability_random(30), 10, "as random10 at n = 30", heavy=True),
    "long_horizon": ProblemSpec(_example_31, 1000, "example (31) over T = 1000 steps", heavy=True),
}


def problem_names(include_heavy: bool = False) -> list[str]:
    """The zoo's problem names, heavy ones only when asked."""
    return [name for name, spec in PROBLEMS.items() if include_heavy or not spec.heavy]


def check_problems(names: Any, argument: str = "problems") -> list[str]:
    """Validate problem names; None gives the default (every problem that is not heavy).

    Raises
    ------
    ValueError
        For an unknown name, naming ``argument`` and the valid choices.
    """
    return chosen_names(names, PROBLEMS, problem_names(), argument, "problem")


def make_problem(name: str, rng: Any, horizon: int | None = None) -> Problem:
    """Draw problem ``name`` from ``rng`` (a Generator, an int seed or None), over ``horizon`` steps.

    Parameters
    ----------
    name : str
        A key of `PROBLEMS`.
    rng : numpy.random.Generator, int or None
        The only source of randomness (system, when random, then x_0 and the noises), as
        ``numpy.random.default_rng`` takes it (None: fresh entropy).
    horizon : int, optional
        T (measurements y_0..y_T); the problem's own default when None.

    Returns
    -------
    Problem

    Examples
    --------
    >>> p = make_problem("example31", 0, horizon=3)
    >>> p.xs.shape, p.ys.shape, p.horizon
    ((4, 2), (4, 2), 3)
    """
    spec = PROBLEMS[check_problems([name], "name")[0]]
    T = spec.horizon if horizon is None else int(horizon)
    if T < 0:
        raise ValueError(f"horizon must be a non-negative integer, got {horizon!r}")
    rng = as_generator(rng)
    system, X0 = spec.build(rng, T)
    xs, ys = (spec.draw or simulate)(system, X0, T, rng)
    return Problem(name, system, X0, xs, ys, T, spec.structure)
