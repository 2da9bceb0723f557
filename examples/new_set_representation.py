"""A new set representation in fifteen lines.

In setsmooth a set is anything that can say "x is in me" as CVXPY constraints. Write that one method
and the rest comes for free: support functions and the points attaining them, the interval hull,
membership, set algebra with every other representation, and plotting. Each query becomes a convex
program that CVXPY hands to Clarabel.

Here the new representation is a capsule (a "stadium"): the points within distance r of a segment
[a, b]. setsmooth has no such class; its membership constraint is one second-order cone.

When you know more, say so through the public extension points of `ss.ConvexSet` (never the
private ``_support`` / ``_as_constrained_zonotope``):

* ``support_function(D)`` (and optionally ``support_vectors(D)``): a closed-form support function,
  used by interval hulls, diameters, containment tests and lazy sums and maps instead of a program;
* ``as_constrained_zonotope()``: the set is exactly a constrained zonotope, so every query, filter
  and smoother takes the sparse CZ fast path and never compiles its CVXPY constraints.
"""

from pathlib import Path

import time

import cvxpy as cp
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import setsmooth as ss  # noqa: E402


class Capsule(ss.ConvexSet):
    """The points within Euclidean distance ``radius`` of the segment [a, b]."""

    def __init__(self, a, b, radius: float):
        self.a = np.asarray(a, dtype=float)
        self.b = np.asarray(b, dtype=float)
        self.radius = float(radius)
        self.dim = self.a.size

    def constraints(self, x):
        t = cp.Variable()  # where along the segment the nearest point sits
        nearest = self.a + t * (self.b - self.a)
        return [cp.norm(x - nearest, 2) <= self.radius, t >= 0, t <= 1]


capsule = Capsule(a=[-1.0, -0.4], b=[1.0, 0.6], radius=0.35)

# Support function h(d) = max over the capsule of dᵀx, and a point attaining it. For a capsule it is
# also max(dᵀa, dᵀb) + r‖d‖, which makes a good check.
d = np.array([1.0, 2.0])
exact = max(d @ capsule.a, d @ capsule.b) + capsule.radius * np.linalg.norm(d)
print(f"h({d}) = {capsule.support(d):.6f}   (closed form {exact:.6f})")
print(f"attained at {np.round(capsule.support_point(d), 6)}")

# The interval hull: 2·dim support values.
hull = capsule.interval_hull()
print(f"interval hull: lo = {np.round(hull.lo, 6)}, hi = {np.round(hull.hi, 6)}")

# A constrained zonotope Z(G, c, A, b): the slice ξ₁ + ξ₂ + ξ₃ = 1 of the unit cube (a triangle),
# mapped by G.
Z = ss.ConstrainedZonotope(G=[[0.4, -0.3, 0.1], [0.1, 0.2, -0.35]], c=[0.0, 0.0],
                           A=[[1.0, 1.0, 1.0]], b=[1.0])

# Capsule ⊕ Z has no closed form, so it stays exact and lazy: its support function is the sum.
total = capsule + Z
print(f"capsule ⊕ Z is a {type(total).__name__}; "
      f"h = {total.support(d):.6f} = {capsule.support(d):.6f} + {Z.support(d):.6f}")



# -- extension point 1: a closed-form support function -------------------------------------------------
class FastCapsule(Capsule):
    """The same capsule, with h(d) = max(dᵀa, dᵀb) + r‖d‖ and its maximizers in closed form."""

    def support_function(self, D):
        return np.maximum(D @ self.a, D @ self.b) + self.radius * np.linalg.norm(D, axis=1)

    def support_vectors(self, D):
        end = np.where((D @ self.a >= D @ self.b)[:, None], self.a, self.b)
        return end + self.radius * D / np.linalg.norm(D, axis=1, keepdims=True)


