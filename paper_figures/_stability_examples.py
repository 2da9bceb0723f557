"""What the stability paper's figure scripts share: examples (25)–(26), the authors' data, the designers.

Figs. 2 and 3 run four designers on one simulated trajectory of example (25) (observable) and (26)
(detectable): Alice [0, 4]², Bob [−4, 4]² and David [−2, 2]² with the classical filter (Algorithm 1),
Carol [−1, 1]² with the OIT-inspired filter (Algorithm 2); the true initial set is [1, 3]².

The trajectory is the authors' own: MATLAB's ``rng(seed); rand(r, c)`` (Mersenne twister, filled
column-major) equals ``numpy.random.RandomState(seed).random_sample(r*c).reshape(c, r).T`` bit for bit,
with the draw order of their scripts (w_0..w_50, then v_0..v_50, then x_0). RandomState appears here
only to replay those seeds; everything else draws from `numpy.random.Generator`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import setsmooth as ss
from setsmooth import analysis

PAPER = "stability"
PAPER_TITLE = ("Stability paper — Cong, Wang, Zhou, *Stability of Linear Set-Membership Filters With "
               "Respect to Initial Conditions: An Observation-Information Perspective* (Automatica 2024)")
T = 50                                          # k = 0..50 in Figs. 2–3
TRUE_X0 = ((1.0, 1.0), (3.0, 3.0))              # ⟦x_0⟧ = [1, 3]²
DESIGNERS = {"Alice": ((0.0, 0.0), (4.0, 4.0)), "Bob": ((-4.0, -4.0), (4.0, 4.0)),
             "Carol": ((-1.0, -1.0), (1.0, 1.0)), "David": ((-2.0, -2.0), (2.0, 2.0))}
CLASSICAL = ("Alice", "Bob", "David")           # Algorithm 1; Carol runs Algorithm 2
GAP_TOL = 1e-6                                  # a gap below this (absolute, 2-norm) counts as zero


@dataclass(frozen=True)
class Example:
    """One of the paper's 2-D examples with the authors' seed and the P of Carol's Algorithm 2."""

    name: str
    A: tuple
    C: tuple
    seed: int
    P: tuple | None = None          # Carol's decomposition (paper: P = I₂ for (25), [[0, 1], [−1, 0]] for (26))
    B: tuple = ((0.5,), (1.0,))

    def system(self) -> ss.LinearSystem:
        unit = ss.Box([-1.0], [1.0])
        return ss.LinearSystem(np.array(self.A), None, np.array(self.C), E=np.array(self.B), W=unit, V=unit)

    def decomposition(self) -> analysis.ObservabilityDecomposition:
        if self.P is None:
            return analysis.observability_decomposition(self.A, self.C, B=self.B, P=np.eye(2), n_o=2)
        return analysis.observability_decomposition(self.A, self.C, B=self.B, P=self.P, n_o=1)


EXAMPLE_25 = Example("(25)", ((1.0, 1.0), (0.0, 1.0)), ((1.0, 0.0),), seed=24629)
EXAMPLE_26 = Example("(26)", ((0.5, 1.0), (0.0, 1.0)), ((0.0, 1.0),), seed=2330, P=((0.0, 1.0), (-1.0, 0.0)))


def matlab_rand(rs: np.random.RandomState, rows: int, cols: int) -> np.ndarray:
    """MATLAB's ``rand(rows, cols)`` after ``rng(seed)``: column-major fill of the Mersenne twister."""
    return rs.random_sample(rows * cols).reshape(cols, rows).T


def authors_data(example: Example) -> tuple[np.ndarray, np.ndarray]:
    """The authors' trajectory (x_k, y_k), k = 0..T, regenerated from their seed (see module docstring)."""
    rs = np.random.RandomState(example.seed)
    system = example.system()
    w = 2.0 * (matlab_rand(rs, system.p, T + 1) - 0.5)
    v = 2.0 * (matlab_rand(rs, system.m, T + 1) - 0.5)
    x0 = 2.0 * (matlab_rand(rs, system.n, 1) - 0.5)[:, 0] + 2.0
    xs = [x0]
    for k in range(T):
        xs.append(system.step(k, xs[-1], w[:, k]))
    xs = np.array(xs)
    ys = np.array([system.measure(k, xs[k], v[:, k]) for k in range(T + 1)])
    return xs, ys


