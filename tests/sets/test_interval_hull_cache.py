"""The interval hull of an (immutable) set is computed once: hull, diameter and centre share it."""

import pickle

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.solvers.cz_program import CZProgram


def _sets():
    return {
        "cz": ss.ConstrainedZonotope(np.eye(2), [0.0, 1.0], A=[[1.0, 1.0]], b=[0.5]),
        "hpolytope": ss.HPolytope(np.vstack([np.eye(2), -np.eye(2), [[1.0, 1.0]]]), [1, 2, 1, 1, 1.5]),
        "lazy": ss.Ellipsoid([0.0, 0.0], np.eye(2)) & ss.HPolytope([[1.0, 0.0]], [0.0]),
    }


@pytest.mark.parametrize("name", ["cz", "hpolytope", "lazy"])
def test_hull_diameter_and_centre_solve_the_hull_programs_once(name, monkeypatch):
    S = _sets()[name]
    calls = []
    if name == "cz":  # the hull's LPs, whichever entry point reaches them
        original_solve = CZProgram._solve

        def counting(self, D, *args, **kwargs):
            calls.append((D.shape[0], "auto"))
            return original_solve(self, D, *args, **kwargs)

        monkeypatch.setattr(CZProgram, "_solve", counting)
    else:
        original = type(S)._support_points

        def counting(self, D, path, certified):
            calls.append((D.shape[0], path))
            return original(self, D, path, certified)

        monkeypatch.setattr(type(S), "_support_points", counting)
    hull = S.interval_hull()
    assert S.diameter() == pytest.approx(float(np.max(hull.hi - hull.lo)))
    assert np.allclose(S.center(), (hull.lo + hull.hi) / 2)
    assert S.interval_hull() is hull
    assert calls == [(4, "auto")]  # one stacked program of 2·dim directions
    # A fresh set with the same data gives the same hull (the cache holds the true answer).
    fresh = _sets()[name].interval_hull()
    assert np.array_equal(fresh.lo, hull.lo) and np.array_equal(fresh.hi, hull.hi)


def test_certified_and_generic_hulls_are_kept_apart():
    S = _sets()["cz"]
    plain, certified = S.interval_hull(certified=False), S.interval_hull(certified=True)
    generic = S.interval_hull(path="generic")
    assert plain is not certified and plain is not generic
    assert S.interval_hull() is certified  # the default: certified where available
    assert np.all(certified.hi >= plain.hi - 1e-12) and np.all(certified.lo <= plain.lo + 1e-12)
    assert np.allclose(generic.hi, plain.hi, atol=1e-6)
    assert S.interval_hull(certified=True) is certified


def test_a_set_with_a_cached_hull_pickles_and_keeps_answering():
    S = _sets()["cz"]
    hull = S.interval_hull()
    T = pickle.loads(pickle.dumps(S))
    assert np.array_equal(T.interval_hull().lo, hull.lo) and np.array_equal(T.interval_hull().hi, hull.hi)
    assert T.support([1.0, 1.0]) == pytest.approx(S.support([1.0, 1.0]))


def test_a_cz_pickles_without_its_stored_vertices():
    """`cz_vertices` keeps a set's vertices on it (derived data, like its program): a pickle carries
    the set, not them, and the copy enumerates the same vertices again."""
    from setsmooth.sets.cz_vertices import cz_vertices

    S = ss.ConstrainedZonotope(np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 1.0]]), [0.0, 0.0],
                               A=[[1.0, 1.0, 1.0]], b=[0.5])
    V = cz_vertices(S)
    T = pickle.loads(pickle.dumps(S))
    assert "_vertices" in S.__dict__ and "_vertices" not in T.__dict__
    assert np.array_equal(cz_vertices(T), V)


def test_an_empty_set_caches_its_empty_hull():
    S = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[5.0])
    assert isinstance(S.interval_hull(), ss.EmptySet)
    assert S.diameter() == -np.inf
    assert np.isnan(S.center()).all()


def test_plain_and_certified_hulls_of_a_cz_share_one_set_of_solves(monkeypatch):
    """The plain hull's solves certify it too: asking for both solves once, and the certified hull
    is the one computed on its own (and encloses the plain one)."""
    rng = np.random.default_rng(3)
    data = dict(G=rng.normal(size=(3, 6)), c=rng.normal(size=3), A=rng.normal(size=(2, 6)), b=[0.1, -0.2])
    alone = ss.ConstrainedZonotope(**data).interval_hull(certified=True)
    S = ss.ConstrainedZonotope(**data)
    calls = []
    original_solve = CZProgram._solve

    def counting(self, D, *args, **kwargs):
        calls.append(D.shape[0])
        return original_solve(self, D, *args, **kwargs)

    monkeypatch.setattr(CZProgram, "_solve", counting)
    plain = S.interval_hull(certified=False)
    certified = S.interval_hull(certified=True)
    assert S.interval_hull() is certified  # certified where available
    assert calls == [6]
    assert np.all(certified.hi >= plain.hi) and np.all(certified.lo <= plain.lo)
    assert np.allclose(certified.lo, alone.lo, rtol=0, atol=1e-12)
    assert np.allclose(certified.hi, alone.hi, rtol=0, atol=1e-12)
