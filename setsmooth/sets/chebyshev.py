"""The Chebyshev ball of a constrained zonotope: the largest Euclidean ball inside it.

A CZ has no H-representation at hand, so the ball is found in one of three ways:

* dimension 1 and 2: exactly, from the set's polygon (`vertices_2d`) as an H-polytope;
* a CZ without constraints and with finite bounds (a zonotope) with few facets: exactly, from the
  facets of `containment.zonotope_halfspaces`;
* otherwise an **inner** ball by a lifting (one SOCP): B(x, r) ⊆ Z when x = Gξ₀ + c, Aξ₀ = b and a
  matrix K with GK = rI, AK = 0 keeps ξ₀ + Ku a factor for every ‖u‖₂ ≤ 1, that is
  |ξ₀_i| + ‖K_i‖₂ ≤ h_i; the ball is contained in Z, and it is the Chebyshev ball whenever its
  radius meets the upper bound of the interval hull (``exact`` then says so).
"""

from __future__ import annotations

from dataclasses import dataclass

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .. import tolerances as tol
from ..solvers import chebyshev_ball as h_ball
from ..solvers.cvxpy_problems import solve_problem
from .containment import zonotope_halfspaces
from .vertices_2d import vertices_2d


@dataclass(frozen=True)
class ChebyshevBall:
    """The largest Euclidean ball found inside a set.

    Attributes
    ----------
    center : ndarray, shape (n,)
        NaN for an empty set.
    radius : float
        ``-inf`` for an empty set, 0 for a set without interior.
    exact : bool
        True: the largest inscribed ball. False: a ball inside the set (an inner bound).
    """

    center: np.ndarray
    radius: float
    exact: bool


def chebyshev_ball(Z) -> ChebyshevBall:
    """The Chebyshev ball of the constrained zonotope ``Z`` (see the module docstring).

    Raises
    ------
    ValueError
        When Z contains balls of every radius (a free direction).
    """
    n = Z.dim
    if Z.is_empty():
        return ChebyshevBall(np.full(n, np.nan), -np.inf, True)
    hull = Z.interval_hull()
    widths = hull.hi - hull.lo
    if not np.all(np.isfinite(widths)):
        raise ValueError("the set is unbounded; the Chebyshev ball is defined for bounded sets")
    if n == 1:
        return ChebyshevBall(hull.midpoint(), float(widths[0]) / 2, True)
    H = None
    if n == 2:
        V = vertices_2d(Z)
        if len(V) < 3:  # a point or a segment: no interior
            return ChebyshevBall(V.mean(axis=0), 0.0, True)
        edges = np.roll(V, -1, axis=0) - V
        H = np.column_stack([edges[:, 1], -edges[:, 0]])  # outward normals of the CCW polygon
        k = np.einsum("ij,ij->i", H, V)
    elif Z.nc == 0 and np.isfinite(Z.h).all():
        G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
        facets = zonotope_halfspaces(G * Z.h, np.asarray(Z.c))
        if facets is not None:
            H, k = facets
    if H is not None:
        center, radius = h_ball(H, k)
        return ChebyshevBall(center, max(radius, 0.0), True)
    return _lifted_ball(Z, widths)


def _lifted_ball(Z, widths: np.ndarray) -> ChebyshevBall:
    G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    h, n = np.asarray(Z.h), Z.dim
    bounded = np.flatnonzero(np.isfinite(h))
    xi, K, r = cp.Variable(Z.ng), cp.Variable((Z.ng, n)), cp.Variable(nonneg=True)
    cons = [G @ K == r * np.eye(n)]
    if Z.nc:
        cons += [A @ K == 0, A @ xi == np.asarray(Z.b)]
    if bounded.size:
        cons.append(cp.abs(xi[bounded]) + cp.norm(K[bounded], 2, axis=1) <= h[bounded])
    status = solve_problem(cp.Problem(cp.Maximize(r), cons), "computing a Chebyshev ball", "chebyshev ball")
    if status == "unbounded":
        raise ValueError("the set contains balls of every radius; it has no Chebyshev centre")
    if status != "optimal":  # feasible set, so only an empty interior lifting fails: radius 0
        point = Z.support_point(np.ones(n))
        return ChebyshevBall(point, 0.0, False)
    # The ball is inside Z up to the solver's accuracy on this program (SOLVER_TOL).
    center = G @ np.asarray(xi.value) + np.asarray(Z.c)
    radius = max(float(r.value), 0.0)
    # Any inscribed ball fits in the interval hull: its half-width is an upper bound on the radius.
    exact = bool(radius >= widths.min() / 2 * (1 - tol.SOLVER_CHECK_TOL))
    return ChebyshevBall(center, radius, exact)
