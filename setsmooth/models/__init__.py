"""Models: linear and nonlinear systems with bounded noises, and how their noises are related.

`systems` holds `LinearSystem`, `NonlinearSystem` and `simulate`; `statespace` and `discretization`
build a `LinearSystem` from a python-control model, sampled soundly for noise bounded at every instant;
`related_noise` states how x_0, the process and the measurement noises are related (`JointRange`,
`ScalarRelatedNoiseSystem`); `intervals` checks the η and the intervals of scalar monotone systems and
holds their interval ranges (`IntervalEstimates`).
"""

from .related_noise import JointRange, ScalarRelatedNoiseSystem
from .systems import LinearSystem, NonlinearSystem, simulate

__all__ = ["LinearSystem", "NonlinearSystem", "simulate", "JointRange", "ScalarRelatedNoiseSystem"]
