"""Dynamical systems with bounded noises, and their simulation, under one name.

`LinearSystem` is defined in `setsmooth.models.linear_system`, `NonlinearSystem` in
`setsmooth.models.nonlinear_system` and `simulate` in `setsmooth.models.simulation`; this module
re-exports them, so ``from setsmooth.models.systems import LinearSystem`` keeps working.
"""

from .linear_system import LinearSystem
from .nonlinear_system import NonlinearSystem
from .simulation import simulate

__all__ = ["LinearSystem", "NonlinearSystem", "simulate"]
