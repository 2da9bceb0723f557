"""What the rethinking paper's figure scripts share: its settings, published numbers and conventions.

The example systems live in `setsmooth.papers.rethinking_examples` (one definition for figures, tests and
docs); this module adds the paper's run sizes, the published numbers and the report's conventions.
"""

from __future__ import annotations

import numpy as np

from setsmooth.papers.rethinking_examples import (RETHINKING_27_V, RETHINKING_27_W, RETHINKING_27_X0,
                                                  RETHINKING_30_X0)

PAPER = "rethinking"
PAPER_TITLE = ("Rethinking paper — Cong, Wang, Zhou, *Rethinking the Mathematical Framework and Optimality "
               "of Set-Membership Filtering* (IEEE TAC 2022)")

# -- Fig. 1 (Section II-B) ---------------------------------------------------------------------------
FIG1_PRIOR = (1.0, 3.0)            # ⟦x⟧
FIG1_NOISE = (0.0, 2.0)            # ⟦y | x⟧ = {x} + [0, 2]
FIG1_Y = 2.0
FIG1_PROBES = (1.5, 2.5)           # the green and red x of the caption

# -- Fig. 2 (Section IV-A) ---------------------------------------------------------------------------
FIG2_T = 20                        # k ∈ [0, 20]; the text only says "k ≥ 5", the horizon is our choice
PAPER_RUNS_FIG2 = 10_000
PAPER_SAMPLES = 10_000             # N of Algorithm 2
PAPER_RATIO_FIG2 = 0.84            # "stays around 84 % for k ≥ 5"
FIG2_STEADY_FROM = 5

# -- Fig. 3 (Section IV-B) ---------------------------------------------------------------------------
FIG3_STEPS = (0, 10, 20)
PAPER_AREA_RATIOS = {10: 0.271, 20: 0.0104}


def quantile_rank(values: np.ndarray, x: float) -> float:
    """Fraction of ``values`` below ``x``: where a published number falls in our distribution."""
    values = np.asarray(values)
    return float(np.mean(values < x))


#: The conventions shared by the rethinking paper's figures, printed above their rows in REPORT.md.
REPORT_PREAMBLE = """\
Reproduction of the rethinking paper's figures (Sections II-B and IV). Each section lists the published
value or claim beside ours; the plotted numbers are in `<name>.json`.

Conventions shared by these figures:
- Example (27)–(28): ⟦x_0⟧ = [{x0[0]:g}, {x0[1]:g}], ⟦w_k⟧ = [{w[0]:g}, {w[1]:g}], ⟦v_k⟧ = [{v[0]:g}, {v[1]:g}].
  The text's ⟦v_k | w_(k−1)⟧ = [0, 2 − w_(k−1)] and Algorithm 2's test y_k/x_k ∈ [0, 1 − 2w_(k−1)] are
  inconsistent with ⟦v_k⟧ = [1, 2] and with Algorithm 1's update [y/2, y] (law of total range (9)); we
  read ⟦v_k | w_(k−1)⟧ = [1, 2 − w_(k−1)] (`setsmooth.papers.rethinking_examples`). With it the classical
  range holds the true state in every run; with the printed [0, 2 − w] it does not.
- Example (30)–(31): ⟦x_0⟧ = [{x30:g}, {x30b:g}]², ⟦w⟧ = ⟦v_k⟧ = [−1, 1], one identical w. (32) prints
  D = 0 but (31) adds v_k; we take D = 1 (with D = 0 the posteriors are segments and area ratios are
  undefined). The classical filter is `classical_filter` (exact CZs); the optimal one `optimal_filter`
  with `JointRange.identical_process_noise` (the projection of the trajectory set under the joint
  range), which equals the paper's augmentation (33)–(35) (tested).
- Noises and x_0 are uniform on their (conditional) ranges (Fig. 2 caption). Runs are seeded with
  `numpy.random.SeedSequence(seed).spawn(...)` (Fig. 2: one child per chunk of runs).
""".format(x0=RETHINKING_27_X0, w=RETHINKING_27_W, v=RETHINKING_27_V, x30=RETHINKING_30_X0[0][0],
           x30b=RETHINKING_30_X0[1][0])
