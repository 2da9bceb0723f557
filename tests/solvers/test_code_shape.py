"""The solver core stays small enough to read: no function above cyclomatic complexity 15 (radon's
count of decision points) and no module far above 350 lines in `setsmooth.solvers`.

The policy that once lived in one 188-line function of complexity 63 is now data (`policy.POLICIES`)
and a loop of small steps (`maximization.Search`); this test keeps it that way.
"""

from __future__ import annotations

from pathlib import Path

from radon.complexity import cc_visit

SOLVERS = Path(__file__).resolve().parents[2] / "setsmooth" / "solvers"
MAX_COMPLEXITY = 15
MAX_LINES = 360


def _modules() -> list[Path]:
    modules = sorted(SOLVERS.glob("*.py"))
    assert len(modules) > 10  # the premise: the package is where this test thinks it is
    return modules


def test_no_function_of_the_solver_core_is_above_complexity_15():
    offenders = [f"{path.name}:{block.fullname} ({block.complexity})"
                 for path in _modules() for block in cc_visit(path.read_text())
                 if block.complexity > MAX_COMPLEXITY]
    assert not offenders, offenders


def test_no_module_of_the_solver_core_is_far_above_350_lines():
    long = [f"{path.name} ({n})" for path in _modules()
            if (n := len(path.read_text().splitlines())) > MAX_LINES]
    assert not long, long
