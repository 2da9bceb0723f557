"""Related noises by state augmentation: a process noise that is the same at every step.

The classical filter treats w_0, w_1, ... as unrelated: any sequence in W. When the disturbance is in
fact one unknown constant w ∈ W (a bias, a slope, a miscalibrated actuator), the true range of x_k
is smaller: the rethinking paper (Section IV-B) shows the classical filter is then only an outer
bound, and obtains the optimal filter by augmenting the state with w, whose dynamics are w_{k+1} = w_k.
With setsmooth that is an ordinary `LinearSystem` on (x, w) without process noise; the x-part of its
posterior is the optimal range. Both filters below use the same data.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402
from setsmooth.papers.smoothing_examples import smoothing_example_31  # noqa: E402

system = smoothing_example_31()                  # Φ, Γ, Ξ, Ψ = I; W = [−1, 1], V = [−1, 1]²
Phi, Gamma, C = system.A_at(0), system.E_at(0), system.C_at(0)
X0, T = ss.Box([-5, -5], [5, 5]), 20
rng = np.random.default_rng(5)
w = system.W.sample(rng, 1)                      # one constant disturbance for the whole run
xs, ys = ss.simulate(system, X0, T, rng, ws=np.repeat(w, T, axis=0))

classical = ss.classical_filter(system, X0, ys)  # w_k unrelated: an outer bound here

# (x, w) with w_{k+1} = w_k: process noise of dimension 0 is written as a zero map of a point.
A_aug = np.block([[Phi, Gamma], [np.zeros((1, 2)), np.eye(1)]])
augmented = ss.LinearSystem(A_aug, None, np.hstack([C, np.zeros((2, 1))]), E=np.zeros((3, 1)),
                            W=ss.Box([0.0], [0.0]), V=system.V)
joint = ss.classical_filter(augmented, X0 * system.W, ys)
optimal = ss.SetEstimates([P.project([0, 1]) for P in joint], system=system, kind="optimal")

print(f"true state inside: classical {classical.contains_trajectory(xs).all()}, "
      f"optimal {optimal.contains_trajectory(xs).all()}")
ratio = optimal.diameters()[1:] / classical.diameters()[1:]
print(f"∞-norm diameter ratio optimal / classical: {ratio[4]:.2f} at k = 5, {ratio[-1]:.2f} at k = {T}")
print(f"the bias w = {w[0, 0]:.3f} is known to within "
      f"[{joint[T].interval_hull().lo[2]:.3f}, {joint[T].interval_hull().hi[2]:.3f}] at k = {T}")

fig, (ax, ax_set) = plt.subplots(1, 2, figsize=(10, 4.0))
ax.plot(np.arange(T + 1), classical.diameters(), "o-", color="tab:blue", markersize=3,
        label="classical filter (w_k unrelated)")
ax.plot(np.arange(T + 1), optimal.diameters(), "o-", color="tab:red", markersize=3,
        label="optimal filter (w constant)")
ax.set_xlabel("k")
ax.set_ylabel("∞-norm diameter of ⟦x_k | y_0:k⟧")
ax.set_yscale("log")
ax.legend(fontsize=8, frameon=False)
k = 8
classical[k].plot(ax_set, facecolor="tab:blue", alpha=0.3, edgecolor="tab:blue", label="classical")
optimal[k].plot(ax_set, facecolor="tab:red", alpha=0.6, edgecolor="tab:red", label="optimal")
ax_set.plot(*xs[k], "k*", markersize=9, label="true state")
ax_set.set_title(f"posteriors at k = {k}", fontsize=9)
ax_set.set_aspect("equal")
ax_set.legend(fontsize=8, frameon=False, loc="lower right")
fig.suptitle("A constant disturbance: classical vs optimal filtering by state augmentation")
fig.tight_layout()

out = Path(__file__).resolve().parent / "out"
out.mkdir(exist_ok=True)
fig.savefig(out / "related_noise_constant_bias.png", dpi=150)
print(f"saved {out / 'related_noise_constant_bias.png'}")
