"""setsmooth: set-membership filtering and smoothing with sets as CVXPY-constrained variables.

The public names are imported on first use (PEP 562 module ``__getattr__``): ``import setsmooth`` and
the command line (``setsmooth figures --help``) do not pay for CVXPY, SciPy and the solvers until a
set, system or estimator is touched. ``from setsmooth import *`` and ``setsmooth.Box`` behave as with
eager imports.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

#: Public name -> the submodule defining it (each listed in that submodule's ``__all__``;
#: ``tests/test_namespace.py`` checks both ways).
_EXPORTS = {
    **dict.fromkeys(["ConvexSet", "Box", "Zonotope", "ConstrainedZonotope", "HPolytope", "Ellipsoid",
                     "EmptySet", "Reals", "LinearMap", "MinkowskiSum", "Intersection",
                     "GeneralizedIntersection", "CartesianProduct", "reduce", "ReductionMethod",
                     "DropZeros", "DropDependentConstraints", "MergeParallelGenerators", "Rescale",
                     "EliminateConstraints", "Girard", "Combastel", "IntervalHull", "CORA_GIRARD",
                     "CORA_COMBASTEL", "VPolytope", "Containment", "is_subset",
                     "pontryagin_difference", "ChebyshevBall", "Polygon"], ".sets"),
    "SolverError": ".solvers",
    **dict.fromkeys(["LinearSystem", "NonlinearSystem", "simulate"], ".models"),
    **dict.fromkeys(["classical_filter", "interval_filter", "kalman_filter", "rts_smoother",
                     "KalmanResult", "oit_inspired_filter", "oit_cz_filter", "OITResult",
                     "first_inconsistency", "Inconsistency", "ModelInvalidationWarning",
                     "ModelInvalidatedError"], ".filters"),
    **dict.fromkeys(["optimal_smoother", "interval_smoother"], ".smoothers"),
    **dict.fromkeys(["trajectory_set", "filtering_map"], ".trajectories"),
    **dict.fromkeys(["LSUModel", "LSUResult", "lsu_cz_filter", "lsuo_filter", "lsup_filter",
                     "lsu_point_estimate"], ".filters.lsu"),
    **dict.fromkeys(["JointRange", "ScalarRelatedNoiseSystem"], ".models"),
    **dict.fromkeys(["joint_trajectory_set", "optimal_filter", "optimal_joint_smoother",
                     "augment_identical_process_noise"], ".filters.optimal"),
    **dict.fromkeys(["sampled_optimal_filter", "classical_interval_filter", "SampledRanges"],
                    ".filters.sampled"),
    **dict.fromkeys(["SetEstimates", "Estimates", "IntervalEstimates"], ".results"),
    **dict.fromkeys(["observation_set", "observation_information_set", "observation_information_tower"],
                    ".analysis.observation_information"),
}

#: Public names that are modules -> the module.
_MODULES = {
    "analysis": ".analysis",
    "montecarlo": ".runs.montecarlo",
    "paper_examples": ".papers.smoothing_examples",
    "rethinking_examples": ".papers.rethinking_examples",
    "references": ".papers.references",
}

#: The public namespace: every name above, one list (its order is `_EXPORTS`'s, then the modules').
__all__ = [*_EXPORTS, *_MODULES]


def __getattr__(name: str) -> Any:
    if name in _MODULES:
        value = import_module(_MODULES[name], __name__)
    elif name in _EXPORTS:
        value = getattr(import_module(_EXPORTS[name], __name__), name)
    else:
        raise AttributeError(f"module 'setsmooth' has no attribute {name!r}")
    globals()[name] = value  # later look-ups are plain attribute reads
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # pragma: no cover  (static tools see the eager imports)
    from . import analysis
    from .papers import smoothing_examples as paper_examples
    from .runs import montecarlo
    from .filters import KalmanResult, classical_filter, interval_filter, kalman_filter, rts_smoother
    from .papers import references
    from .filters.lsu import (LSUModel, LSUResult, lsu_cz_filter, lsu_point_estimate, lsuo_filter,
                              lsup_filter)
    from .filters import OITResult, oit_cz_filter, oit_inspired_filter
    from .filters import (Inconsistency, ModelInvalidatedError, ModelInvalidationWarning,
                          first_inconsistency)
    from .analysis.observation_information import (observation_information_set,
                                                   observation_information_tower, observation_set)
    from .results import Estimates, IntervalEstimates, SetEstimates
    from .sets import (Box, CartesianProduct, ConstrainedZonotope, ConvexSet, Ellipsoid, EmptySet,
                       GeneralizedIntersection, HPolytope, Intersection, LinearMap, MinkowskiSum, Reals,
                       Zonotope)
    from .sets import (CORA_COMBASTEL, CORA_GIRARD, Combastel, DropDependentConstraints, DropZeros,
                       EliminateConstraints, Girard, IntervalHull, MergeParallelGenerators,
                       ReductionMethod, Rescale, reduce)
    from .sets import ChebyshevBall, Containment, Polygon, VPolytope, is_subset, pontryagin_difference
    from .smoothers import interval_smoother, optimal_smoother
    from .solvers import SolverError
    from .models import LinearSystem, NonlinearSystem, simulate
    from .trajectories import filtering_map, trajectory_set
    from .papers import rethinking_examples
    from .filters.optimal import (augment_identical_process_noise, joint_trajectory_set, optimal_filter,
                                  optimal_joint_smoother)
    from .filters.sampled import SampledRanges, classical_interval_filter, sampled_optimal_filter
    from .models import JointRange, ScalarRelatedNoiseSystem
