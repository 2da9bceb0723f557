"""Sets are safe to share between threads and to send to other processes, after any query.

Solver instances live in the per-thread cache of `setsmooth.solvers.instances`, never on a set, so a
set queried on either path pickles, and one set queried from several threads answers as it does
serially.
"""

from __future__ import annotations

import pickle
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

import setsmooth as ss

DIRECTIONS = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0], [0.3, -0.7]])


def _cz():
    return ss.ConstrainedZonotope([[1.0, 0.5, 0.0], [0.0, 1.0, 0.7]], [0.1, -0.2],
                                  A=[[1.0, 1.0, 1.0]], b=[0.4])


def _sets():
    E = ss.Ellipsoid([0.2, 0.0], np.diag([1.0, 0.5]))
    H = ss.HPolytope([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, -2.0]], [1.0, 0.5, 0.5, 1.0])
    free = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, -1.0]], b=[0.0],
                                  h=[1.0, np.inf])  # a free factor pinned by the constraint
    return {
        "Box": ss.Box([-1.0, 0.0], [1.0, 2.0]),
        "Zonotope": ss.Zonotope([[1.0, 1.0], [0.0, 1.0]], [0.0, 0.5]),
        "ConstrainedZonotope": _cz(),
        "CZ with a free factor": free,
        "HPolytope": H,
        "Ellipsoid": E,
        "EmptySet": ss.EmptySet(2),
        "Reals": ss.Reals(2),
        "LinearMap": np.array([[1.0, 2.0], [0.0, 1.0]]) @ H,
        "MinkowskiSum": E + H,
        "Intersection": E & H,
        "GeneralizedIntersection": E.intersect_preimage([[1.0, 0.0], [0.0, 1.0]], H),
        "CartesianProduct (projected)": (E * H).project([0, 3]),
    }


def _answers(S, path):
    return (S.support_many(DIRECTIONS, path=path), S.is_empty(path=path),
            S.contains([0.1, 0.1], path=path))


def _assert_same(a, b):
    np.testing.assert_allclose(a[0], b[0], rtol=1e-9, atol=1e-9)
    assert a[1:] == b[1:]


@pytest.mark.parametrize("name", list(_sets()))
def test_every_set_type_pickles_after_queries_on_both_paths_and_answers_the_same(name):
    S = _sets()[name]
    before = {path: _answers(S, path) for path in ("auto", "generic")}
    again = pickle.loads(pickle.dumps(S))
    for path in ("auto", "generic"):
        _assert_same(_answers(again, path), before[path])
    for value in vars(again).values():  # still immutable
        if isinstance(value, np.ndarray):
            assert not value.flags.writeable


@pytest.mark.parametrize("name", ["ConstrainedZonotope", "Intersection", "HPolytope"])
@pytest.mark.parametrize("path", ["auto", "generic"])
def test_one_set_queried_from_four_threads_answers_as_it_does_serially(name, path):
    rng = np.random.default_rng(1)
    D = rng.standard_normal((40, 2))
    S = _sets()[name]
    serial = np.array([S.support(d, path=path) for d in D])
    fresh = pickle.loads(pickle.dumps(S))  # no solver built yet: the threads race to build them
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = np.array(list(pool.map(lambda d: fresh.support(d, path=path), D)))
    np.testing.assert_allclose(threaded, serial, rtol=1e-9, atol=1e-9)


def _support_in_worker(S):
    return S.support_many(DIRECTIONS), S.support_many(DIRECTIONS, path="generic")


def test_a_queried_set_goes_to_a_process_pool():
    S = _cz() & ss.Ellipsoid([0.0, 0.0], np.eye(2))  # lazy: generic path only
    Z = _cz()
    local = [_support_in_worker(T) for T in (S, Z)]
    with ProcessPoolExecutor(max_workers=2) as pool:
        remote = list(pool.map(_support_in_worker, [S, Z]))
    for (a_auto, a_gen), (b_auto, b_gen) in zip(local, remote):
        np.testing.assert_allclose(b_auto, a_auto, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(b_gen, a_gen, rtol=1e-9, atol=1e-9)
