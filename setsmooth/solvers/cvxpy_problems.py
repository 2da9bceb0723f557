"""CVXPY problems solved through `conic.ConicForm`: compiled by CVXPY, solved and checked here.

`conic_form` compiles a problem into the conic data Clarabel takes; `solve_problem` solves it and
writes the solution back into the problem's variables (CVXPY's own inversion of its reductions).
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .conic import ConicForm

__all__ = ["conic_form", "solve_problem"]


def conic_form(problem: cp.Problem, context: str, kind: str) -> tuple[ConicForm, np.ndarray, object,
                                                                       object]:
    """Compile ``problem``: (form, q, chain, inverse data)."""
    data, chain, inverse = problem.get_problem_data(cp.CLARABEL, solver_opts={})
    if data.get("lower_bounds") is not None or data.get("upper_bounds") is not None:
        raise ValueError("conic_form handles problems without variable bounds only")
    return (ConicForm(data["A"], data["b"], data["dims"], context, kind, data.get("P")),
            np.asarray(data["c"], dtype=float), chain, inverse)


def solve_problem(problem: cp.Problem, context: str, kind: str) -> str:
    """Solve a CVXPY problem through `ConicForm`; on 'optimal' its variables hold the solution.

    Returns
    -------
    str
        'optimal', 'infeasible' or 'unbounded'.
    """
    form, q, chain, inverse = conic_form(problem, context, kind)
    sol = form.solve(q)
    if sol.status == "optimal":
        _unpack(problem, sol.z, sol.value, chain, inverse)
    return sol.status


class _Raw:
    """The fields of a Clarabel solution that CVXPY's inversion reads."""

    def __init__(self, z: np.ndarray, value: float):
        self.status, self.x, self.z, self.obj_val = "Solved", z, None, value  # no duals needed
        self.solve_time, self.iterations = 0.0, 0


def _unpack(problem: cp.Problem, z: np.ndarray, value: float, chain, inverse) -> None:
    solution = chain.invert(_Raw(z, value), inverse)
    problem.unpack(solution)
