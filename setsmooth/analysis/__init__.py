"""Analysis of linear set-membership filters (stability paper).

Observability decomposition (17), observability index, detectability and marginal stability
(`observability`); reproducible random systems (`random_systems`); the OIT diameter bound (16) and Υ∞
of Algorithm 3 (`bounds`); Theorem 2, Proposition 2 and Corollary 1 (`stability`); estimation gaps
and diameters (`hausdorff`). ``from setsmooth import analysis`` gives every public name here.
"""

from .bounds import (OITBound, Upsilon, minimize_oit_diameter_bound, noise_diameter, oit_diameter_bound,
                     upsilon_inf, upsilon_search)
from .hausdorff import (diameter, hausdorff_distance, point_polygon_distance, polytope_vertices,
                        vertex_hausdorff_surrogate)
from .observability import (ObservabilityDecomposition, is_detectable, is_marginally_stable, is_observable,
                            observability_decomposition, observability_index, spectral_radius)
from .random_systems import (RandomSystem, random_detectable_system, random_observable_system,
                             random_stable_matrix)
from .stability import (Condition, CriterionResult, check_bounded_gap_necessary, check_egregium,
                        check_stability_criterion, condition_i, condition_ii, contains_set)

__all__ = ["ObservabilityDecomposition", "observability_decomposition", "observability_index",
           "is_observable", "is_detectable", "is_marginally_stable", "spectral_radius",
           "RandomSystem", "random_observable_system", "random_detectable_system", "random_stable_matrix",
           "oit_diameter_bound", "OITBound", "minimize_oit_diameter_bound", "noise_diameter",
           "Upsilon", "upsilon_inf", "upsilon_search",
           "Condition", "CriterionResult", "check_stability_criterion", "check_bounded_gap_necessary",
           "check_egregium", "condition_i", "condition_ii", "contains_set",
           "hausdorff_distance", "vertex_hausdorff_surrogate", "polytope_vertices", "diameter",
           "point_polygon_distance"]
