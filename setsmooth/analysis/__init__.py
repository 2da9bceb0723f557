"""Analysis of linear set-membership filters (stability paper): observability decomposition (17),
observability index, detectability, marginal stability, and reproducible random systems.

``from setsmooth import analysis`` gives every public name here.
"""

from .observability import (ObservabilityDecomposition, is_detectable, is_marginally_stable, is_observable,
                            observability_decomposition, observability_index, spectral_radius)
from .random_systems import (RandomSystem, random_detectable_system, random_observable_system,
                             random_stable_matrix)

__all__ = ["ObservabilityDecomposition", "observability_decomposition", "observability_index",
           "is_observable", "is_detectable", "is_marginally_stable", "spectral_radius",
           "RandomSystem", "random_observable_system", "random_detectable_system", "random_stable_matrix"]
