"""`ParametricPoints`: support points along time where a block of the constraint matrix changes too."""

import numpy as np

import setsmooth as ss
from setsmooth.solvers.parametric import ParametricPoints


def _program(rng, nc=6, ng=14, n=3):
    G = rng.standard_normal((n, ng))
    A = rng.standard_normal((nc, ng))
    block = (np.array([0, 0, 1, 2, 2]), np.array([3, 4, 5, 3, 6]))
    A[block] = 1.0  # placeholders: the entries are stored
    return G, A, block


def test_points_follow_the_block_and_b_and_equal_each_sets_own_support():
    """A sequence of programs whose b, h and block entries change: every value equals the CZ's own
    support (solved from scratch) and every point is in the set."""
    rng = np.random.default_rng(3)
    n = 3
    G, A, block = _program(rng, n=n)
    D = np.vstack([np.eye(n), -np.eye(n)])
    free = np.zeros(G.shape[1], dtype=bool)
    free[0] = True  # one free factor, as the inner windows' states
    session = ParametricPoints(G, A, D, free, block).session()
    for step in range(6):
        values = rng.uniform(-1.0, 1.0, block[0].size)
        A_now = A.copy()
        A_now[block] = values
        xi0 = rng.uniform(-0.5, 0.5, G.shape[1])  # a feasible point: b = A ξ0
        h = np.where(free, np.inf, rng.uniform(0.8, 1.5, G.shape[1]))
        b = A_now @ xi0
        c = rng.standard_normal(n)
        got, points = session.points(c, b, h, values)
        Z = ss.ConstrainedZonotope(G, c, A_now, b, h=np.where(free, np.inf, h))
        own = Z.support_many(D)
        scale = 1.0 + np.abs(own).max()
        assert np.all(np.abs(got - own) <= 1e-7 * scale), step
        assert all(Z.contains(p, tol=1e-6) for p in points)
        assert np.allclose(np.einsum("ij,ij->i", D, points), got)


def test_an_infeasible_program_gives_no_points():
    rng = np.random.default_rng(4)
    G, A, block = _program(rng)
    D = np.vstack([np.eye(3), -np.eye(3)])
    free = np.zeros(G.shape[1], dtype=bool)
    session = ParametricPoints(G, A, D, free, block).session()
    b = np.full(A.shape[0], 1e3)  # far beyond what |ξ| ≤ 1 reaches
    values, points = session.points(np.zeros(3), b, np.ones(G.shape[1]), np.ones(block[0].size))
    assert np.isnan(values).all() and np.isnan(points).all()
