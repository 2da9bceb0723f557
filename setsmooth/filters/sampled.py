"""Algorithm 2 of the rethinking paper: a Monte Carlo approximation of the optimal filter, beside Algorithm 1.

For a `ScalarRelatedNoiseSystem` (x_{k+1} = η(x_k) + w_k, y_k = g(x_k, v_k), ⟦v_k | w_{k−1}⟧ given), the
optimal posterior (rethinking (29), Theorem 1 with ⟦w_{k−1} | x_{k−1}, y_{0:k−1}⟧ = ⟦w_{k−1}⟧) is

    ⟦x_k | y_{0:k}⟧ = { η(x_{k−1}) + w_{k−1} : x_{k−1} ∈ ⟦x_{k−1} | y_{0:k−1}⟧, w_{k−1} ∈ ⟦w_{k−1}⟧,
                                             y_k ∈ g(η(x_{k−1}) + w_{k−1}, ⟦v_k | w_{k−1}⟧) }.

Algorithm 2 draws (x_{k−1}, w_{k−1}) uniformly from [a*_{k−1}, b*_{k−1}] × ⟦w⟧, keeps the x_k that pass the
test until N are accepted, and takes [min, max] of them. Every accepted x_k is a possible state, so the
result is an **inner approximation** of the optimal range, [a*_k, b*_k] ⊆ ⟦x_k | y_{0:k}⟧ (each step also
starts from an inner approximation), which fills it as N grows. It is not a guaranteed range: the true
state can lie outside it. At k = 0 the posterior is exact (v_0 is unrelated, line 4).

`sampled_optimal_filter` runs many independent filters at once, vectorised over runs and samples: each
round draws a (runs × M) block, and per run the first N accepted samples in draw order are kept (which
accepted samples are kept never depends on their values, so they are N independent uniform draws from
the accepted region, as in the algorithm's loop).

`classical_interval_filter` is Algorithm 1 (Theorem 2: the marginal ranges ⟦w⟧, ⟦v_k⟧ and no relation),
the existing `interval_filter` with η and the measurement interval of ⟦v_k⟧; it is an outer bound of the
optimal range (Theorem 3) and contains the true state. Unlike Algorithm 1's line 9 it also uses y_k = 0
(for (28) that pins x_k = 0); that measurement has probability zero.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import check_rng, real_array
from ..results import IntervalEstimates
from ..models.intervals import noise_intervals
from ..models.related_noise import ScalarRelatedNoiseSystem
from .consistency import check_on_inconsistent, report_inconsistency
from .interval import _interval_filter

__all__ = ["SampledRanges", "sampled_optimal_filter", "classical_interval_filter"]

#: Candidates drawn per round of the vectorised sampler (runs × M): bounds the memory (~10 arrays of
#: this many floats) while keeping each NumPy call long enough to amortise its overhead.
_BLOCK = 1 << 20


@dataclass(frozen=True)
class SampledRanges:
    """Sampled optimal ranges [lo, hi] of one or many runs of Algorithm 2 (inner approximations).

    A batch of runs that follows the `Estimates` protocol with a leading runs axis: ``lo``, ``hi``,
    ``centers`` and ``diameters()`` have shape (runs, T+1), ``first_empty`` is a list (one step or
    None per run), ``contains_trajectory(xs)`` takes and returns (runs, T+1) arrays and
    ``plot_tubes`` draws every run's tube on the same axes. ``sampled[r]`` is run r's
    `IntervalEstimates`. The ranges are inner approximations: the true state may lie outside them.

    Attributes
    ----------
    lo, hi : ndarray, shape (runs, T+1)
        Endpoints; NaN from the step where no sample was accepted within ``max_draws`` (the inner
        approximation lost every state consistent with the data) on.
    accepted : ndarray of int, shape (runs, T+1)
        Samples accepted per step (N unless ``max_draws`` ran out; 0 at k = 0, which is exact).
    draws : ndarray of int, shape (runs, T+1)
        Candidates drawn per step until the N-th acceptance.
    n_samples : int
        N.
    """

    lo: np.ndarray
    hi: np.ndarray
    accepted: np.ndarray
    draws: np.ndarray
    n_samples: int

    @property
    def lengths(self) -> np.ndarray:
        """μ(⟦x_k | y_{0:k}⟧) = hi − lo, the interval lengths of Fig. 2 (NaN where empty)."""
        return self.hi - self.lo

    @property
    def centers(self) -> np.ndarray:
        """Midpoints of the ranges, shape (runs, T+1)."""
        return (self.lo + self.hi) / 2.0

    def diameters(self, norm: float | str = np.inf) -> np.ndarray:
        """The lengths hi − lo, shape (runs, T+1) (a scalar state: every norm gives them)."""
        return np.array([self[r].diameters(norm) for r in range(len(self))]).reshape(self.lo.shape)

    @property
    def first_empty(self) -> list:
        """Per run, the first step whose range is empty (no sample accepted), or None."""
        return [self[r].first_empty for r in range(len(self))]

    def contains_trajectory(self, xs: Any, tol: float | None = None) -> np.ndarray:
        """Whether each run's true x_k lies in its range, shape (runs, T+1).

        Parameters
        ----------
        xs : array_like, shape (runs, T+1), or (T+1,) for one run
        tol : float, optional
            As in `IntervalEstimates.contains_trajectory`.
        """
        states = real_array(xs, "xs", f"an array of shape {self.lo.shape}")
        if states.shape != self.lo.shape and not (len(self) == 1 and states.shape == self.lo.shape[1:]):
            raise ValueError(f"xs must have shape {self.lo.shape} (one trajectory per run), got {states.shape}")
        states = states.reshape(self.lo.shape)
        return np.array([self[r].contains_trajectory(states[r], tol) for r in range(len(self))])

    def plot_tubes(self, ax: Any = None, dims: Any = None, *, truth: Any = None, label: str | None = None,
                   **kwargs) -> list:
        """Every run's range tube on the same axes (`IntervalEstimates.plot_tubes`; ``truth`` of shape
        (runs, T+1)); the label goes to the first run only. Returns the axes."""
        truths = None if truth is None else real_array(truth, "truth").reshape(self.lo.shape)
        for r in range(len(self)):
            ax = self[r].plot_tubes(ax, dims, truth=None if truths is None else truths[r],
                                    label=label if r == 0 else None, **kwargs)
        return ax

    def __len__(self) -> int:
        return self.lo.shape[0]

    def __getitem__(self, run: int) -> IntervalEstimates:
        """The ranges of one run."""
        return IntervalEstimates(self.lo[run], self.hi[run])


def classical_interval_filter(system: ScalarRelatedNoiseSystem, ys: Any, *,
                              on_inconsistent: str = "warn") -> IntervalEstimates:
    """Rethinking Algorithm 1: the classical SMF (Theorem 2) of a scalar related-noise system.

    Prediction [η(a) + w_lo, η(b) + w_hi], update ∩ measurement_interval(y_k, ⟦v_k⟧): the relation
    ⟦v_k | w_{k−1}⟧ is ignored, only the marginal ranges are used. By Theorem 3 the result contains the
    optimal range, hence the true state.

    Parameters
    ----------
    system : ScalarRelatedNoiseSystem
    ys : array_like, shape (T+1,)
        Measurements y_0..y_T of one run.
    on_inconsistent : {'warn', 'raise', 'ignore'}, keyword-only
        As in `interval_filter`: an empty range proves the data inconsistent with the model (it
        contains the optimal range), reported as an `IntervalInconsistency` in a
        `ModelInvalidationWarning` (default), raised as `ModelInvalidatedError`, or ignored.

    Returns
    -------
    IntervalEstimates

    Examples
    --------
    >>> from setsmooth.papers.rethinking_examples import rethinking_example_27
    >>> r = classical_interval_filter(rethinking_example_27(), [1.0, 2.0])
    >>> r.lo.tolist(), [round(float(v), 6) for v in r.hi]     # [0.5, 1] ∩ [0, 1], then [1, 2] ∩ [η(0.5), η(1) + 1]
    ([0.5, 1.0], [1.0, 2.0])
    """
    if not isinstance(system, ScalarRelatedNoiseSystem):
        raise TypeError(f"system must be a ScalarRelatedNoiseSystem, got {type(system).__name__}")
    check_on_inconsistent(on_inconsistent)
    ys = real_array(ys, "ys", "an array of measurements")
    if ys.ndim != 1 or ys.shape[0] < 1:
        raise ValueError(f"ys must have shape (T+1,) (one run), got {ys.shape}")
    if not np.isfinite(ys).all():
        raise ValueError("ys contains NaN or inf")
    estimates, found = _interval_filter(system.eta, noise_intervals(system.w_range, len(ys) - 1),
                                        system.x0_range, ys, functools.partial(_measurement_interval, system))
    report_inconsistency(found, on_inconsistent)
    return estimates


def _measurement_interval(system: ScalarRelatedNoiseSystem, k: int, y) -> tuple[float, float]:
    lo, hi = system.measurement_interval(np.asarray(y, dtype=float), *system.v_range)
    return float(lo), float(hi)


def sampled_optimal_filter(system: ScalarRelatedNoiseSystem, ys: Any, rng: np.random.Generator,
                           n_samples: int = 10_000, *, max_draws: int | None = None) -> SampledRanges:
    """Rethinking Algorithm 2: Monte Carlo inner approximations of the optimal ranges ⟦x_k | y_{0:k}⟧.

    Parameters
    ----------
    system : ScalarRelatedNoiseSystem
    ys : array_like, shape (T+1,) or (runs, T+1)
        Measurements of one run or of many independent runs (filtered together, vectorised).
    rng : numpy.random.Generator
        The only source of randomness.
    n_samples : int
        N, accepted samples per step and run (10,000 in the paper).
    max_draws : int, optional
        Candidates drawn at most per step and run before giving up with fewer than N accepted (an
        inner approximation can lose the data's support); 1000·N by default.

    Returns
    -------
    SampledRanges
        With ``lo``/``hi`` of shape (runs, T+1) (runs = 1 for 1-D ``ys``). Each range is inside the
        optimal one and inside the classical one of `classical_interval_filter`.

    Raises
    ------
    TypeError, ValueError
        For a wrong system or generator, ``ys`` not of shape (T+1,)/(runs, T+1) or not finite,
        ``n_samples`` < 1 or ``max_draws`` < ``n_samples``.

    Examples
    --------
    >>> import numpy as np
    >>> from setsmooth.papers.rethinking_examples import rethinking_example_27
    >>> system = rethinking_example_27()
    >>> xs, ys = system.simulate(10, np.random.default_rng(0), runs=4)
    >>> sampled = sampled_optimal_filter(system, ys, np.random.default_rng(1), n_samples=500)
    >>> sampled.lo.shape, bool((sampled.accepted[:, 1:] == 500).all())
    ((4, 11), True)
    """
    if not isinstance(system, ScalarRelatedNoiseSystem):
        raise TypeError(f"system must be a ScalarRelatedNoiseSystem, got {type(system).__name__}")
    check_rng(rng)
    ys = real_array(ys, "ys", "an array of measurements")
    if ys.ndim == 1:
        ys = ys[None, :]
    if ys.ndim != 2 or ys.shape[1] < 1 or ys.shape[0] < 1:
        raise ValueError(f"ys must have shape (T+1,) or (runs, T+1), got {ys.shape}")
    if not np.isfinite(ys).all():
        raise ValueError("ys contains NaN or inf")
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)) or n_samples < 1:
        raise ValueError(f"n_samples must be a positive integer (N of Algorithm 2), got {n_samples!r}")
    max_draws = 1000 * int(n_samples) if max_draws is None else max_draws
    if isinstance(max_draws, bool) or not isinstance(max_draws, (int, np.integer)) or max_draws < n_samples:
        raise ValueError(f"max_draws must be an integer >= n_samples = {n_samples}, got {max_draws!r}")

    runs, steps = ys.shape
    lo = np.full((runs, steps), np.nan)
    hi = np.full((runs, steps), np.nan)
    accepted = np.zeros((runs, steps), dtype=np.int64)
    draws = np.zeros((runs, steps), dtype=np.int64)
    # Line 4: k = 0 is exact, the classical update of ⟦x_0⟧ (v_0 is unrelated to everything).
    m_lo, m_hi = system.measurement_interval(ys[:, 0], *system.v_range)
    a, b = np.maximum(system.x0_range[0], m_lo), np.minimum(system.x0_range[1], m_hi)
    alive = a <= b
    lo[alive, 0], hi[alive, 0] = a[alive], b[alive]
    for k in range(1, steps):
        alive = np.flatnonzero(~np.isnan(lo[:, k - 1]))
        if alive.size == 0:
            break
        step = _sampled_step(system, lo[alive, k - 1], hi[alive, k - 1], ys[alive, k], rng,
                             int(n_samples), int(max_draws))
        lo[alive, k], hi[alive, k], accepted[alive, k], draws[alive, k] = step
    return SampledRanges(lo, hi, accepted, draws, int(n_samples))


def _sampled_step(system: ScalarRelatedNoiseSystem, a: np.ndarray, b: np.ndarray, y: np.ndarray,
                  rng: np.random.Generator, N: int, max_draws: int):
    """Lines 6–14 for many runs at once: (lo, hi, accepted, draws) of [a*_k, b*_k] per run.

    Each round gives run r a budget of m_r candidates: first a pilot of min(N, _PILOT), then the number
    that accepts at most the remaining need at an upper confidence bound of the run's acceptance rate,
    so that few runs overshoot and the first-N cut (a cumulative count) is only computed for those.
    """
    runs = a.size
    need = np.full(runs, N, dtype=np.int64)
    drawn = np.zeros(runs, dtype=np.int64)
    got = np.zeros(runs, dtype=np.int64)
    lo = np.full(runs, np.inf)
    hi = np.full(runs, -np.inf)
    w_lo, w_hi = system.w_range
    active = np.arange(runs)
    while active.size:
        budget = _budget(need[active], drawn[active], got[active], max_draws)
        M = int(budget.max())
        if active.size * M > _BLOCK:   # memory bound: split the runs' budgets over several rounds
            M = max(_PILOT, _BLOCK // active.size)
            budget = np.minimum(budget, M)
        # The draws are rectangular (the random stream does not depend on the budgets); only run r's
        # first budget_r candidates count, and everything below works on those alone, run after run
        # (row-major order: run r's candidates are the segment starts[r] .. starts[r] + budget_r).
        counted = np.arange(M)[None, :] < budget[:, None]
        x_prev = rng.random((active.size, M))[counted]
        x_prev *= np.repeat(b[active] - a[active], budget)
        x_prev += np.repeat(a[active], budget)
        w = rng.random((active.size, M))[counted]
        w *= w_hi - w_lo
        w += w_lo
        x = system.eta(x_prev) + w                                          # line 9, (27)
        v_lo, v_hi = system.conditional_v(w)
        g_lo, g_hi = system.measurement(x, v_lo), system.measurement(x, v_hi)
        yk = np.repeat(y[active], budget)
        # Line 10: y_k ∈ g(x_k, ⟦v_k | w_{k−1}⟧), the interval between g(x, lo) and g(x, hi): y lies
        # between them when it is at or above g(x, lo) and not above g(x, hi), or the other way round.
        # Three passes instead of min/max; a y exactly on an end can be refused when g decreases in v
        # (a null set), an inconsistent x_k is never accepted.
        ok = (g_lo <= yk) != (g_hi < yk)
        starts = np.concatenate([[0], np.cumsum(budget)[:-1]])
        total = np.add.reduceat(ok, starts, dtype=np.int64)
        used = budget.copy()
        for r in np.flatnonzero(total > need[active]):  # keep the first `need` acceptances, in draw order
            run = ok[starts[r]:starts[r] + budget[r]]
            count = np.cumsum(run, dtype=np.int64)
            run &= count <= need[active[r]]
            used[r] = np.argmax(count >= need[active[r]]) + 1
            total[r] = need[active[r]]
        lo[active] = np.minimum(lo[active], np.minimum.reduceat(np.where(ok, x, np.inf), starts))
        hi[active] = np.maximum(hi[active], np.maximum.reduceat(np.where(ok, x, -np.inf), starts))
        drawn[active] += used
        got[active] += total
        need[active] -= total
        active = active[(need[active] > 0) & (drawn[active] < max_draws)]
    empty = got == 0
    lo[empty], hi[empty] = np.nan, np.nan
    return lo, hi, got, drawn


#: Candidates of a run's first round (its acceptance rate is unknown before).
_PILOT = 1024


def _budget(need: np.ndarray, drawn: np.ndarray, got: np.ndarray, max_draws: int) -> np.ndarray:
    """Candidates to draw next per run: at most the remaining need accepted at a high acceptance rate."""
    rate = (got + 1) / (drawn + 2)
    seen = np.maximum(drawn, 1)
    high = np.minimum(1.0, rate + 3 * np.sqrt(rate * (1 - rate) / seen) + 1 / seen)
    budget = np.where(drawn == 0, np.minimum(need, _PILOT), np.ceil(need / high))
    # A small remaining need: overshooting is cheap, another round is not.
    small = need < 64
    budget = np.where(small & (drawn > 0), np.ceil(need / rate * 1.5) + 16, budget)
    return np.maximum(1, np.minimum(budget, max_draws - drawn)).astype(np.int64)
