"""The independent check of a conic answer (`conic.ConicForm`), in the equilibrated data.

Clarabel's own tolerances are global; `violations` checks primal feasibility row by row, dual
feasibility column by column and the duality gap, each against its own terms.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol

__all__ = ["Magnitudes", "violations"]


@dataclass(frozen=True)
class Magnitudes:
    """|A| and its largest entry in every row and column: the terms `violations` measures each
    row and column against. A function of A alone, so made once per matrix (a `conic.ConicForm`
    keeps it with its scaled data) rather than once per answer checked."""

    abs: sp.spmatrix
    row: np.ndarray
    col: np.ndarray

    @classmethod
    def of(cls, A) -> "Magnitudes":
        absA = abs(A)
        return cls(absA, np.asarray(absA.max(axis=1).todense()).ravel(),
                   np.asarray(absA.max(axis=0).todense()).ravel())


def violations(q: np.ndarray, z: np.ndarray, y: np.ndarray, A, sizes: Magnitudes, b: np.ndarray,
               n_zero: int, n_linear: int, soc: list[int], P=None, strict: bool = False) -> list[str]:
    """Check the answer in the equilibrated data given to Clarabel, where every row and column
    has comparable weight: primal feasibility row by row (relative to the row's size times the
    solution's, plus its right-hand side), dual feasibility column by column, and the duality
    gap. Clarabel's own tolerances are global, so they let a row written at a much smaller
    scale than the others go unnoticed. ``sizes`` is ``Magnitudes.of(A)``."""
    check = tol.SOLVER_CHECK_TOL
    absA = sizes.abs
    r = b - A @ z  # the slack s, which must lie in K
    # Each row against its own terms Σⱼ|A_ij z_j| + |b_i|: a row of 1e-8-sized terms must hold to
    # 1e-14, however large the other rows.
    # The floor is Clarabel's own accuracy on the equilibrated data, where the solution's
    # entries have comparable sizes: a row whose terms all vanish holds to rounding, not 0.
    row_size = sizes.row
    # (The equilibrated data have unit size, so a solution at the origin is measured against 1.)
    z_unit = max(np.abs(z).max(initial=0.0), 1.0)
    allowed = check * (absA @ np.abs(z) + np.abs(b)) + tol.SOLVER_TOL * row_size * z_unit
    bad = []
    lin = slice(n_zero, n_linear)
    if np.any(np.abs(r[:n_zero]) > allowed[:n_zero]) or np.any(-r[lin] > allowed[lin]):
        bad.append("primal feasibility")
    row = n_linear
    for k in soc:
        if np.linalg.norm(r[row + 1:row + k]) - r[row] > allowed[row:row + k].max():
            bad.append("primal feasibility (second-order cone)")
        row += k
    if P is None and not np.any(q):
        return bad  # a feasibility program: every feasible point is optimal
    # Dual: Aᵀy + q = 0 with y ∈ K* (Clarabel keeps y in the self-dual cones K), column by column
    # against its own terms, with the same kind of floor (multipliers of inactive rows are
    # ~1e-10, not 0); then the gap qᵀz + bᵀy against the terms of both sums.
    col_size = sizes.col
    dual_allowed = check * (absA.T @ np.abs(y) + np.abs(q)) \
        + tol.SOLVER_TOL * (col_size * np.abs(y).max(initial=0.0) + np.abs(q).max(initial=0.0))
    Pz = np.zeros_like(z) if P is None else P @ z
    dual_allowed = dual_allowed + check * (np.zeros_like(z) if P is None else abs(P) @ np.abs(z))
    if np.any(np.abs(A.T @ y + q + Pz) > dual_allowed):
        bad.append("dual feasibility")
    y_size = np.abs(y).max(initial=0.0)
    terms = np.abs(q) @ np.abs(z) + np.abs(b) @ np.abs(y) + np.abs(z) @ np.abs(Pz)
    floor = tol.SOLVER_TOL * (np.abs(q).max(initial=0.0) * z_unit
                              + np.abs(b).max(initial=0.0) * y_size)
    gap = abs(q @ z + z @ Pz + b @ y)
    if gap > check * terms + floor:
        bad.append("duality gap")
    elif strict and gap > check * terms:
        # The floor is the solver's accuracy on unit-size variables; where the answer's own
        # terms are far smaller (the objective's variables far below the others: 1e-7 against
        # 1 in a CZ written in coordinates of 1e-12 before `ConicForm._defined_sizes`), it passed
        # answers 7e-5 of the scale off. The first answer must close the gap relative to its
        # terms; failing that it is solved again rescaled to it (`ConicForm._solve_verified`), where the
        # floor is the solver's accuracy and a gap of vanishing terms (support 0) stands.
        bad.append("duality gap relative to the objective's own terms")
    return bad
