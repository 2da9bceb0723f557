"""The tolerance policy: every numerical decision in setsmooth uses these constants.

Values returned by interior-point solvers are accurate to roughly ``SOLVER_TOL`` relative to the
problem's scale, so every decision that compares solver output (membership, emptiness, equality of
support values, vertex detection) is made with a margin derived from these constants rather than with
a literal scattered through the code.

``scale`` in the helpers below is a magnitude of the data involved (for example ``1 + |c| + Σ h|G|``),
so that a tolerance means the same thing for a set of width 1e-3 and one of width 1e3.
"""

from __future__ import annotations

import numpy as np

#: Feasibility and optimality-gap tolerance asked of Clarabel (absolute and relative).
SOLVER_TOL = 1e-9

#: Relative accuracy to which a reduced-accuracy ('AlmostSolved') LP answer is verified (duality gap,
#: primal feasibility) before it is returned; an answer failing the check raises ``SolverError``.
SOLVER_CHECK_TOL = 1e-6

#: A reduced-accuracy answer that passes the check above with a relative duality gap (and
#: residuals) below this is used at once; a looser one is kept while the fallbacks (refinement, the
#: fully presolved program, the simplex method) look for a tighter one.
ACCURATE_GAP_TOL = 1e-8

#: Relative margin used to decide membership ``contains`` when the caller gives no ``tol``.
MEMBERSHIP_TOL = 1e-7

#: Relative tolerance below which a reduced cost on an unbounded factor counts as zero, so that a
#: weak-duality certificate stays finite (see ``solvers.factor_set``).
REDUCED_COST_TOL = 1e-7

#: Relative violation above which a set counts as empty, on both paths: the optimum t* of the elastic
#: phase-one program (every constraint relaxed by t) in equilibrated units, relative to 1 + ‖b̂‖∞. On
#: the fast path min{t : |Âη − b̂| ≤ t, |η_B| ≤ 1} in the presolved units (rows of unit ∞-norm,
#: bounded factors of unit bound; ``solvers.factor_set``), on the generic path the conic form's
#: equilibrated rows (``solvers.conic``). Ten times the solver's accuracy, so that the verdict is not
#: solver noise; a set emptied by less is within the tolerance of a non-empty one and solved as such.
EMPTINESS_TOL = 1e-8

#: Multipliers that will certify a support value should cancel the objective on free factors to
#: this (presolved units); a solution leaving more is solved again with iterative refinement.
CERTIFICATE_LEAK_TOL = 1e-11

#: Relative tolerance of the rank decisions (null spaces, pseudo-inverses, recession directions).
RANK_TOL = 1e-10

#: Relative tolerance for merging or discarding polygon vertices in ``vertices_2d``.
VERTEX_TOL = 1e-7


def scaled(tol: float, scale: float) -> float:
    """Return the absolute tolerance ``tol * max(1, scale)``."""
    return tol * max(1.0, float(scale))


def nearly_equal(a: float, b: float, tol: float = MEMBERSHIP_TOL) -> bool:
    """Decide ``a == b`` for two (possibly infinite) values with a relative tolerance."""
    if np.isinf(a) or np.isinf(b):
        return bool(a == b)
    return abs(a - b) <= scaled(tol, max(abs(a), abs(b)))

#: Relative tolerance below which two generators (unit-normalized, sign-aligned) are candidates for
#: merging by `MergeParallelGenerators`; what is left over beyond rounding level is kept in a box, so
#: the merge never shrinks the set.
PARALLEL_TOL = 1e-10

#: Screen of `MergeParallelGenerators` on the Gram matrix of unit generators: |cos| ≥ 1 − this makes
#: a pair a candidate, confirmed on the columns against ``PARALLEL_TOL`` (the Gram matrix cannot
#: resolve angles below ~1e-8).
PARALLEL_COS_TOL = 1e-6

#: Margin of the spectral verdicts of `setsmooth.analysis`: (A, C) is detectable when ρ(Ã_ō) < 1 − this.
SPECTRAL_TOL = 1e-9

#: Eigenvalues within this of the unit circle count as on it for marginal stability, and are grouped
#: into one cluster within this distance (a defective eigenvalue of multiplicity 3 splits by ~eps^{1/3}).
SPECTRAL_CLUSTER_TOL = 1e-5

#: Υ∞ (Algorithm 3, Line 1): the golden-section search over γ ∈ (ρ(Ã_ō), 1) stops when the bracket
#: is narrower than this fraction of 1 − ρ (the returned value is attained at a γ, so it stays a bound).
UPSILON_GAMMA_TOL = 1e-6
#: Relative error (to the largest entry) assumed of each matrix exponential computed by
#: `scipy.linalg.expm` when bounding a continuous-time noise integral (`setsmooth.models.discretization`);
#: the bound uses the larger of this and the observed disagreement between e^{Aτ_j} and e^{Aδ/2}(e^{Aδ})^j.
EXPM_RELATIVE_ERROR = 1e-13
#: Relative rounding level of a set's coordinates in the default membership margin (`ConvexSet.contains`):
#: the margin is ``MEMBERSHIP_TOL`` times the set's width plus this times the coordinates' magnitude,
#: the rounding a chain of set operations accumulates (about 450 unit roundoffs).
MAGNITUDE_TOL = 1e-13
#: Relative slack with which `sets.cz_vertices.cz_vertices` accepts a basic solution whose basic factors
#: exceed their bounds by rounding (the point is then clipped to the bounds).
VERTEX_FEASIBILITY_TOL = 1e-9
#: A-posteriori check of every fast-path support value (`solvers.cz_program`): the certified
#: weak-duality bound U and the solver's primal value L of the same solve bracket the exact support,
#: so U − L is a proven bound on the error of both. It must be below this fraction of the set's width
#: along the direction (L(d) + L(−d), when −d is queried too, as interval hulls do), else the
#: direction is solved again by the simplex method. A tenth of the accuracy the estimators promise.
SUPPORT_GAP_TOL = 1e-7

#: Floor of that check relative to the magnitude |U| + |L| of the values, for the rounding of the
#: solver's value L = dᵀc + (Gᵀd)ᵀξ (8 ulps); the certificate's own rounding allowance, which
#: `certified_bound` reports, is added to it four times. (2⁻⁴⁰, the floor before, let a bracket of
#: 3e-6 pass at states 1.9e6: 2e-6 of a unit-width hull.)
SUPPORT_GAP_FLOOR = 2.0 ** -50

#: The relative width w / (|h(d)| + |h(−d)|) below which a plain support value is not guaranteed to
#: 1e-7 of the width (the bracket's floor decides there, ``SUPPORT_GAP_FLOOR / SUPPORT_GAP_TOL`` ≈
#: 8.9e-9): along such directions the plain value is the certified bound (docs/numerical_core.md).
GUARANTEED_WIDTH_RATIO = SUPPORT_GAP_FLOOR / SUPPORT_GAP_TOL
