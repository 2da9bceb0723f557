"""Uniform sampling from bounded sets by rejection from the interval hull."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .. import tolerances as tol
from .._validation import check_rng

#: The flatness check factors dense matrices up to this many generators.
FLATNESS_CHECK_MAX_GENERATORS = 2000


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
