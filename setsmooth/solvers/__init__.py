"""Every convex program in setsmooth is solved in this package: the one door to the solvers.

* `clarabel_lp`: the Clarabel adapter, its settings, and the status policy (`SolverError`).
* `factor_set`: the **fast path** for constrained zonotopes: the factor set {ξ : Aξ = b, |ξ| ≤ h},
  presolved (`presolve`, `free_factors`), one sparse LP per direction (`FactorConstraints`): the
  attempts of the solver policy (`policy`, as data), each answered by a backend (`backends`:
  Clarabel; HiGHS by `highs` and `warm_simplex`) and judged by `maximization`; emptiness by an
  elastic phase-one program (`phase_one`), unbounded directions by a recession program
  (`recession`). `cz_program`: the support and certificate programs of one CZ (`CZProgram`),
  `cz_membership` its membership program; `certify`: floating-point-sound weak-duality bounds;
  `small_products`: a small program's sparse products summed densely, bit for bit scipy's.
* `generic`: the **generic path** for any set: its CVXPY constraints with the direction as a
  ``cp.Parameter``, compiled once per program (`GenericProgram`), and the Chebyshev ball of an
  H-polytope.
* `conic`: a compiled conic program solved by Clarabel directly (`ConicForm`): equilibration
  (`conic_scaling`), verification of answers (`conic_checks`), Clarabel's status names, emptiness by
  an elastic phase-one program; `cvxpy_problems`: CVXPY problems solved through it.
* `closest`: the point of a constrained zonotope closest to a reference in the 1-, 2- or ∞-norm
  (`closest_point`), one program on the factor set.
* `instances`: solver instances kept per thread (`cached_instance`), never on a set.

The two paths give the same answers; the tests run both on the same sets and compare.
"""

from .clarabel_lp import LPSolution, SolverError, solve_lp
from .closest import closest_point
from .conic import ConicForm
from .cz_program import CZProgram, SupportSolution
from .factor_set import STACK_MAX_VARIABLES, FactorConstraints
from .generic import GenericProgram, chebyshev_ball

__all__ = ["SolverError", "LPSolution", "solve_lp", "FactorConstraints", "CZProgram",
           "STACK_MAX_VARIABLES", "SupportSolution", "GenericProgram", "chebyshev_ball", "ConicForm",
           "closest_point"]
