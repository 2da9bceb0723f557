"""Constrained-zonotope algebra: every operation exact, in closed form, on the matrices (G, c, A, b).

A constrained zonotope Z(G, c, A, b) = {Gξ + c : Aξ = b, ‖ξ‖∞ ≤ 1} is closed under the operations a
set-membership estimator needs (smoothing paper (35)–(37)):

    linear map                M Z            = Z(MG, Mc, A, b)
    Minkowski sum             Z ⊕ W          = Z([G_z G_w], c_z + c_w, blkdiag(A_z, A_w), [b_z; b_w])
    generalized intersection  {s ∈ S : Rs ∈ Y} adds the equality R G_s ξ_s − G_y ξ_y = c_y − R c_s

so the results are again CZs (watch the numbers of factors ng and constraints nc grow). The last panel
chains the three into one step of the classical set-membership filter: predict, then keep the states
consistent with a measurement.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402


def sizes(Z: ss.ConstrainedZonotope) -> str:
    return f"ng = {Z.ng}, nc = {Z.nc}"


def draw_strip(ax, r, lo, hi, **style):
    """The strip {x ∈ ℝ² : lo ≤ rᵀx ≤ hi}, as a long band (the axes clip it)."""
    r = np.asarray(r, dtype=float)
    along = np.array([-r[1], r[0]]) * 100
    a, b = lo * r / (r @ r), hi * r / (r @ r)
    ax.fill(*np.array([a - along, a + along, b + along, b - along]).T, **style)


# The slice ξ₁ + ξ₂ + ξ₃ + ξ₄ = 1.5 of the unit 4-cube, mapped to the plane: an octagon.
S = ss.ConstrainedZonotope(G=[[1.0, 0.6, 0.4, 0.0], [0.0, 0.6, -0.5, 0.4]], c=[-0.75, -0.3],
                           A=[[1.0, 1.0, 1.0, 1.0]], b=[1.5])

# Linear map: rotate by 60° and shrink the second axis.
theta = np.pi / 3
M = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]]) @ np.diag([1.0, 0.5])
MS = M @ S

# Minkowski sum with a small zonotope.
W = ss.Zonotope([[0.25, 0.1], [0.0, 0.2]], [0.0, 0.0])
SW = S + W

# Generalized intersection: the points s of S with s₁ + s₂ in [−0.2, 0.5].
R = np.array([[1.0, 1.0]])
Y = ss.Box([-0.2], [0.5])
SY = S.intersect_preimage(R, Y)

# One filter step, x⁺ = A x + w, y = C x + v with ‖w‖∞ ≤ 0.1, |v| ≤ 0.15, measurement y = 0.2:
A_sys = np.array([[0.9, 0.4], [-0.4, 0.9]])
C_sys = np.array([[0.0, 1.0]])
prior = A_sys @ S + ss.Box([-0.1, -0.1], [0.1, 0.1])                  # stability paper (3)
posterior = prior.intersect_preimage(C_sys, ss.Box([0.2 - 0.15], [0.2 + 0.15]))  # (4)

for name, Z in [("S", S), ("M S", MS), ("S ⊕ W", SW), ("S ∩_R Y", SY), ("prior", prior),
                ("posterior", posterior)]:
    print(f"{name:<10} {type(Z).__name__:<20} {sizes(Z)}")

blue, orange, green, grey = "tab:blue", "tab:orange", "tab:green", "0.5"
fig, axes = plt.subplots(2, 2, figsize=(10, 9), sharex=True, sharey=True)
(ax_map, ax_sum), (ax_int, ax_filter) = axes

S.plot(ax_map, facecolor=blue, alpha=0.35, edgecolor=blue, label=f"S  ({sizes(S)})")
MS.plot(ax_map, facecolor=orange, alpha=0.5, edgecolor=orange, label=f"M S  ({sizes(MS)})")
ax_map.set_title("linear map  M S")

SW.plot(ax_sum, facecolor=orange, alpha=0.35, edgecolor=orange, label=f"S ⊕ W  ({sizes(SW)})")
S.plot(ax_sum, facecolor=blue, alpha=0.5, edgecolor=blue, label=f"S  ({sizes(S)})")
W.plot(ax_sum, facecolor=green, alpha=0.7, edgecolor=green, label="W, a zonotope")
ax_sum.set_title("Minkowski sum  S ⊕ W")

draw_strip(ax_int, R[0], Y.lo[0], Y.hi[0], color=grey, alpha=0.15,
           label="{x : Rx ∈ Y},  R = [1 1],  Y = [−0.2, 0.5]")
S.plot(ax_int, facecolor=blue, alpha=0.3, edgecolor=blue, label=f"S  ({sizes(S)})")
SY.plot(ax_int, facecolor=orange, alpha=0.6, edgecolor=orange,
        label=f"S ∩_R Y  ({sizes(SY)})")
ax_int.set_title("generalized intersection  {s ∈ S : Rs ∈ Y}")

draw_strip(ax_filter, C_sys[0], 0.05, 0.35, color=grey, alpha=0.15,
           label="states consistent with y = 0.2")
S.plot(ax_filter, facecolor="none", edgecolor=blue, linestyle="--", alpha=1,
       label="posterior at k (S)")
prior.plot(ax_filter, facecolor=blue, alpha=0.3, edgecolor=blue,
           label=f"prior  A S ⊕ [−0.1, 0.1]²  ({sizes(prior)})")
posterior.plot(ax_filter, facecolor=orange, alpha=0.6, edgecolor=orange,
               label=f"posterior at k+1  ({sizes(posterior)})")
ax_filter.set_title("one filter step: predict, then update")

for ax in axes.flat:
    ax.set_aspect("equal")
    ax.legend(loc="upper left", fontsize=8, frameon=False)
ax_map.set_xlim(-1.9, 1.9)
ax_map.set_ylim(-1.6, 2.0)
fig.suptitle("Constrained zonotopes: exact algebra in closed form")
fig.tight_layout()

out = Path(__file__).resolve().parent / "out"
out.mkdir(exist_ok=True)
fig.savefig(out / "cz_algebra.png", dpi=150)
print(f"saved {out / 'cz_algebra.png'}")
