"""Model invalidation everywhere: every set-membership estimator says when the data contradict the model.

One plant, one sensor fault (an offset of 3 from k = 30, the noise bound being 0.1), and each estimator:
the exact filter and the smoothers (exact: empty exactly when the data are inconsistent), the OIT and
LSU filters (outer bounds: empty only when they are). Each names k = 30 and y_30 with the same warning
class, raises with ``on_inconsistent='raise'`` and is silent on consistent data.
"""

from __future__ import annotations

import warnings

import control
import numpy as np
import pytest

import setsmooth as ss

A = np.array([[1.0, 0.1], [-0.2, 0.95]])
FAULT_STEP = 30


@pytest.fixture(scope="module")
def data():
    """The plant x⁺ = A x + 0.1 w, y = x_1 + v, |w| ≤ 1, |v| ≤ 0.1, as a system and as an LSU model."""
    plant = control.ss(A, 0.1 * np.eye(2), [[1.0, 0.0]], 0, dt=True)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1, -1], [1, 1]), V=ss.Box([-0.1], [0.1]),
                                             noise_inputs=[0, 1])
    model = ss.LSUModel(A=A, B=np.zeros((2, 1)), C=[[1.0, 0.0]], omega=[0.1, 0.1], v=[0.1],
                        x1_lo=[-1, -1], x1_hi=[1, 1])
    X0 = ss.Box([-1, -1], [1, 1])
    xs, ys = ss.simulate(system, X0, 40, np.random.default_rng(1))
    faulty = ys.copy()
    faulty[FAULT_STEP:] += 3.0
    return system, model, X0, xs, ys, faulty


ESTIMATORS = {
    "optimal_smoother trajectory": lambda d, ys, **kw: ss.optimal_smoother(d[0], d[2], ys, **kw),
    "optimal_smoother recursion": lambda d, ys, **kw: ss.optimal_smoother(d[0], d[2], ys,
                                                                          method="recursion", **kw),
    "oit_cz_filter": lambda d, ys, **kw: ss.oit_cz_filter(d[0], d[2], ys, **kw),
    "oit_cz_filter hulls": lambda d, ys, **kw: ss.oit_cz_filter(d[0], d[2], ys, hulls=True, **kw),
    "oit_inspired_filter": lambda d, ys, **kw: ss.oit_inspired_filter(d[0], d[2], ys, **kw),
    "lsu_cz_filter": lambda d, ys, **kw: ss.lsu_cz_filter(d[1], ys, np.zeros((len(ys), 1)), **kw),
    "lsuo_filter": lambda d, ys, **kw: ss.lsuo_filter(d[1], ys, np.zeros((len(ys), 1)), **kw),
    "lsup_filter": lambda d, ys, **kw: ss.lsup_filter(d[1], ys, np.zeros((len(ys), 1)), **kw),
}


@pytest.mark.parametrize("name", ESTIMATORS)
def test_a_sensor_fault_is_reported_at_its_step_by_every_estimator(data, name):
    faulty = data[5]
    with pytest.warns(ss.ModelInvalidationWarning, match=rf"k = {FAULT_STEP}\b") as record:
        result = ESTIMATORS[name](data, faulty)
    found = [w.message.inconsistency for w in record if isinstance(w.message, ss.ModelInvalidationWarning)]
    assert len(found) == 1, "one warning per estimator call"
    assert found[0].step == FAULT_STEP and np.array_equal(found[0].measurement, faulty[FAULT_STEP])
    # the offset minus what the predicted output set absorbs: positive, at most the offset
    assert 0.0 < found[0].distance <= 3.0
    expected_first = 0 if name.startswith("optimal_smoother") else FAULT_STEP  # a smoothed set uses all data
    assert result.first_empty == expected_first
    assert isinstance(result[FAULT_STEP], ss.EmptySet)
    with pytest.raises(ss.ModelInvalidatedError, match=rf"k = {FAULT_STEP}\b"):
        ESTIMATORS[name](data, faulty, on_inconsistent="raise")


@pytest.mark.parametrize("name", ESTIMATORS)
def test_consistent_data_give_no_warning(data, name):
    _, _, _, xs, ys, _ = data
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        result = ESTIMATORS[name](data, ys)
    assert not any(isinstance(S, ss.EmptySet) for S in result)


def test_outer_bound_verdicts_say_what_they_prove(data):
    _, _, _, _, _, faulty = data
    with pytest.warns(ss.ModelInvalidationWarning) as record:
        ss.lsuo_filter(data[1], faulty, np.zeros((len(faulty), 1)))
    found = record[0].message.inconsistency
    assert found.estimator == "LSUO" and "outer bound" in str(found)
    # the exact filter's verdict at the same step: the outer prediction is larger, its miss no larger
    exact = ss.first_inconsistency(data[0], data[2], faulty)
    assert exact.step == found.step and found.distance <= exact.distance + 1e-9


def test_ignore_is_silent_and_unknown_values_are_refused(data):
    _, _, _, _, _, faulty = data
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        for name in ("oit_cz_filter", "lsup_filter", "optimal_smoother trajectory"):
            ESTIMATORS[name](data, faulty, on_inconsistent="ignore")
    for name in ESTIMATORS:
        with pytest.raises(ValueError, match="on_inconsistent"):
            ESTIMATORS[name](data, faulty[:5], on_inconsistent="loud")


