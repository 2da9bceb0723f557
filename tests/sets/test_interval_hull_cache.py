"""The interval hull of an (immutable) set is computed once: hull, diameter and centre share it."""

import pickle

import numpy as np
import pytest

import setsmooth as ss


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
    original = type(S)._support_points

    def counting(self, D, path, certified):
        calls.append((D.shape[0], path, certified))
        return original(self, D, path, certified)

    monkeypatch.setattr(type(S), "_support_points", counting)
    hull = S.interval_hull()
    assert S.diameter() == pytest.approx(float(np.max(hull.hi - hull.lo)))
    assert np.allclose(S.center(), (hull.lo + hull.hi) / 2)
    assert S.interval_hull() is hull
    assert len(calls) == 1 and calls[0][:2] == (4, "auto")  # one stacked program of 2·dim directions
    # A fresh set with the same data gives the same hull (the cache holds the true answer).
    fresh = _sets()[name].interval_hull()
    assert np.array_equal(fresh.lo, hull.lo) and np.array_equal(fresh.hi, hull.hi)


def test_certified_and_generic_hulls_are_kept_apart():
    S = _sets()["cz"]
    plain, certified = S.interval_hull(), S.interval_hull(certified=True)
    generic = S.interval_hull(path="generic")
    assert plain is not certified and plain is not generic
    assert np.all(certified.hi >= plain.hi - 1e-12) and np.all(certified.lo <= plain.lo + 1e-12)
    assert np.allclose(generic.hi, plain.hi, atol=1e-6)
    assert S.interval_hull(certified=True) is certified


def test_a_set_with_a_cached_hull_pickles_and_keeps_answering():
    S = _sets()["cz"]
    hull = S.interval_hull()
    T = pickle.loads(pickle.dumps(S))
    assert np.array_equal(T.interval_hull().lo, hull.lo) and np.array_equal(T.interval_hull().hi, hull.hi)
    assert T.support([1.0, 1.0]) == pytest.approx(S.support([1.0, 1.0]))


def test_an_empty_set_caches_its_empty_hull():
    S = ss.ConstrainedZonotope(np.eye(2), [0.0, 0.0], A=[[1.0, 1.0]], b=[5.0])
    assert isinstance(S.interval_hull(), ss.EmptySet)
    assert S.diameter() == -np.inf
    assert np.isnan(S.center()).all()
