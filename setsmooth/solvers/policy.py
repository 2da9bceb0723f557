"""Which backends a support program asks, in which order: the solver policy, as data.

`policy(program, purpose)` returns the attempts for one objective; `FactorConstraints.maximize` asks
them in turn and takes the first answer that its acceptance test passes (a 'solved' answer, or a
'candidate' whose independent check in the presolved units is within ``ACCURATE_GAP_TOL``). The
order is a function of the caller's purpose alone, never of time, load
or the queries asked before.

Purposes:

* 'plain': the caller takes the answer as it is: Clarabel's kept instance first (the cheapest solve),
  a refined fresh one, the simplex method, HiGHS's interior-point method last.
* 'bracketed': the caller brackets the answer between a certified bound and the solver's value and
  escalates it when the bracket is loose (`CZProgram._verified`). The warm-started simplex method
  first, free factors or not: on the recursion smoother's degenerate sets Clarabel stops at
  'AlmostSolved' on most directions, and simplex first is 1.5–4.5× faster there
  (``benchmarks/bench_bracketed_order.py``); on programs with free factors (trajectory sets,
  posterior views: the states are free) the least-squares correction of the multipliers
  (`certify.correct_multipliers`) makes the simplex method's as tight as Clarabel's, and simplex
  first took 30 reliability cases from 107 to 57 CPU-s with fewer escalations (777 for 1,205) and
  the same counts, and a 3-state trajectory smoother's certified hulls at T = 600 from 88 to 33 s
  (evidence: docs/numerical_core.md).
* 'escalated': a direction whose bracket was loose. A cold simplex solve first (a vertex with
  multipliers exact to rounding, from HiGHS's own presolve and scaling rather than another
  objective's basis), then a refined interior-point solve.

One purpose concerns a sequence of programs rather than one:

* 'along time': programs over one constraint matrix whose b and factor bounds change from one to
  the next, the same directions asked of each (the OIT-CZ windows, `parametric.ParametricSupport`),
  and those where a declared block of the matrix's entries changes too (the inner windows of the
  filter's hulls along time and the chords of hit-and-run on a constrained zonotope,
  `parametric.ParametricPoints`).
  The sequence backends (`backends.SEQUENCE_BACKENDS`) keep state along it: HiGHS's dual simplex
  method from each direction's last optimal basis. A direction they leave unsettled, or whose
  certificate fails, goes to the set's own verified support ('bracketed', then 'escalated').

An attempt ``on_full`` runs on the fully presolved program (linearly dependent rows dropped by a
rank-revealing QR, built only when the attempt is reached); where that program is the kept one, it
is the same attempt as without ``on_full`` and is asked only if that one is not in the policy.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Attempt", "policy", "POLICIES", "PURPOSES", "SEQUENCE_PURPOSES"]


@dataclass(frozen=True)
class Attempt:
    """One backend (`backends.BACKENDS`) on the kept or the fully presolved program."""

    backend: str
    on_full: bool = False


#: The attempts after a purpose's first two: a refined Clarabel solve and the simplex method on the
#: fully presolved program, HiGHS's interior-point method last (it settles nearly flat sets where
#: every simplex basis is singular and Clarabel reports 'NumericalError').
FALLBACKS = (Attempt("clarabel refined", True), Attempt("simplex", True), Attempt("interior"))

#: The attempts by purpose.
POLICIES: dict[str, tuple[Attempt, ...]] = {
    "plain": (Attempt("clarabel"), Attempt("clarabel refined")) + FALLBACKS,
    "bracketed": (Attempt("simplex"), Attempt("clarabel")) + FALLBACKS,
    "escalated": (Attempt("simplex cold"), Attempt("clarabel refined"),
                  Attempt("clarabel refined", True), Attempt("interior")),
    "along time": (Attempt("simplex along time"),),
}

#: The purposes of one program's objectives (`FactorConstraints.maximize`), whose attempts name
#: `backends.BACKENDS`.
PURPOSES = ("plain", "bracketed", "escalated")

#: The purposes of a sequence of programs, whose attempts name `backends.SEQUENCE_BACKENDS`.
SEQUENCE_PURPOSES = ("along time",)


def policy(program, purpose: str) -> tuple[Attempt, ...]:
    """The attempts for one objective over ``program`` (a `presolved.Presolved`), in order.

    Parameters
    ----------
    program : Presolved or ParametricSupport
        The kept presolved program, or the sequence's engine for 'along time' (the order does not
        depend on it today; the argument keeps the policy a function of the program and the
        purpose).
    purpose : {'plain', 'bracketed', 'escalated', 'along time'}
        What the caller does with the answer (module docstring).
    """
    if purpose not in PURPOSES + SEQUENCE_PURPOSES:
        raise ValueError(f"purpose must be one of {PURPOSES + SEQUENCE_PURPOSES}, got {purpose!r}")
    return POLICIES[purpose]