def test_line5_failure_is_an_inconsistency_not_a_crash(monkeypatch):
    from setsmooth.filters import oit

    monkeypatch.setattr(oit, "MAX_DOUBLINGS", 3)  # θ ≤ 8 cannot reach y_0 = 100
    plant = control.ss([[1.0, 1.0], [0.0, 1.0]], [[0.5], [1.0]], [[1.0, 0.0]], 0, dt=True)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]),
                                             noise_inputs=[0])
    ys = np.array([[100.0], [0.0]])
    with pytest.warns(ss.ModelInvalidationWarning, match="k = 0"):
        result = ss.oit_cz_filter(system, ss.Box([-1, -1], [1, 1]), ys, delta_bar=1)
    assert all(isinstance(S, ss.EmptySet) for S in result) and result.first_empty == 0


def test_the_helper_refuses_smoothed_sets_which_do_not_locate_the_step(data):
    system, _, X0, _, _, faulty = data
    with pytest.warns(ss.ModelInvalidationWarning):
        smoothed = ss.optimal_smoother(system, X0, faulty)
    with pytest.raises(ValueError, match="filter's sets"):
        ss.first_inconsistency(system, X0, faulty, smoothed)
    assert ss.first_inconsistency(system, X0, faulty).step == FAULT_STEP


def test_a_detectable_system_reports_the_fault_and_stays_empty_after_it():
    # x_0 is unobservable (eigenvalue 0.5): the OIT-CZ's later windows start from earlier hulls
    plant = control.ss([[0.5, 1.0], [0.0, 1.0]], [[0.5], [1.0]], [[0.0, 1.0]], 0, dt=True)
    system = ss.LinearSystem.from_statespace(plant, W=ss.Box([-1.0], [1.0]), V=ss.Box([-1.0], [1.0]),
                                             noise_inputs=[0])
    X0 = ss.Box([-1, -1], [1, 1])
    xs, ys = ss.simulate(system, X0, 36, np.random.default_rng(5))
    faulty = ys.copy()
    faulty[FAULT_STEP:] += 10.0
    for hulls in (False, True):
        with pytest.warns(ss.ModelInvalidationWarning, match=rf"k = {FAULT_STEP}\b"):
            result = ss.oit_cz_filter(system, X0, faulty, hulls=hulls)
        assert result.first_empty == FAULT_STEP
        assert all(isinstance(S, ss.EmptySet) for S in result[FAULT_STEP:])
        assert np.isnan(result.lo[FAULT_STEP:]).all() and np.isfinite(result.lo[:FAULT_STEP]).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        assert ss.oit_cz_filter(system, X0, ys).contains_trajectory(xs).all()


def _scalar_interval_runs():
    """The scalar interval filters on their papers' examples: (name, run(ys, **kw), consistent ys)."""
    from setsmooth.papers.rethinking_examples import rethinking_example_27
    from setsmooth.papers.smoothing_examples import eta_33, measurement_interval_34

    _, ys_33 = ss.simulate(ss.paper_examples.smoothing_example_33(), ss.Box([-5.0], [5.0]), 12,
                           np.random.default_rng(4))
    system_27 = rethinking_example_27()
    _, ys_27 = system_27.simulate(12, np.random.default_rng(4))
    return [
        ("interval_filter", lambda ys, **kw: ss.interval_filter(eta_33, (-1, 1), (-5, 5), ys,
                                                                measurement_interval_34, **kw), ys_33[:, 0]),
        ("classical_interval_filter", lambda ys, **kw: ss.classical_interval_filter(system_27, ys, **kw),
         ys_27[0]),
    ]


@pytest.mark.parametrize("case", range(2), ids=["interval_filter", "classical_interval_filter"])
def test_the_scalar_interval_filters_report_a_fault_as_the_others_do(case):
    name, run, ys = _scalar_interval_runs()[case]
    fault = 6
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        assert run(ys).first_empty is None
    faulty = ys.copy()
    faulty[fault:] += 40.0
    with pytest.warns(ss.ModelInvalidationWarning, match=rf"k = {fault}\b.*states consistent with y_{fault}") \
            as record:
        result = run(faulty)
    found = [w.message.inconsistency for w in record if isinstance(w.message, ss.ModelInvalidationWarning)]
    assert len(found) == 1 and found[0].step == fault == result.first_empty
    assert np.array_equal(found[0].measurement, [faulty[fault]])
    # the gap between the states y_6 allows and the predicted range, which the two intervals show
    (c_lo, c_hi), (p_lo, p_hi) = found[0].consistent, found[0].predicted
    assert found[0].distance == max(c_lo - p_hi, p_lo - c_hi) > 0
    with pytest.raises(ss.ModelInvalidatedError, match=rf"k = {fault}\b"):
        run(faulty, on_inconsistent="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ss.ModelInvalidationWarning)
        assert run(faulty, on_inconsistent="ignore").first_empty == fault
    with pytest.raises(ValueError, match="on_inconsistent"):
        run(faulty, on_inconsistent="loud")
