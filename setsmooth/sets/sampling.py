"""Uniform sampling from bounded sets by rejection from the interval hull."""

from __future__ import annotations

import numpy as np

from .._validation import check_rng


def rejection_sample(S, rng: np.random.Generator, size: int = 1, max_tries: int = 200_000) -> np.ndarray:
    """Draw ``size`` points uniformly from the bounded set ``S``, shape (size, dim).

    Proposals are uniform on the interval hull and accepted when ``S.contains`` them (one membership
    program each), which gives exactly the uniform distribution on ``S``.

    Raises
    ------
    ValueError
        For empty or unbounded sets, and when fewer than ``size`` proposals out of ``max_tries`` are
        accepted (a flat set has acceptance zero: sample its parametrization instead).
    """
    check_rng(rng)
    hull = S.interval_hull()
    if hull.is_empty():
        raise ValueError("cannot sample from an empty set")
    if not hull.is_bounded:
        raise ValueError("cannot sample uniformly from an unbounded set")
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
