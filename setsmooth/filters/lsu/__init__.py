"""Bayesian filtering of the LSU model on bounded supports (LSU paper, Kuklišová Pavelková).

`LSUModel` (4)–(6); `lsu_cz_filter` (Algorithm 1, constrained-zonotope supports) with the point
estimates of Section 3.3 (`lsu_point_estimate`); the baselines `lsuo_filter` (orthotopes) and
`lsup_filter` (parallelotopes). Each returns an `LSUResult`.
"""

from .cz import DEFAULT_MAX_CONSTRAINTS, DEFAULT_MAX_GENERATORS, lsu_cz_filter, lsu_cz_reduction
from .estimates import POINT_ESTIMATES, closest_to_zonotope_center, lsu_point_estimate, posterior_std
from .model import LSUModel
from .orthotope import lsuo_filter
from .parallelotope import lsup_filter
from .result import LSUResult

__all__ = ["LSUModel", "LSUResult", "lsu_cz_filter", "lsu_cz_reduction", "lsuo_filter", "lsup_filter",
           "lsu_point_estimate", "closest_to_zonotope_center", "posterior_std", "POINT_ESTIMATES",
           "DEFAULT_MAX_GENERATORS", "DEFAULT_MAX_CONSTRAINTS"]
