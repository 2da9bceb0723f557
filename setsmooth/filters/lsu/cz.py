"""The LSU-CZ filter (LSU paper Algorithm 1): uniform posteriors on constrained-zonotope supports.

    data update (15):   𝕏_t       = reduce(𝕏_{t|t−1} ∩_C (y_t − 𝕍))
    time update (16):   𝕏_{t+1|t} = A 𝕏_t + B u_t + 𝕎

The exact posterior of the LSU model is not uniform (the time update sums uniform densities); the
paper keeps it uniform on the support (16) (the KL-optimal uniform approximation of Pavelková & Jirsa
2018), so the filter is the classical set-membership recursion on supports, which the library runs
(`classical_filter`), plus one reduction per data update holding the support's complexity at
``max_generators`` (n_g) and ``max_constraints`` (n_c). The paper states neither its maxima nor its
reduction; ours is the library's CORA-style pipeline

    Rescale('iter' | 'exact') → EliminateConstraints(n_c) → Girard((n_g − n_c)/n),

Scott et al. (2016) §4.1–4.3: rescaling by interval propagation, constraint elimination, and Girard's
generator reduction of the lifted zonotope to (n_g − n_c)/n degrees of freedom per dimension, so
that every support has at most n_g generators and n_c constraints. Each step is an outer
approximation, so every support contains the exact set-membership posterior.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...sets.empty import EmptySet
from ...sets.reduction import EliminateConstraints, Girard, Rescale
from ...models.linear_system import LinearSystem
from ..classical import classical_filter
from ..consistency import Inconsistency, check_on_inconsistent, outer_inconsistency, report_inconsistency
from .estimates import POINT_ESTIMATES, summarize
from .model import LSUModel
from .result import LSUResult

__all__ = ["lsu_cz_filter", "lsu_cz_reduction", "DEFAULT_MAX_GENERATORS", "DEFAULT_MAX_CONSTRAINTS"]

#: Default complexity maxima of the LSU-CZ support for the paper's n = 3 (our choice; see
#: `paper_figures/lsu_complexity.py` for how the errors change with them).
DEFAULT_MAX_GENERATORS = 9
DEFAULT_MAX_CONSTRAINTS = 2


def lsu_cz_reduction(n: int, max_generators: int, max_constraints: int, rescale: str = "iter") -> tuple:
    """The reduction pipeline that holds a CZ in ℝⁿ at ≤ ``max_generators`` generators and
    ≤ ``max_constraints`` constraints: Rescale(rescale), EliminateConstraints(n_c),
    Girard((n_g − n_c)/n). ``rescale='exact'`` tightens the factor bounds by LPs (2 per factor)
    instead of interval propagation: much tighter supports at high noise, several times the cost
    (`paper_figures/lsu_complexity.py`).

    Raises
    ------
    ValueError
        Unless 0 ≤ n_c and n_g ≥ n + n_c (Girard's order is at least 1).
    """
    for name, value in (("max_generators", max_generators), ("max_constraints", max_constraints)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"{name} must be an integer, got {value!r}")
    if max_constraints < 0 or max_generators < n + max_constraints:
        raise ValueError(f"need max_constraints ≥ 0 and max_generators ≥ n + max_constraints = "
                         f"{n} + {max_constraints}, got max_generators={max_generators}, "
                         f"max_constraints={max_constraints}")
    return (Rescale(rescale), EliminateConstraints(int(max_constraints)),
            Girard((max_generators - max_constraints) / n))


def lsu_cz_filter(model: LSUModel, ys: Any, us: Any, *, max_generators: int = DEFAULT_MAX_GENERATORS,
                  max_constraints: int = DEFAULT_MAX_CONSTRAINTS, rescale: str = "iter",
                  estimates: tuple[str, ...] = POINT_ESTIMATES, std: bool = True,
                  rng: np.random.Generator | None = None, on_inconsistent: str = "warn") -> LSUResult:
    """Run LSU-CZ (LSU paper Algorithm 1) on one data sequence.

    Parameters
    ----------
    model : LSUModel
    ys : array_like, shape (t̄, m)
        Outputs y_1..y_t̄.
    us : array_like, shape (t̄, ℓ_u)
        Known inputs u_1..u_t̄.
    max_generators, max_constraints : int
        The complexity maxima n_g, n_c of every support 𝕏_t (Algorithm 1, initialization).
    rescale : {'iter', 'exact'}
        How the factor bounds are tightened before the reduction (`Rescale`): interval propagation
        (default, no LP) or LPs.
    estimates : tuple of str
        Point estimates to compute at every step: 'interval_hull' (Method 1, LSUCZ-1), 'closest'
        (Method 2, LSUCZ-2), 'centroid' (the posterior mean of the approximation).
    std : bool
        Also compute the posterior standard deviations (`posterior_std`).
    rng : numpy.random.Generator, optional
        Only used for a centroid or spread that must be sampled (dimension > 6 or too many vertices).
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when a support is empty. Every support contains the exact set-membership
        posterior, so an empty one proves the data inconsistent with the model (a non-empty one does
        not prove them consistent; `setsmooth.filters.consistency`): 'warn' issues a
        `ModelInvalidationWarning` naming the first such index i (``ys[i]``), the measurement and its
        distance from the output set predicted from the support before it; 'raise' raises
        `ModelInvalidatedError`.

    Returns
    -------
    LSUResult
        ``supports[i]`` = 𝕏_{i+1} ⊇ the exact set-membership posterior; an `EmptySet` (and NaN
        estimates) from the first step whose support is empty, which means the data contradict the
        model.

    Raises
    ------
    ValueError, TypeError
        For data of the wrong shape, maxima that cannot be met, or an unknown estimate name;
        `ModelInvalidatedError` (a ValueError) for inconsistent data with ``on_inconsistent='raise'``.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> model = ss.LSUModel(A=[[0.9, 0.2], [0.0, 0.8]], B=[[1.0], [0.5]], C=[[1.0, 0.0]],
    ...                     omega=[0.01, 0.01], v=[0.1], x1_lo=[-1, -1], x1_hi=[1, 1])
    >>> us = np.random.default_rng(0).standard_normal((20, 1))
    >>> xs, ys = model.simulate(us, np.random.default_rng(1))
    >>> result = ss.lsu_cz_filter(model, ys, us, max_generators=6, max_constraints=2)
    >>> all(S.contains(x) for S, x in zip(result.supports, xs))
    True
    """
    if not isinstance(model, LSUModel):
        raise TypeError(f"model must be an LSUModel, got {type(model).__name__}")
    ys, us = model.check_data(ys, us)
    check_on_inconsistent(on_inconsistent)
    methods = lsu_cz_reduction(model.n, max_generators, max_constraints, rescale)
    bad = [e for e in estimates if e not in POINT_ESTIMATES]
    if bad:
        raise ValueError(f"estimates must be among {POINT_ESTIMATES}, got {bad}")
    supports = classical_filter(_support_system(model, us), model.prior.to_constrained_zonotope(), ys,
                                reduce=methods, detect_empty=False)
    points = {e: np.full((len(ys), model.n), np.nan) for e in estimates}
    spread = np.full((len(ys), model.n), np.nan) if std else None
    for i, support in enumerate(supports):
        values, s = summarize(support, tuple(estimates), std, rng)
        if values is None:  # empty: the data contradict the model, and every later support is empty
            supports = supports[:i] + [EmptySet(model.n) for _ in supports[i:]]
            break
        for e in estimates:
            points[e][i] = values[e]
        if std:
            spread[i] = s
    settings = {"max_generators": max_generators, "max_constraints": max_constraints, "rescale": rescale,
                "reduction": [repr(m) for m in methods]}
    if on_inconsistent != "ignore":
        report_inconsistency(empty_support(model, ys, us, supports, "LSU-CZ"), on_inconsistent)
    return LSUResult("LSU-CZ", supports, points, spread, settings)


def empty_support(model: LSUModel, ys: np.ndarray, us: np.ndarray, supports: list,
                  name: str) -> Inconsistency | None:
    """The first empty support of an LSU filter (an `EmptySet`) as an `Inconsistency` of the model's
    support system (`outer_inconsistency`), or None."""
    if not any(isinstance(S, EmptySet) for S in supports):  # consistent runs build no system
        return None
    return outer_inconsistency(_support_system(model, us), model.prior, ys, supports, name)


def _support_system(model: LSUModel, us: np.ndarray) -> LinearSystem:
    """The LSU model as the library's `LinearSystem` on supports: x_{k+1} ∈ A x_k + 𝕎 + {B u_k},
    y_k ∈ C x_k + 𝕍 (k = t − 1)."""
    u = us[:-1] if len(us) > 1 else None
    return LinearSystem(model.A, None if u is None else model.B, model.C, W=model.W, V=model.V, u=u)