def box(lo_hi) -> ss.Box:
    return ss.Box(*lo_hi)


def designer_estimates(example: Example, ys: np.ndarray) -> dict[str, list[ss.ConvexSet]]:
    """Posterior sets of the truth (from ⟦x_0⟧) and of the four designers, k = 0..T."""
    system = example.system()
    sets = {"true": ss.classical_filter(system, box(TRUE_X0), ys)}
    for name in CLASSICAL:
        sets[name] = ss.classical_filter(system, box(DESIGNERS[name]), ys)
    # Carol: Algorithm 2 with the paper's switching time k_* and the example's P (Lemma 1's θ̄ = ∞).
    sets["Carol"] = ss.oit_inspired_filter(system, box(DESIGNERS["Carol"]), ys,
                                           decomposition=example.decomposition())
    return sets


def polygons(sets: list[ss.ConvexSet]) -> list[np.ndarray]:
    """The exact polygon of each set (empty array for an empty set), computed once and reused."""
    return [np.zeros((0, 2)) if S.is_empty() else S.vertices_2d() for S in sets]


def draw_polygon(ax, P: np.ndarray, color, **kw) -> None:
    """Outline of the polygon with vertices ``P`` (counter-clockwise); nothing for an empty one."""
    if len(P) == 0:
        return
    closed = np.vstack([P, P[:1]])
    ax.plot(closed[:, 0], closed[:, 1], color=color, **kw)


def curves(true_polys: list[np.ndarray], polys: list[np.ndarray]) -> dict[str, np.ndarray]:
    """2-norm diameters (0 for an empty estimate, the paper's convention), exact 2-norm Hausdorff gaps
    and the authors' vertex surrogate (NaN for an empty estimate)."""
    empty = np.array([len(P) == 0 for P in polys])
    diam = np.array([0.0 if len(P) == 0 else analysis.diameter(P, 2) for P in polys])
    gap = np.array([np.nan if len(P) == 0 else analysis.hausdorff_distance(P, Q, 2)
                    for P, Q in zip(polys, true_polys)])
    surrogate = np.array([np.nan if len(P) == 0 else analysis.vertex_hausdorff_surrogate(P, Q)
                          for P, Q in zip(polys, true_polys)])
    return {"empty": empty, "diameter": diam, "gap": gap, "gap_surrogate": surrogate}


def check_horizon(horizon: int, panels) -> int:
    """The figures' horizon: an integer between the last panel time and T = 50."""
    if isinstance(horizon, bool) or not isinstance(horizon, (int, np.integer)) or not max(panels) <= horizon <= T:
        raise ValueError(f"horizon must be an integer in [{max(panels)}, {T}], got {horizon!r}")
    return int(horizon)


def first_empty(empty: np.ndarray) -> int | None:
    idx = np.flatnonzero(empty)
    return int(idx[0]) if idx.size else None


def gaps_vanish_from(gap: np.ndarray, tol: float = GAP_TOL) -> int | None:
    """The least k₀ with gap_k ≤ tol for every k ≥ k₀ (None when the last gap is not ≤ tol)."""
    small = np.nan_to_num(gap, nan=np.inf) <= tol
    if not small[-1]:
        return None
    k0 = len(small)
    while k0 > 0 and small[k0 - 1]:
        k0 -= 1
    return k0


def describe_box(lo_hi) -> str:
    lo, hi = lo_hi
    sides = {f"[{a:g}, {b:g}]" for a, b in zip(lo, hi)}
    return sides.pop() + "²" if len(sides) == 1 else " × ".join(f"[{a:g}, {b:g}]" for a, b in zip(lo, hi))