fast = FastCapsule(capsule.a, capsule.b, capsule.radius)
D = np.random.default_rng(0).standard_normal((200, 2))
start = time.perf_counter()
slow_values = capsule.support_many(D)           # 200 cone programs
slow_time = time.perf_counter() - start
start = time.perf_counter()
fast_values = fast.support_many(D)              # one line of NumPy
fast_time = time.perf_counter() - start
print(f"support_function: 200 directions in {fast_time * 1e3:.2f} ms instead of {slow_time * 1e3:.0f} ms; "
      f"largest difference {np.abs(fast_values - slow_values).max():.1e}")


# -- extension point 2: a set that is exactly a constrained zonotope ---------------------------------------
class Diamond(ss.ConvexSet):
    """{x : ‖x − c‖₁ ≤ r} in ℝ², which is the zonotope with generators (r/2)(1, 1) and (r/2)(1, −1)."""

    def __init__(self, center, r):
        self.c, self.r, self.dim = np.asarray(center, dtype=float), float(r), 2
        self.constraint_calls = 0

    def constraints(self, x):
        self.constraint_calls += 1
        return [cp.norm1(x - self.c) <= self.r]

    def as_constrained_zonotope(self):
        return ss.Zonotope(self.r / 2 * np.array([[1.0, 1.0], [1.0, -1.0]]), self.c)


class PlainDiamond(Diamond):
    """The same set without the hook: the filter compiles its constraints (the CVXPY path)."""

    def as_constrained_zonotope(self):
        return None


def diamond_system(W):
    return ss.LinearSystem([[0.9, 0.3], [-0.2, 0.8]], None, [[1.0, 0.0]], W=W, V=ss.Box([-0.2], [0.2]))


X0 = ss.Box([-1.0, -1.0], [1.0, 1.0])
W, Wp = Diamond([0.0, 0.0], 0.3), PlainDiamond([0.0, 0.0], 0.3)
_, ys = ss.simulate(diamond_system(W), X0, 12, np.random.default_rng(1))  # one record for both filters


def run_filter(W):
    start = time.perf_counter()
    post = ss.classical_filter(diamond_system(W), X0, ys)
    widths = [S.diameter() for S in post]
    return time.perf_counter() - start, widths


fast_time, fast_widths = run_filter(W)
slow_time, slow_widths = run_filter(Wp)
print(f"as_constrained_zonotope: filter + diameters in {fast_time:.2f} s (constraints() called "
      f"{W.constraint_calls} times) instead of {slow_time:.2f} s ({Wp.constraint_calls} calls); "
      f"largest diameter difference {np.max(np.abs(np.subtract(fast_widths, slow_widths))):.1e}")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2), sharex=True, sharey=True)

capsule.plot(left, facecolor="tab:blue", alpha=0.45, edgecolor="tab:blue", label="capsule")
hull.plot(left, facecolor="none", edgecolor="0.3", linestyle="--", alpha=1, label="interval hull")
point = capsule.support_point(d)
left.annotate("", xy=point + 0.5 * d / np.linalg.norm(d), xytext=point,
              arrowprops=dict(arrowstyle="->", color="black"))
left.plot(*point, "o", color="black", markersize=4, label="support point along d = (1, 2)")
left.set_title("queries: support, interval hull")

total.plot(right, facecolor="tab:purple", alpha=0.2, edgecolor="tab:purple", label="capsule ⊕ Z")
capsule.plot(right, facecolor="tab:blue", alpha=0.45, edgecolor="tab:blue", label="capsule")
Z.plot(right, facecolor="tab:orange", alpha=0.8, edgecolor="tab:orange",
       label="Z, a constrained zonotope")
right.set_title("algebra: Minkowski sum with a CZ")

for ax in (left, right):
    ax.set_aspect("equal")
    ax.legend(loc="upper left", fontsize=8, frameon=False)
fig.suptitle("Capsule: a new set written as one CVXPY constraint")
fig.tight_layout()

out = Path(__file__).resolve().parent / "out"
out.mkdir(exist_ok=True)
fig.savefig(out / "new_set_representation.png", dpi=150)
print(f"saved {out / 'new_set_representation.png'}")
