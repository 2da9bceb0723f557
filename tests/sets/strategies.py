"""Hypothesis strategies for random sets of every representation, each drawn with known members.

Structure (dimension, representation, number of generators and constraints, which operation) comes
from hypothesis; the numbers inside come from a NumPy generator seeded by hypothesis, so the data is
continuous (no accidental exact cancellations) yet every example is reproducible.

Every strategy returns a `Drawn`: the set and a few points known to lie in it by construction, which
lets the algebra strategies translate operands so that intersections are non-empty.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from hypothesis import strategies as st

import setsmooth as ss

MAX_DIM = 6


@dataclass
class Drawn:
    """A random set with points known to be members (shape (m, dim); m = 0 for an empty set)."""

    set: ss.ConvexSet
    members: np.ndarray
    label: str

    def __repr__(self) -> str:
        return f"Drawn({self.label})"


def rngs():
    return st.integers(0, 2**32 - 1).map(np.random.default_rng)


def dims(max_dim: int = MAX_DIM):
    return st.integers(1, max_dim)


def directions(rng: np.random.Generator, n: int, k: int = 6) -> np.ndarray:
    """k random directions plus the coordinate axes, shape (k + 2n, n)."""
    eye = np.eye(n)
    return np.vstack([rng.standard_normal((k, n)), eye, -eye])


# --------------------------------------------------------------------------------------------------
# Representations
# --------------------------------------------------------------------------------------------------

@st.composite
def boxes(draw, n: int, unbounded: bool = False, full: bool = False) -> Drawn:
    rng = draw(rngs())
    lo = rng.uniform(-2, 2, n)
    width = rng.uniform(0.1, 3, n)
    if not full and draw(st.booleans()):
        width[rng.integers(n)] = 0.0  # a flat box
    hi = lo + width
    members = rng.uniform(lo, hi, size=(3, n))
    label = "Box"
    if unbounded:
        kind = draw(st.sampled_from(["free", "half-line", "both"]))
        j = rng.integers(n)
        if kind in ("free", "both"):
            lo[j], hi[j] = -np.inf, np.inf
            members[:, j] = rng.normal(0, 5, 3)
        if kind == "half-line" or (kind == "both" and n > 1):
            i = (j + 1) % n if kind == "both" else j
            lo[i] = -np.inf
            members[:, i] = hi[i] - rng.exponential(3, 3)
        label = f"Box({kind})"
    return Drawn(ss.Box(lo, hi), members, label)


@st.composite
def zonotopes(draw, n: int, full: bool = False) -> Drawn:
    rng = draw(rngs())
    ng = draw(st.integers(n if full else 0, 2 * n + 1))
    G = 0.7 * rng.standard_normal((n, ng))
    c = rng.uniform(-1, 1, n)
    xi = rng.uniform(-1, 1, size=(3, ng))
    return Drawn(ss.Zonotope(G, c), xi @ G.T + c, f"Zonotope(ng={ng})")


def _factor_members(rng, A, xi0, h, count=3):
    """Points ξ0 + t v of the factor set {Aξ = Aξ0, |ξ| ≤ h} along random null-space directions v."""
    N = scipy.linalg.null_space(A) if A.shape[0] else np.eye(A.shape[1])
    out = [xi0]
    for _ in range(count - 1):
        if N.shape[1] == 0:
            out.append(xi0)
            continue
        v = N @ rng.standard_normal(N.shape[1])
        lo, hi = -5.0, 5.0
        for j in np.flatnonzero(np.isfinite(h) & (np.abs(v) > 1e-12)):
            a, b = (-h[j] - xi0[j]) / v[j], (h[j] - xi0[j]) / v[j]
            lo, hi = max(lo, min(a, b)), min(hi, max(a, b))
        out.append(xi0 + rng.uniform(lo, hi) * 0.95 * v)
    return np.array(out)


@st.composite
def constrained_zonotopes(draw, n: int, infinite: bool | None = None,
                          bounded: bool = True, full: bool = False) -> Drawn:
    """A feasible CZ by construction: ξ0 strictly inside the bounds, b = Aξ0.

    With ``infinite`` some bounds h are +inf; with ``bounded`` there are at most nc of them and the
    columns of A on them are generic (full column rank), which pins the free factors down.
    """
    rng = draw(rngs())
    ng = draw(st.integers(max(1, n - 1), n + 4)) if not full else draw(st.integers(n + 1, n + 4))
    nc = draw(st.integers(1, min(4, ng))) if not full else draw(st.integers(1, ng - n))
    if infinite is None:
        infinite = draw(st.booleans())
    h = rng.uniform(0.3, 1.5, ng)
    n_inf = 0
    if infinite:
        n_inf = draw(st.integers(1, min(nc, ng))) if bounded else draw(st.integers(1, ng))
        h[rng.choice(ng, n_inf, replace=False)] = np.inf
    G = 0.7 * rng.standard_normal((n, ng))
    c = rng.uniform(-1, 1, n)
    A = rng.standard_normal((nc, ng))
    xi0 = rng.uniform(-0.8, 0.8, ng) * np.where(np.isfinite(h), h, 1.0)
    b = A @ xi0
    xis = _factor_members(rng, A, xi0, h)
    sparse = draw(st.booleans())
    Gs, As = (sp.csc_matrix(G), sp.csc_matrix(A)) if sparse else (G, A)
    Z = ss.ConstrainedZonotope(Gs, c, A=As, b=b, h=h)
    return Drawn(Z, xis @ G.T + c,
                 f"CZ(ng={ng}, nc={nc}, n_inf={n_inf}, {'sparse' if sparse else 'dense'})")


@st.composite
def hpolytopes(draw, n: int) -> Drawn:
    """A bounded H-polytope: a rotated simplex's normals plus random extra faces around x0."""
    rng = draw(rngs())
    U, _ = np.linalg.qr(rng.standard_normal((n, n)))
    base = np.vstack([np.eye(n), -np.ones((1, n)) / np.sqrt(n)]) @ U.T
    extra = rng.standard_normal((draw(st.integers(0, n + 2)), n))
    H = np.vstack([base, extra])
    x0 = rng.uniform(-1, 1, n)
    k = H @ x0 + rng.uniform(0.2, 1.5, H.shape[0])
    radius = 0.2 / np.linalg.norm(H, axis=1).max()
    delta = rng.standard_normal((2, n))
    delta *= radius * rng.uniform(0, 1, (2, 1)) / np.linalg.norm(delta, axis=1, keepdims=True)
    return Drawn(ss.HPolytope(H, k), np.vstack([x0, x0 + delta]), f"HPolytope(m={H.shape[0]})")


