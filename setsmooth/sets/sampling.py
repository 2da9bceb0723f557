"""Uniform sampling from bounded sets: exact where the representation allows, else hit-and-run.

`uniform_sample` (what ``ConvexSet.sample`` calls) picks, for ``method='auto'``:

* **exact** — a set that flattens to a constrained zonotope of dimension ≤ `EXACT_SAMPLING_MAX_DIM`
  whose vertices can be enumerated (`sets.cz_vertices.cz_vertices`): its hull is cut into simplices and
  each draw picks a simplex with probability ∝ volume, then uniform barycentric weights. Exactly
  uniform, no program per draw (the vertices cost no LP at all).
* **hit-and-run** — otherwise: a Markov chain whose every move picks a random direction d and a point
  uniform on the chord {x + t d} ∩ S. The uniform distribution on S is its stationary law (Smith
  1984), so every proposal is accepted; the chord is closed-form for an `HPolytope` (no program at
  all); for a set with a constrained-zonotope form it is max and min of t over
  {Gξ − t d = x − c, Aξ = b, |ξ| ≤ h}, one program whose matrix changes from move to move only in
  the column −d, re-solved from the last move's bases (`_CZChords`); for any other set it is the
  two-direction program on the 1-D set {t : x + t d ∈ S}. The draws are approximately uniform: after
  ``burn_in`` moves, one draw every ``thin`` moves.
* **rejection** (on request; `rejection_sample`) — proposals uniform on the interval hull, accepted by
  one membership program each: exactly uniform, but its cost grows with how thin S is in its hull.

References
----------
R. L. Smith, "Efficient Monte Carlo procedures for generating points uniformly distributed over
bounded regions", Operations Research 32 (1984).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.spatial import QhullError

from .. import tolerances as tol
from .._validation import check_count, check_rng
from ..solvers.parametric import ParametricPoints
from . import _matrices as mx
from .cz_vertices import cz_vertices, hull_geometry
from .hpolytope import HPolytope

#: The flatness check factors dense matrices up to this many generators.
FLATNESS_CHECK_MAX_GENERATORS = 2000

#: `uniform_sample` samples exactly (vertices and simplices) up to this dimension.
EXACT_SAMPLING_MAX_DIM = 6

SAMPLING_METHODS = ("auto", "exact", "hit_and_run", "rejection")


def uniform_sample(S, rng: np.random.Generator, size: int = 1, method: str = "auto") -> np.ndarray:
    """Draw ``size`` points uniformly from the bounded set ``S``, shape (size, dim).

    Parameters
    ----------
    S : ConvexSet
        Bounded, non-empty, with interior in its space.
    rng : numpy.random.Generator
    size : int
    method : {'auto', 'exact', 'hit_and_run', 'rejection'}
        See the module docstring; 'auto' takes 'exact' when it is available, 'hit_and_run' otherwise.

    Returns
    -------
    ndarray, shape (size, dim)

    Raises
    ------
    ValueError
        For an empty, unbounded or flat set (naming the affine dimension when it is known), an unknown
        ``method``, or 'exact' on a set without an enumerable vertex set.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.Zonotope([[1.0, 0.5], [0.0, 1.0]], [0.0, 0.0])
    >>> uniform_sample(Z, np.random.default_rng(0), 3).shape
    (3, 2)
    """
    check_rng(rng)
    size = check_count(size)
    if method not in SAMPLING_METHODS:
        raise ValueError(f"method must be one of {SAMPLING_METHODS}, got {method!r}")
    if method == "rejection":
        return rejection_sample(S, rng, size)
    if method in ("auto", "exact"):
        geometry = exact_geometry(S)
        if geometry is not None:
            return geometry.sample(rng, size)
        if method == "exact":
            raise ValueError(f"no exact sampler for {type(S).__name__} of dimension {S.dim}: it needs a "
                             f"constrained-zonotope form of dimension ≤ {EXACT_SAMPLING_MAX_DIM} with at "
                             "most cz_vertices.MAX_VERTEX_CANDIDATES basic solutions")
    return hit_and_run(S, rng, size)


def exact_geometry(S):
    """The `HullGeometry` of ``S`` from its vertices, or None when ``S`` has no CZ form of dimension ≤
    `EXACT_SAMPLING_MAX_DIM` with an enumerable vertex set.

    Raises
    ------
    ValueError
        When ``S`` is empty or flat (no interior).
    """
    cz = S._flat_cz
    if cz is None or S.dim > EXACT_SAMPLING_MAX_DIM:
        return None
    V = cz_vertices(cz)
    if V is None:
        return None
    if V.shape[0] == 0:
        raise ValueError("cannot sample from an empty set")
    try:
        return hull_geometry(V)
    except ValueError as err:
        raise ValueError(f"cannot sample uniformly from {type(S).__name__}: {err}") from None
    except QhullError:
        # Nearly degenerate vertex sets (a 5-D CZ of reliability system 209: "wide merge") defeat
        # Qhull's triangulation: no exact geometry, so 'auto' samples by hit-and-run instead.
        return None


def hit_and_run(S, rng: np.random.Generator, size: int = 1, *, burn_in: int | None = None,
                thin: int | None = None, start=None) -> np.ndarray:
    """Approximately uniform draws from the bounded set ``S`` by hit-and-run (Smith 1984).

    Directions are Gaussian, shaped by the spread of the set's 2·dim extreme points and, after
    burn-in, of the burn-in draws (symmetric and independent of the current point, so the uniform law
    stays stationary; thin slanted sets are crossed along their length). The chord of an
    `HPolytope` {Hx ≤ k} is closed-form; any other set's chord is the interval
    hull of the 1-D set {t : x + t d ∈ S} (one program, two directions).

    Parameters
    ----------
    S : ConvexSet
    rng : numpy.random.Generator
    size : int
    burn_in : int, optional
        Moves before the first draw; default 20·dim² + 50.
    thin : int, optional
        Moves between draws; default 2·dim + 1.
    start : array_like, optional
        A point of ``S`` to start from; default: the mean of the 2·dim support points along ±eᵢ
        (which are computed anyway, to shape the directions).

    Returns
    -------
    ndarray, shape (size, dim)

    Raises
    ------
    ValueError
        For an empty or unbounded set, or one without interior (every chord through the start has
        zero length).
    """
    check_rng(rng)
    size = check_count(size)
    hull = S.interval_hull()
    if hull.is_empty():
        raise ValueError("cannot sample from an empty set")
    if not hull.is_bounded:
        raise ValueError("cannot sample uniformly from an unbounded set")
    n = S.dim
    burn_in = 20 * n * n + 50 if burn_in is None else int(burn_in)
    thin = 2 * n + 1 if thin is None else int(thin)
    chord = _chord_function(S)
    E = np.vstack([np.eye(n), -np.eye(n)])
    anchors = np.array([S.support_point(d) for d in E])
    x = anchors.mean(axis=0) if start is None else np.asarray(start, dtype=float)
    # Directions d = L g, g standard normal: symmetric and independent of the current point, so the
    # uniform law stays stationary. L rounds the set: the Cholesky factor of the spread of its 2n
    # extreme points, then (after burn-in) of the burn-in draws, so a thin slanted set is crossed
    # along its length instead of across it.
    L = _shape(anchors, hull.widths())
    lengths = []
    out = np.empty((size, n))
    history = []
    for move in range(burn_in + thin * size):
        if move == burn_in and burn_in >= 4 * n:
            L = _shape(np.array(history), hull.widths())
        d = L @ rng.standard_normal(n)
        lo, hi = chord(x, d)
        if move < 4 * n:
            lengths.append((hi - lo) * np.linalg.norm(d))
        x = x + rng.uniform(lo, hi) * d
        if move < burn_in:
            history.append(x)
        kept = move - burn_in
        if kept >= 0 and kept % thin == thin - 1:
            out[kept // thin] = x
        if move == 4 * n - 1 and max(lengths) <= tol.VERTEX_TOL * max(1.0, float(hull.widths().max())):
            raise ValueError(f"cannot sample uniformly from {type(S).__name__}: every chord through "
                             f"the start has zero length (the set has no interior in ℝ^{n})")
    return out


def _shape(points: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """A Cholesky factor of the covariance of ``points``, regularized by 1e-6 of the hull widths."""
    n = widths.size
    cov = np.cov(points.T).reshape(n, n) + np.diag((1e-6 * np.maximum(widths, tol.RANK_TOL)) ** 2)
    return np.linalg.cholesky(cov)


def _chord_function(S):
    """(x, d) ↦ (t_lo, t_hi) with {x + t d : t ∈ [t_lo, t_hi]} = the chord of S through x along d."""
    if isinstance(S, HPolytope):
        H, k = np.asarray(S.H), np.asarray(S.k)

        def polytope_chord(x, d):
            rate, room = H @ d, np.maximum(k - H @ x, 0.0)
            with np.errstate(divide="ignore", invalid="ignore"):
                up = np.where(rate > 0, room / rate, np.inf).min(initial=np.inf)
                down = np.where(rate < 0, room / rate, -np.inf).max(initial=-np.inf)
            return float(down), float(up)

        return polytope_chord

    def program_chord(x, d):
        line = (S + (-x)).preimage(d[:, None]).interval_hull()
        if line.is_empty():  # x left S by rounding: stay
            return 0.0, 0.0
        return float(line.lo[0]), float(line.hi[0])

    cz = S._flat_cz
    return program_chord if cz is None else _CZChords(cz, program_chord)


class _CZChords:
    """Chords of Z = Z(G, c, A, b, h): t_hi = max t and t_lo = min t over

        Gξ − t d = x − c,  Aξ = b,  |ξ| ≤ h  (t free),

    one program whose matrix changes from move to move only in the column −d and whose right-hand
    side only in x − c: a `ParametricPoints` session (the solver policy's 'along time' backends),
    each end re-solved from its last basis. The ends are the solver's values at points checked
    against the program, as the interval hull of ``program_chord`` gives them; a move the session
    leaves without a checked end (x left Z by rounding, an unsettled solve) is ``program_chord``'s.
    """

    def __init__(self, cz, program_chord):
        n, ng = cz.G.shape
        self.c, self.b = np.asarray(cz.c), np.asarray(cz.b)
        self.h = np.append(cz.h, np.inf)
        column = np.concatenate([np.ones(n), np.zeros(cz.nc)])[:, None]  # −d's place, stored entries
        matrix = mx.hstack([mx.vstack([cz.G, cz.A]), column])  # sparse where Z is
        t_only = np.zeros((1, ng + 1))
        t_only[0, ng] = 1.0
        engine = ParametricPoints(t_only, matrix, np.array([[1.0], [-1.0]]), np.isinf(self.h),
                                  (np.arange(n), np.full(n, ng)))
        self.session = engine.session()
        self.fallback = program_chord

    def __call__(self, x: np.ndarray, d: np.ndarray) -> tuple[float, float]:
        rhs = np.concatenate([x - self.c, self.b])
        values, _ = self.session.points(np.zeros(1), rhs, self.h, -d)
        if np.isnan(values).any():
            return self.fallback(x, d)
        return float(-values[1]), float(values[0])


def rejection_sample(S, rng: np.random.Generator, size: int = 1, max_tries: int = 200_000) -> np.ndarray:
    """Draw ``size`` points uniformly from the bounded set ``S``, shape (size, dim).

    Proposals are uniform on the interval hull and accepted when ``S.contains`` them (one membership
    program each), which gives exactly the uniform distribution on ``S``.

    Raises
    ------
    ValueError
        For empty or unbounded sets, and when fewer than ``size`` proposals out of ``max_tries`` are
        accepted, and at once for a constrained zonotope whose affine hull has a lower dimension than
        the space (`affine_rank`): a flat set has acceptance zero.
    """
    check_rng(rng)
    size = check_count(size)
    hull = S.interval_hull()
    if hull.is_empty():
        raise ValueError("cannot sample from an empty set")
    if not hull.is_bounded:
        raise ValueError("cannot sample uniformly from an unbounded set")
    cz = S._flat_cz
    rank = None if cz is None else affine_rank(cz)
    if rank is not None and rank < S.dim:
        raise ValueError(f"cannot sample uniformly from {type(S).__name__}: it lies in an affine subspace "
                         f"of dimension {rank} < {S.dim} (no interior), so uniform proposals from its "
                         "interval hull are never accepted; sample its factors instead")
    out = []
    tries = 0
    while len(out) < size:
        if tries >= max_tries:
            raise ValueError(f"rejection sampling accepted {len(out)} of {tries} proposals; "
                             "the set is too thin inside its interval hull")
        p = rng.uniform(hull.lo, hull.hi)
        tries += 1
        if S.contains(p, tol=0.0):
            out.append(p)
    return np.array(out).reshape(size, S.dim)


def affine_rank(Z) -> int | None:
    """An upper bound on the dimension of the affine hull of a constrained zonotope Z(G, c, A, b, h).

    Every point is Gξ + c with Aξ = b, and ξ = ξ₀ + N z with N a basis of the null space of A
    (restricted to the factors with h > 0; the others are fixed at 0), so Z lies in
    c + Gξ₀ + range(G N): its dimension is at most rank(G N). Returns None above
    `FLATNESS_CHECK_MAX_GENERATORS` generators.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> segment = ss.ConstrainedZonotope(0.1 * np.eye(2), np.zeros(2), A=[[1.0, 0.5]], b=[0.2])
    >>> affine_rank(segment)
    1
    """
    if Z.ng > FLATNESS_CHECK_MAX_GENERATORS:
        return None
    live = np.flatnonzero(Z.h > 0)
    G = Z.G.toarray() if sp.issparse(Z.G) else np.asarray(Z.G)
    A = Z.A.toarray() if sp.issparse(Z.A) else np.asarray(Z.A)
    G, A = G[:, live], A[:, live]
    N = sla.null_space(A, rcond=tol.RANK_TOL) if A.shape[0] else np.eye(live.size)
    GN = G @ N
    if GN.size == 0:
        return 0
    s = np.linalg.svd(GN, compute_uv=False)
    return int(np.count_nonzero(s > tol.RANK_TOL * max(GN.shape) * s[0])) if s[0] > 0 else 0
