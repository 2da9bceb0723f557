"""From python-control: B and D act on the known input u, E and F on the noises (CORA's names).

A sampled plant with a feedthrough, its filter and smoother tubes, and the model-invalidation check.
"""
from pathlib import Path

import control
import numpy as np
import setsmooth as ss

plant = control.ss([[0.0, 1.0], [-4.0, -0.4]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.2]]).sample(0.1)
u = np.sin(0.3 * np.arange(41))[:, None]               # the known force, time first: (T + 1, n_u)
system = ss.LinearSystem.from_statespace(plant, E=[[0.0], [0.1]], W=ss.Box([-1.0], [1.0]),
                                         V=ss.Box([-0.05], [0.05]), u=u)
X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])
xs, ys = ss.simulate(system, X0, 40, 1)                # seed 1: states x_0..x_40, outputs y = Cx + Du + v
filtered, smoothed = ss.classical_filter(system, X0, ys), ss.optimal_smoother(system, X0, ys)
axes = filtered.plot_tubes(dims=(0, 1))
smoothed.plot_tubes(axes, truth=xs)
(out := Path(__file__).parent / "out").mkdir(exist_ok=True)
axes[0].legend(loc="lower left", fontsize=8)
axes[0].figure.savefig(out / "python_control_quickstart.png", dpi=120)
print("data consistent with the model:", ss.first_inconsistency(system, X0, ys) is None)
ys[25:] += 0.3                                         # a sensor that drifts from k = 25
print("drifting sensor caught at k =", ss.first_inconsistency(system, X0, ys).step)