@st.composite
def ellipsoids(draw, n: int, full: bool = False) -> Drawn:
    """E(c, LLᵀ) with rank L drawn in 0..n (degenerate Q included unless ``full``)."""
    rng = draw(rngs())
    r = n if full else draw(st.integers(0, n))
    L = 0.8 * rng.standard_normal((n, r))
    c = rng.uniform(-1, 1, n)
    u = rng.standard_normal((3, r))
    u *= rng.uniform(0, 1, (3, 1)) / np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-300)
    return Drawn(ss.Ellipsoid(c, L @ L.T), u @ L.T + c, f"Ellipsoid(rank={r})")


@st.composite
def reals(draw, n: int) -> Drawn:
    rng = draw(rngs())
    return Drawn(ss.Reals(n), rng.normal(0, 3, (3, n)), "Reals")


def empties(n: int):
    return st.just(Drawn(ss.EmptySet(n), np.zeros((0, n)), "EmptySet"))


# --------------------------------------------------------------------------------------------------
# Everything, and the algebra
# --------------------------------------------------------------------------------------------------
#
# Well-posedness. Intersections are made non-empty by translating one operand onto a member of the
# other. When both operands are flat (a segment and a line in ℝ³, two degenerate ellipsoids) they then
# touch only by construction, and rounding leaves them a few ulps apart: an ill-posed feasibility
# problem on which interior-point solvers legitimately give up (SolverError). So the second operand
# of an intersection, and the operand of a preimage, is always full-dimensional (``full=True``) with
# the common point inside it; flat sets still appear everywhere else.

def base_sets(n: int, bounded: bool = False, allow_empty: bool = True, full: bool = False):
    """Any single representation of dimension n.

    ``bounded``: only bounded, non-empty ones; ``full``: only ones with non-empty interior.
    """
    options = [boxes(n, full=full), zonotopes(n, full=full),
               constrained_zonotopes(n, full=full), hpolytopes(n), ellipsoids(n, full=full)]
    if not bounded:
        options += [boxes(n, unbounded=True, full=full),
                    constrained_zonotopes(n, bounded=False, full=full), reals(n)]
        if allow_empty and not full:
            options.append(empties(n))
    return st.one_of(options)


def full_dimensional(n: int):
    """Bounded sets with non-empty interior (generic data), for uniform sampling."""
    return base_sets(n, bounded=True, full=True)


def cz_flattenable(n: int, bounded: bool = False, full: bool = False):
    """Sets with an exact constrained-zonotope form (the fast path and certified values apply)."""
    options = [boxes(n, full=full), zonotopes(n, full=full), constrained_zonotopes(n, full=full)]
    if not bounded:
        options += [constrained_zonotopes(n, bounded=False, full=full), reals(n)]
    return st.one_of(options)


def _matrix(rng, rows, cols, singular=False):
    M = rng.standard_normal((rows, cols))
    if singular and min(rows, cols) > 1:
        M = M[:, :1] @ rng.standard_normal((1, cols))  # rank one
    return M


def _shift(T: Drawn, target: np.ndarray) -> Drawn:
    """T translated so that its first member lands on ``target`` (a common point for intersections)."""
    if T.members.shape[0] == 0:
        return T
    v = target - T.members[0]
    return Drawn(T.set + v, T.members + v, T.label)


