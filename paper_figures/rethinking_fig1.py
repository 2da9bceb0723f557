"""Rethinking paper Fig. 1: the law of total range (9) and Bayes' rule for uncertain variables (10).

Prior ⟦x⟧ = [1, 3], likelihood ⟦y | x⟧ = [x, x + 2], observation y = 2. Computed with the library's set
operations: the joint range ⟦x, y⟧ = M([1, 3] × [0, 2]) with M = [[1, 0], [1, 1]] (a zonotope, (4)); the
marginal ⟦y⟧ is its projection (law of total range: the union of ⟦y | x⟧ over x ∈ ⟦x⟧); the likelihood
⟦y | x⟧ and the posterior ⟦x | y⟧ are intersections with the lines {x} × ℝ and ℝ × {y} projected
((39)–(40): the projection form of Bayes' rule). No Monte Carlo: ``runs`` is ignored.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import setsmooth as ss

import _rethinking_examples as ex
import _verdicts as v
from _outputs import Stopwatch, cli, finish, row

NAME = "rethinking_fig1"
PAPER = ex.PAPER
DEFAULT_RUNS = 1


def joint_range() -> ss.ConvexSet:
    """⟦x, y⟧ = {(x, x + n) : x ∈ ⟦x⟧, n ∈ [0, 2]} (rethinking (4))."""
    prior_and_noise = ss.Box([ex.FIG1_PRIOR[0], ex.FIG1_NOISE[0]], [ex.FIG1_PRIOR[1], ex.FIG1_NOISE[1]])
    return np.array([[1.0, 0.0], [1.0, 1.0]]) @ prior_and_noise


def conditional(joint: ss.ConvexSet, given: int, value: float) -> ss.ConvexSet:
    """⟦other | coordinate ``given`` = value⟧: the joint range cut by a line, projected ((38)–(39))."""
    cut = joint.intersect_preimage(np.eye(2)[[given]], ss.Box([value], [value]))
    return cut.project([1 - given])


def interval(S: ss.ConvexSet) -> list[float] | None:
    """[lo, hi] of a 1-D set (None when empty), rounded for the report."""
    if S.is_empty():
        return None
    hull = S.interval_hull()
    return [round(float(hull.lo[0]), 9) + 0.0, round(float(hull.hi[0]), 9) + 0.0]


def main(runs: int = DEFAULT_RUNS, seed: int = 0, out: Path | None = None, workers: int | None = None,
         progress: bool = True, executor=None) -> dict:
    clock = Stopwatch()
    joint = joint_range()
    marginal_y = interval(joint.project([1]))
    posterior = interval(conditional(joint, 1, ex.FIG1_Y))
    likelihoods = {x: interval(conditional(joint, 0, x)) for x in ex.FIG1_PROBES}
    # Bayes' rule (10) pointwise, on a grid of the prior: x is kept iff ⟦y | x⟧ ∋ y.
    grid = np.linspace(*ex.FIG1_PRIOR, 41)
    kept = [x for x in grid if conditional(joint, 0, x).contains([ex.FIG1_Y])]
    by_rule = [float(min(kept)), float(max(kept))]
    rows = [
        row("⟦y⟧ by the law of total range (9)", "[1, 5]", f"{marginal_y}"),
        row("⟦y | x = 1.5⟧; meets y = 2", "[1.5, 3.5]; yes",
            f"{likelihoods[1.5]}; {'yes' if likelihoods[1.5][0] <= ex.FIG1_Y <= likelihoods[1.5][1] else 'no'}"),
        row("⟦y | x = 2.5⟧; meets y = 2", "[2.5, 4.5]; no",
            f"{likelihoods[2.5]}; {'yes' if likelihoods[2.5][0] <= ex.FIG1_Y <= likelihoods[2.5][1] else 'no'}"),
        row("posterior ⟦x | y = 2⟧ (projection of the cut joint range)", "[1, 2]", f"{posterior}"),
        row("posterior by Bayes' rule (10) on a 41-point grid of ⟦x⟧", "[1, 2]",
            f"[{by_rule[0]:g}, {by_rule[1]:g}]"),
    ]
    exact = "none (exact set algebra)"
    checks = [v.value("⟦y⟧ by the law of total range (9)", marginal_y, [1.0, 5.0], rel_tol=1e-9, error=exact),
              v.value("posterior ⟦x | y = 2⟧", posterior, [1.0, 2.0], rel_tol=1e-9, error=exact),
              v.value("⟦y | x = 1.5⟧ and ⟦y | x = 2.5⟧", [*likelihoods[1.5], *likelihoods[2.5]],
                      [1.5, 3.5, 2.5, 4.5], rel_tol=1e-9, error=exact)]
    data = {
        "figure": "Rethinking paper Fig. 1",
        "rows": rows,
        "checks": checks,
        "settings": {"runs": runs, "seed": seed, "prior": ex.FIG1_PRIOR, "likelihood": "[x, x + 2]",
                     "y": ex.FIG1_Y, "method": "zonotope joint range, cuts and projections (set algebra)"},
        "published": {"runs": "-"},
        "joint_range_vertices": joint.vertices_2d(), "marginal_y": marginal_y, "posterior": posterior,
        "likelihoods": {str(x): v for x, v in likelihoods.items()},
    }
    return finish(out, NAME, PAPER, _plot(joint, marginal_y, posterior, likelihoods), data, clock)


def _plot(joint, marginal_y, posterior, likelihoods):
    fig, ax = plt.subplots(figsize=(6.4, 6.2))
    joint.plot(ax, facecolor="tab:blue", alpha=0.15, edgecolor="tab:blue", label=r"$[\![x, y]\!]$")
    ax.plot([ex.FIG1_PRIOR[0] - 0.5, ex.FIG1_PRIOR[1] + 0.5], [ex.FIG1_Y] * 2, color="tab:purple", ls="-.",
            label=f"$y = {ex.FIG1_Y:g}$")
    for x, color in zip(ex.FIG1_PROBES, ("tab:green", "tab:red")):
        lo, hi = likelihoods[x]
        ax.axvline(x, color=color, ls="--", lw=1)
        ax.plot([x, x], [lo, hi], color=color, lw=4, label=fr"$[\![y \mid x = {x:g}]\!] = [{lo:g}, {hi:g}]$")
    ax.plot(posterior, [ex.FIG1_Y] * 2, color="tab:purple", lw=5,
            label=fr"$[\![x \mid y = 2]\!] = [{posterior[0]:g}, {posterior[1]:g}]$")
    ax.plot([ex.FIG1_PRIOR[0] - 0.4] * 2, marginal_y, color="k", lw=4,
            label=fr"$[\![y]\!] = [{marginal_y[0]:g}, {marginal_y[1]:g}]$ (law of total range)")
    ax.plot(ex.FIG1_PRIOR, [0.3, 0.3], color="tab:blue", lw=4, label=r"$[\![x]\!] = [1, 3]$")
    ax.set(xlabel="$x$", ylabel="$y$", xlim=(0.3, 3.7), ylim=(0, 5.6),
           title="Law of total range and Bayes' rule for uncertain variables")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    cli(main, DEFAULT_RUNS, __doc__.splitlines()[0])
