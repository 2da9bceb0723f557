"""Model invalidation: the exact filter says when and by how much the data contradict the model."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import setsmooth as ss


def _plant(seed: int = 1, T: int = 40):
    A = np.array([[1.0, 0.1], [-0.2, 0.95]])
    system = ss.LinearSystem(A, None, np.array([[1.0, 0.0]]), E=0.1 * np.eye(2), W=ss.Box([-1, -1], [1, 1]),
                             V=ss.Box([-0.1], [0.1]))
    X0 = ss.Box([-1, -1], [1, 1])
    xs, ys = ss.simulate(system, X0, T, np.random.default_rng(seed))
    return system, X0, xs, ys


def test_consistent_data_raise_no_warning():
    system, X0, _, ys = _plant()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        est = ss.classical_filter(system, X0, ys)
    assert est.first_empty is None
    assert ss.first_inconsistency(system, X0, ys) is None


def test_a_sensor_fault_is_found_at_its_step_with_its_size():
    system, X0, _, ys = _plant()
    faulty = ys.copy()
    faulty[30:] += 3.0  # a sensor offset of 3 from k = 30; the noise bound is 0.1
    with pytest.warns(ss.ModelInvalidationWarning, match=r"from k = 30") as record:
        est = ss.classical_filter(system, X0, faulty)
    found = record[0].message.inconsistency
    assert isinstance(found, ss.Inconsistency) and found.step == est.first_empty == 30
    assert np.array_equal(found.measurement, faulty[30])
    # the offset minus what the predicted output set can absorb: positive, at most the offset
    assert 0.0 < found.distance <= 3.0
    with pytest.raises(ss.ModelInvalidatedError, match="k = 30"):
        ss.classical_filter(system, X0, faulty, on_inconsistent="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        ss.classical_filter(system, X0, faulty, on_inconsistent="ignore")


def test_the_first_measurement_can_contradict_the_initial_set():
    system, X0, _, ys = _plant(T=5)
    bad = ys.copy()
    bad[0] = 10.0
    found = ss.first_inconsistency(system, X0, bad)
    assert found.step == 0 and "initial set X0" in str(found)
    assert found.distance == pytest.approx(10.0 - 1.0 - 0.1, rel=1e-6)  # |x1| <= 1, |v| <= 0.1


def test_on_inconsistent_is_checked_at_the_door():
    system, X0, _, ys = _plant(T=3)
    with pytest.raises(ValueError, match="on_inconsistent"):
        ss.classical_filter(system, X0, ys, on_inconsistent="loud")


def test_estimates_of_other_data_are_refused():
    system, X0, _, ys = _plant(T=4)
    est = ss.classical_filter(system, X0, ys)
    with pytest.raises(ValueError, match="estimates has 5 sets but ys has 4"):
        ss.first_inconsistency(system, X0, ys[:4], est)