@st.composite
def sets(draw, n: int | None = None, depth: int = 2, bounded: bool = False,
         flattenable: bool = False, full: bool = False) -> Drawn:
    """A random set of dimension n: a representation, or an operation on smaller random sets.

    Operations go through the public operators (``M @ S``, ``S + T``, ``S & T``, ``S * T``,
    ``S.intersect_preimage(R, Y)``, ``S.preimage(M)``, ``S.project(dims)``), so the result is whatever
    type the widening rules give. ``bounded`` keeps to bounded, non-empty operands and operations
    that preserve that; ``flattenable`` keeps to CZ-flattenable operands; ``full`` keeps to sets with
    non-empty interior (see the note on well-posedness above).
    """
    if n is None:
        n = draw(dims())
    ops = ["base"]
    if depth > 0:
        ops += ["map", "sum", "intersection", "generalized_intersection", "project", "translate"]
        if n >= 2:
            ops.append("product")
        if not bounded:
            ops.append("preimage")
    op = draw(st.sampled_from(ops))
    if op == "base":
        if flattenable:
            return draw(cz_flattenable(n, bounded=bounded, full=full))
        return draw(base_sets(n, bounded=bounded, full=full))
    rng = draw(rngs())
    sub = dict(depth=depth - 1, bounded=bounded, flattenable=flattenable)
    if op == "map":
        # A full image needs a map onto ℝⁿ: at least n columns and full row rank.
        m = draw(st.integers(n, MAX_DIM) if full else dims(4))
        S = draw(sets(m, full=full, **sub))
        M = _matrix(rng, n, m, singular=not full and draw(st.booleans()))
        return Drawn(M @ S.set, S.members @ M.T, f"({n}x{m} @ {S.label})")
    if op == "translate":
        S = draw(sets(n, full=full, **sub))
        v = rng.uniform(-1, 1, n)
        return Drawn(S.set + v, S.members + v, f"({S.label} + v)")
    if op == "sum":
        S, T = draw(sets(n, full=full, **sub)), draw(sets(n, **sub))
        members = S.members[:, None, :] + T.members[None, :, :]
        return Drawn(S.set + T.set, members.reshape(-1, n), f"({S.label} + {T.label})")
    if op == "product":
        n1 = draw(st.integers(1, n - 1))
        S, T = draw(sets(n1, full=full, **sub)), draw(sets(n - n1, full=full, **sub))
        k = min(len(S.members), len(T.members))
        return Drawn(S.set * T.set, np.hstack([S.members[:k], T.members[:k]]),
                     f"({S.label} * {T.label})")
    if op == "intersection":
        S = draw(sets(n, full=full, **sub))
        T = draw(sets(n, full=True, **sub))
        members = np.zeros((0, n))
        if len(S.members) and len(T.members):
            T = _shift(T, S.members[0])
            members = S.members[:1]
        return Drawn(S.set & T.set, members, f"({S.label} & {T.label})")
    if op == "generalized_intersection":
        q = draw(dims(3))
        S, Y = draw(sets(n, full=full, **sub)), draw(sets(q, full=True, **sub))
        R = rng.standard_normal((q, n))
        members = np.zeros((0, n))
        if len(S.members) and len(Y.members):
            Y = _shift(Y, R @ S.members[0])
            members = S.members[:1]
        return Drawn(S.set.intersect_preimage(R, Y.set), members,
                     f"({S.label} ∩_R {Y.label})")
    if op == "preimage":
        m = draw(dims(4))
        S = draw(sets(m, full=True, **sub))
        M = rng.standard_normal((m, n))
        x = rng.normal(0, 1, n)
        members = np.zeros((0, n))
        if len(S.members):
            S = _shift(S, M @ x)
            members = x[None, :]
        return Drawn(S.set.preimage(M), members, f"preimage({S.label})")
    if op == "project":
        m = draw(st.integers(n, MAX_DIM))
        S = draw(sets(m, full=full, **sub))
        idx = list(rng.permutation(m)[:n])
        return Drawn(S.set.project(idx), S.members[:, idx], f"project({S.label})")
    raise AssertionError(op)  # pragma: no cover


# --------------------------------------------------------------------------------------------------
# Comparisons
# --------------------------------------------------------------------------------------------------

def support_scale(*values: np.ndarray) -> float:
    """A magnitude for relative tolerances: 1 + the largest finite support value seen."""
    finite = [np.abs(v[np.isfinite(v)]).max(initial=0.0) for v in values]
    return 1.0 + max(finite, default=0.0)


def assert_supports_close(a: np.ndarray, b: np.ndarray, rel: float = 1e-6, scale: float | None = None):
    """Equal infinities, and finite values within ``rel`` times the scale of the values."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    inf_a, inf_b = ~np.isfinite(a), ~np.isfinite(b)
    assert np.array_equal(inf_a, inf_b) and np.array_equal(a[inf_a], b[inf_b]), (a, b)
    if scale is None:
        scale = 1.0 + max(np.abs(a[~inf_a]).max(initial=0.0), np.abs(b[~inf_b]).max(initial=0.0))
    np.testing.assert_allclose(a[~inf_a], b[~inf_b], rtol=0, atol=rel * scale)