#: The conventions shared by the stability paper's figures, printed above their rows in REPORT.md.
REPORT_PREAMBLE = """\
Reproduction of Section 7 of the stability paper. Each section lists the published value or claim
beside ours; the plotted numbers are in `<name>.json`.

Conventions shared by these figures:
- Figs. 2–3 use the authors' own trajectories: MATLAB's `rng(seed); rand(r, c)` replayed bit for bit with
  `numpy.random.RandomState(seed)` (column-major fill), seeds 24629 (Fig. 2) and 2330 (Fig. 3), draw order
  w_0..w_50, v_0..v_50, x_0 ~ U[1, 3]², as in their scripts.
- Posterior sets are exact (constrained zonotopes from `classical_filter`); Carol runs Algorithm 2 with
  the switching time k_* = max{{μ_o − 1 + n_λ0, 1}} = 1 and Lemma 1's θ̄ = ∞ (the box made inactive,
  which is the θ → ∞ limit exactly; the authors' code uses a box of half-width 1000 and switches at
  μ_o − 1).
- "Diameter" is the 2-norm diameter (largest distance between two vertices), 0 for an empty estimate
  (the paper's convention). The estimation gap (9) is the exact 2-norm Hausdorff distance to the true
  posterior (vertices of each polygon against the other polygon, closed-form geometry); the authors'
  vertex-to-vertex surrogate, an upper bound, is shown beside it. A gap below {gap_tol:g} counts as 0.
- The bound line of Fig. 2 is (16) minimized over δ ≥ μ − 1 with d_w = d_v = 2.
""".format(gap_tol=GAP_TOL)


EXAMPLES = {"25": EXAMPLE_25, "26": EXAMPLE_26}


def fresh_run(example_key: str, horizon: int, rng: np.random.Generator) -> dict:
    """One fresh trajectory (x_0 uniform on [1, 3]², uniform noises) of an example: where David's
    estimate empties and from which k each other designer's exact gap vanishes (runs beyond the
    authors' one)."""
    example = EXAMPLES[example_key]
    _, ys = ss.simulate(example.system(), box(TRUE_X0), horizon, rng)
    sets = designer_estimates(example, ys)
    true_polys = polygons(sets["true"])
    out = {}
    for name in DESIGNERS:
        c = curves(true_polys, polygons(sets[name]))
        out[name] = {"first_empty": first_empty(c["empty"]), "gap_vanishes_from": gaps_vanish_from(c["gap"])}
    return out


def fresh_run_rows(results: list[dict], figure: str) -> tuple[list[dict], dict]:
    """Report rows summarizing `fresh_run` over the extra runs (none when there are none)."""
    from _outputs import row
    if not results:
        return [], {}
    stats = {name: {key: [r[name][key] for r in results] for key in ("first_empty", "gap_vanishes_from")}
             for name in DESIGNERS}

    def summary(values):
        known = [v for v in values if v is not None]
        never = len(values) - len(known)
        text = f"min {min(known)}, median {int(np.median(known))}, max {max(known)}" if known else "never"
        return text + (f" ({never} of {len(values)} runs: never)" if never and known else "")

    rows = [row(f"{len(results)} fresh runs: David's estimate first empty at k", f"k = 2 in the one run of {figure}",
                summary(stats["David"]["first_empty"]))]
    rows += [row(f"{len(results)} fresh runs: {name}'s exact gap ≤ {GAP_TOL:g} from k", "not stated (one run)",
                 summary(stats[name]["gap_vanishes_from"])) for name in ("Alice", "Bob", "Carol")]
    return rows, stats


def inside_from(sets: list[ss.ConvexSet], xs: np.ndarray) -> int | None:
    """The least k₀ such that x_k lies in sets[k] for every k ≥ k₀ (None if not even at k = T)."""
    ok = [S.contains(x) for S, x in zip(sets, xs)]
    if not ok[-1]:
        return None
    k0 = len(ok)
    while k0 > 0 and ok[k0 - 1]:
        k0 -= 1
    return k0
