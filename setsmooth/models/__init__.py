"""Models: linear and nonlinear systems with bounded noises, and how their noises are related.

`linear_system` holds `LinearSystem`, `nonlinear_system` `NonlinearSystem` and `simulation` `simulate`
(`systems` re-exports the three); `statespace` (`LinearSystem.from_statespace`) and `discretization`
build a `LinearSystem` from a python-control model, sampled soundly for noise bounded at every instant;
`related_noise` states how x_0, the process and the measurement noises are related (`JointRange`,
`ScalarRelatedNoiseSystem`); `intervals` checks the η and the intervals of scalar monotone systems and
holds their interval ranges (`IntervalEstimates`).
"""

from .linear_system import LinearSystem
from .nonlinear_system import NonlinearSystem
from .related_noise import JointRange, ScalarRelatedNoiseSystem
from .simulation import simulate

__all__ = ["LinearSystem", "NonlinearSystem", "simulate", "JointRange", "ScalarRelatedNoiseSystem"]
