"""A long horizon with a bounded filter: order reduction after every update.

The exact filter's constrained zonotopes gain generators and constraints at every step. With
``reduce=ss.CORA_GIRARD`` (the stability paper's Table 1 pipeline: rescaling, elimination down to one
constraint, Girard's reduction to order 1 in degrees of freedom) each posterior is replaced by an outer
bound of fixed complexity, so the cost per step stays flat over any horizon; the price is some width,
measured here against the exact filter on the same data. Every set still contains the true state.
"""

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.papers.smoothing_examples import smoothing_example_31  # noqa: E402

system = smoothing_example_31()          # smoothing paper (31): a rotation, ⟦w⟧ = [−1, 1], ⟦v⟧ = [−1, 1]²
X0 = ss.Box([-5, -5], [5, 5])
T = 300
xs, ys = ss.simulate(system, X0, T, np.random.default_rng(2))

start = time.perf_counter()
reduced = ss.classical_filter(system, X0, ys, reduce=ss.CORA_GIRARD)
d_reduced = reduced.diameters()
t_reduced = time.perf_counter() - start

exact = ss.classical_filter(system, X0, ys)          # exact sets, for comparison at a few steps
checked = np.arange(0, T + 1, 30)
d_exact = np.array([exact[k].diameter() for k in checked])

sizes = [(S.ng, S.nc) for S in reduced[1:]]
print(f"reduced filter, T = {T}: {t_reduced:.1f} s with hulls; at most {max(g for g, _ in sizes)} "
      f"generators and {max(c for _, c in sizes)} constraint(s) per posterior")
print(f"exact posterior at k = {T}: {exact[T].to_constrained_zonotope().ng} generators")
print(f"true state in every reduced posterior: {reduced.contains_trajectory(xs).all()}")
print(f"∞-norm diameter, mean over k = 30, 60, ..., {T}: exact {d_exact[1:].mean():.2f}, "
      f"reduced {d_reduced[checked][1:].mean():.2f}")

fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 5.6))
window = slice(T - 60, T + 1)            # the tube of the last 60 steps, readable
tail = ss.SetEstimates(reduced[window], system=system)
tail.plot_tubes(top, dims=[0], truth=xs[window], times=np.arange(T - 60, T + 1), color="tab:green",
                label="reduced filter (CORA_GIRARD)")
top.set_ylabel("$x_0$")
top.set_title("the last 60 steps: interval hulls and the true state", fontsize=9)
bottom.set_title("all steps: width of the reduced posteriors vs the exact ones", fontsize=9)
top.legend(loc="upper right", fontsize=8, frameon=False)
bottom.plot(np.arange(T + 1), d_reduced, color="tab:green", label="reduced filter")
bottom.plot(checked, d_exact, "o", color="black", markersize=4, label="exact filter")
bottom.set_ylabel("∞-norm diameter")
bottom.set_xlabel("k")
bottom.set_ylim(0, 1.2 * np.max(d_reduced[5:]))
bottom.legend(loc="upper right", fontsize=8, frameon=False)
fig.suptitle(f"Smoothing example (31) over T = {T} steps with order reduction")
fig.tight_layout()

out = Path(__file__).resolve().parent / "out"
out.mkdir(exist_ok=True)
fig.savefig(out / "long_horizon_reduced_filter.png", dpi=150)
print(f"saved {out / 'long_horizon_reduced_filter.png'}")
