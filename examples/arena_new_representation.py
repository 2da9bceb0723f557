"""A new set representation in the arena: define it by its constraints, register a filter, compare.

The representation is an axis-aligned box written the way a researcher would first write any new set:
one `constraints(x)` method and nothing else (setsmooth's own `Box` knows closed forms; this one does
not, so every query is a convex program). The filter built on it is the classical filter, Algorithm 1
of the stability paper, with each posterior replaced by the smallest such box: bounded complexity,
outer bounds.

One call, ``arena.register(name, fn)``, puts it beside the built-in estimators; `run_arena` then
reports, per problem, whether its boxes kept the true state and contained the exact posterior's hull,
how much larger they are, and what they cost. The table, the JSON record and the figure (tightness
against time, unsound entries in red) go to examples/out/arena/, and the figure also to
examples/out/arena_new_representation.png, where the documentation's gallery takes it from.
"""

import shutil
from pathlib import Path

import cvxpy as cp
import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth import arena  # noqa: E402
from setsmooth.filters.steps import predict, update  # noqa: E402


class ConstraintBox(ss.ConvexSet):
    """{x : lo ≤ x ≤ hi}, known only through its constraints."""

    def __init__(self, lo, hi):
        self.lo, self.hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
        self.dim = self.lo.size

    def constraints(self, x):
        return [x >= self.lo, x <= self.hi]


def constraint_box_filter(system, X0, ys):
    """Algorithm 1 with every posterior replaced by its interval hull, as a ConstraintBox: outer bounds."""
    posteriors = []
    for k, y in enumerate(ys):
        prior = X0 if k == 0 else predict(system, k - 1, posteriors[-1])
        hull = update(system, k, prior, y).interval_hull()
        posteriors.append(ConstraintBox(hull.lo, hull.hi))
    return posteriors


arena.register("constraint_box", constraint_box_filter)        # the one call

# Small: two runs over 10 steps on two problems. A function defined in a script reaches process-pool
# workers only when they are forked, so the runs are serial here; put the filter in an importable
# module to run it in parallel or on a Dask cluster.
result = arena.run_arena(problems=["example31", "mass_spring_damper"],
                         estimators=["exact_filter", "reduced_girard", "constraint_box"],
                         runs=2, seed=0, horizon=10, executor="serial")
print(arena.markdown_table(result))
out = Path(__file__).resolve().parent / "out"
paths = arena.write_outputs(result, out / "arena")
shutil.copyfile(paths["figure"], out / "arena_new_representation.png")
print(f"saved {paths['figure']} and {out / 'arena_new_representation.png'}")
