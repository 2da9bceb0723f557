"""The exact filter of a planar polytope system with `Polygon`s (``classical_filter(form='polygon')``).

Stability paper Algorithm 1 with every set a convex polygon in closed form (no solver):

    prior_k     = A_{k-1} posterior_{k-1} ⊕ E_{k-1} W ⊕ {B_{k-1} u_{k-1}}   vertex images and sums
    posterior_k = { x ∈ prior_k : N C_k x ≤ h + N y_k }                 clipping by half-planes

where N y ≤ h are the half-planes of F_k(−V) (exact for a box or an H-polytope of any dimension,
rounded up for a planar polygon). Each `Polygon` contains the exact posterior and exceeds it only by
rounding (`setsmooth.sets.polygon`); a posterior is `EmptySet` only when certainly empty.
"""

from __future__ import annotations

import numpy as np

from ..floating import U
from ..sets._polygon_geometry import SQRT2_UP, TINY, up
from ..sets.algebra import linear_map, minkowski_sum, translate
from ..sets.base import ConvexSet
from ..sets.box import Box
from ..sets.polygon import Polygon, as_polygon, half_planes
from ..sets.empty import EmptySet
from ..sets.hpolytope import HPolytope
from ..sets.vpolytope import VPolytope
from ..sets.zonotope import Zonotope


def polygon_posteriors(system, X0: ConvexSet, ys: np.ndarray) -> list[ConvexSet]:
    """Posteriors ⟦x_k | y_{0:k}⟧, k = 0..T, as Polygons (trusted ys; system, X0 checked here).

    Raises
    ------
    ValueError
        When the form does not apply: n ≠ 2, or X0, E_k W or F_k(−V) has no polygon / half-plane
        closed form (X0 and E_k W: a 2-D Polygon, bounded Box, Zonotope or VPolytope; F_k(−V): also
        a Box or HPolytope of any dimension).
    """
    if system.n != 2:
        raise ValueError(f"form='polygon' needs a planar state (n = 2), got n = {system.n}")
    P0 = as_polygon(X0)
    if P0 is None:
        raise ValueError(f"form='polygon' needs X0 with a polygon form (a 2-D Polygon, bounded Box, "
                         f"Zonotope or VPolytope), got {type(X0).__name__}")
    posteriors: list[ConvexSet] = []
    for k, y in enumerate(ys):
        if k == 0:
            prior: ConvexSet = P0
        else:
            prior = minkowski_sum(linear_map(system.A_at(k - 1), posteriors[-1]), _noise_polygon(system, k - 1))
            u = system.nonzero_input(k - 1)
            if u is not None:
                prior = translate(prior, u)
        posterior = _measurement_cut(system, k, prior, y)
        if isinstance(posterior, EmptySet):
            return posteriors + [EmptySet(2) for _ in range(k, len(ys))]
        posteriors.append(posterior)
    return posteriors


def _noise_polygon(system, k: int) -> Polygon:
    image = noise_polygon(system, k)
    if image is None:
        raise ValueError(f"form='polygon' needs E W with a polygon form (W a Box, Zonotope, VPolytope "
                         f"or Polygon); B({k}) W is a {type(system.process_noise_image(k)).__name__}")
    return image


def noise_polygon(system, k: int, negated: bool = False) -> Polygon | None:
    """E_k W (or E_k(−W)) as a Polygon with the rounding of the image charged (`_charged`), or None
    when it has no polygon form. The smoother's step (`smoothers.linear`) adds it to polygon
    posteriors: the set algebra's image alone is computed in floating point, uncharged."""
    image = as_polygon(system.process_noise_image(k, negated=negated))
    return None if image is None else _charged(image, system.E_at(k), system.W)


def _charged(P: Polygon, M, S) -> Polygon:
    """P, the polygon of the set algebra's M S, with the rounding of that image charged: fl(M G),
    fl(M c) of S's zonotope form (≤ (p + 1)u|M|(|c| + |G|1) per coordinate), fl(points Mᵀ) of a
    VPolytope, and a Box's conversion to c ± r (≤ u max(|lo|, |hi|))."""
    M = np.abs(np.asarray(M.toarray() if hasattr(M, "toarray") else M, dtype=float))
    if isinstance(S, Box):
        bound = M @ np.maximum(np.abs(S.lo), np.abs(S.hi))
    elif isinstance(S, Zonotope):
        bound = M @ (np.abs(S.c) + np.abs(S.G).sum(axis=1))
    elif isinstance(S, VPolytope):
        bound = (np.abs(S.points) @ M.T).max(axis=0)
    else:                                   # a Polygon: mapped by Polygon's own charged closed form
        return P
    charge = SQRT2_UP * (M.shape[1] + 4) * U * float(bound.max()) * (1 + 4 * U) + TINY
    return Polygon._trusted(P.vertices, up(P.pad + charge))


def _measurement_cut(system, k: int, prior: Polygon, y: np.ndarray) -> ConvexSet:
    """{x ∈ prior : C_k x ∈ y_k + F_k(−V)} with y_k + F_k(−V) ⊆ {z : N z ≤ h + N y_k}, the offset
    rounded up by its error bound (≤ (m + 2)u(|N||y| + |h|))."""
    Y = system.measurement_noise_image(k)
    D = system.F_at(k)
    D = D.toarray() if hasattr(D, "toarray") else np.asarray(D)
    identity_D = D.shape[0] == D.shape[1] and np.array_equal(D, np.eye(len(D)))
    if isinstance(system.V, (Box, HPolytope)) and identity_D:
        NV, hV = half_planes(system.V)      # D(−V) = −V = {z : −NV z ≤ hV}, exactly
        halves = (-NV, hV)
    else:
        P_Y = as_polygon(Y)
        halves = None if P_Y is None else _charged(P_Y, D, system.V).half_planes()
    if halves is None:
        raise ValueError(f"form='polygon' needs D(−V) with half-planes (V a Box or HPolytope, or a "
                         f"2-D Zonotope, VPolytope or Polygon); D({k})(−V) is a {type(Y).__name__} of "
                         f"dimension {Y.dim}")
    N, h = halves
    shift = N @ y
    err = (N.shape[1] + 2) * U * (np.abs(N) @ np.abs(y) + np.abs(h)) + TINY
    offsets = np.nextafter(h + shift + err, np.inf)
    return prior.cut_preimage(system.C_at(k), N, offsets)
