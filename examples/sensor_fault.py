"""Model invalidation: a sensor fault injected at k = 30, found by the filter.

A lightly damped oscillator from python-control, sampled every 0.1 s, is measured by a position sensor
with an error of at most 0.05. From k = 30 the sensor reads 0.4 too high, a drift no noise bound
explains. The exact filter's posterior is empty from that step on: the data contradict the model, and
`classical_filter` says so with a `ModelInvalidationWarning` naming the step, the measurement and its
distance from the output set predicted from the earlier data. `first_inconsistency` answers the same
question as a value.
"""

import warnings
from pathlib import Path

import control
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402

plant = control.ss([[0.0, 1.0], [-4.0, -0.4]], [[0.0], [1.0]], [[1.0, 0.0]], 0)
system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), dt=0.1,
                                         V=ss.Box([-0.05], [0.05]), noise_inputs=[0])
X0 = ss.Box([-0.5, -0.5], [0.5, 0.5])
xs, ys = ss.simulate(system, X0, 50, seed := 3)
faulty = ys.copy()
faulty[30:] += 0.4                                           # the sensor drifts from k = 30

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", ss.ModelInvalidationWarning)
    healthy = ss.classical_filter(system, X0, ys)
    broken = ss.classical_filter(system, X0, faulty)
print("healthy data:", "consistent" if healthy.first_empty is None else healthy.first_empty)
for w in caught:
    print("warning:", w.message)
found = ss.first_inconsistency(system, X0, faulty, broken)
print(f"first inconsistent step: {found.step}, miss {found.distance:.3f}")

out = Path(__file__).parent / "out"
out.mkdir(exist_ok=True)
fig, ax = plt.subplots(figsize=(7, 3.2))
k = np.arange(len(ys))
ax.fill_between(k, healthy.lo[:, 0], healthy.hi[:, 0], alpha=0.3, label="posterior, healthy sensor")
ax.fill_between(k[:found.step], broken.lo[:found.step, 0], broken.hi[:found.step, 0], alpha=0.3,
                label="posterior, faulty sensor")
ax.plot(k, xs[:, 0], "k", lw=1, label="true position")
ax.plot(k, faulty[:, 0], ".", ms=3, label="faulty measurements")
ax.axvline(found.step, color="r", ls="--", label=f"invalidated at k = {found.step}")
ax.set_xlabel("k")
ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
fig.savefig(out / "sensor_fault.png", dpi=120)
print("figure:", out / "sensor_fault.png")
