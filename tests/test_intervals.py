"""The shared interval module: one set of checks for the interval filter and the interval smoother."""

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.models.intervals import IntervalEstimates, as_interval, eval_eta, noise_intervals
from setsmooth.papers.smoothing_examples import eta_33, measurement_interval_34


def test_filter_and_smoother_exchange_one_estimates_type():
    ys = np.array([3.0, 4.0, 5.0])
    filtered = ss.interval_filter(eta_33, (-1, 1), (-5, 5), ys, measurement_interval_34)
    assert type(filtered) is IntervalEstimates is ss.IntervalEstimates
    assert type(ss.interval_smoother(eta_33, (-1, 1), filtered)) is IntervalEstimates


@pytest.mark.parametrize("bad", [(1.0, -1.0), (-np.inf, 1.0), [[-1, 1], [0, 1], [0, 1]]])
def test_filter_and_smoother_refuse_a_bad_noise_interval_with_one_message(bad):
    filtered = IntervalEstimates([0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError) as from_filter:
        ss.interval_filter(eta_33, bad, (-5, 5), np.zeros(2), measurement_interval_34)
    with pytest.raises(ValueError) as from_smoother:
        ss.interval_smoother(eta_33, bad, filtered)
    assert str(from_filter.value) == str(from_smoother.value)


def test_noise_intervals_broadcast_a_constant_range_and_check_each_row():
    assert noise_intervals((-1, 2), 2).tolist() == [[-1.0, 2.0], [-1.0, 2.0]]
    with pytest.raises(ValueError, match=r"shape \(2,\) or \(T, 2\) = \(3, 2\)"):
        noise_intervals(np.zeros((2, 2)), 3)


def test_as_interval_names_the_argument_and_eval_eta_refuses_nan():
    assert as_interval((-np.inf, 1), "x0", allow_inf=True) == (-np.inf, 1.0)
    with pytest.raises(ValueError, match="x0 must have finite endpoints"):
        as_interval((-np.inf, 1), "x0", allow_inf=False)
    with pytest.raises(TypeError, match="x0 must be a pair of numbers"):
        as_interval("ab", "x0", allow_inf=True)
    with pytest.raises(ValueError, match="eta must be defined on all of R"):
        eval_eta(lambda x: float("nan"), -1.0)
