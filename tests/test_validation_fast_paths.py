"""The per-step checks' fast paths (a float, a float64 vector, a pair of floats, as callbacks return
them at every step) give the same values and the same errors as the general checks."""

from __future__ import annotations

import numpy as np
import pytest

from setsmooth._validation import as_vector, real_array, real_number
from setsmooth.models.intervals import as_interval, eval_eta

INF, NAN = float("inf"), float("nan")


def outcome(check, *args, **kwargs):
    try:
        return "ok", check(*args, **kwargs)
    except (TypeError, ValueError) as exc:
        return type(exc).__name__, str(exc)


def same(a, b):
    if a[0] != "ok" or b[0] != "ok":
        return a == b
    return np.array_equal(np.asarray(a[1]), np.asarray(b[1]), equal_nan=True)


@pytest.mark.parametrize("values", [[1.5], [0.0, -2.0, 3.0], [NAN], [1.0, INF], [-INF, NAN], list(range(12)),
                                    [1.0] * 11 + [INF], [1.0] * 11 + [NAN]])
@pytest.mark.parametrize("allow_inf", [False, True])
def test_a_float_vector_is_checked_as_its_list_is(values, allow_inf):
    fast = np.array(values, dtype=float)
    for dim in (None, len(values), len(values) + 1):
        assert same(outcome(as_vector, fast, "f(3, x, w)", dim, allow_inf),
                    outcome(as_vector, list(values), "f(3, x, w)", dim, allow_inf))
    if all(np.isfinite(values)) or allow_inf and not np.isnan(values).any():
        assert as_vector(fast, "x", allow_inf=allow_inf) is fast      # taken as it is, no copy


def test_real_array_takes_a_native_float_array_as_it_is_and_converts_others():
    a = np.arange(6.0)[::2]
    assert real_array(a, "a") is a
    big_endian = np.arange(3.0).astype(">f8")
    assert real_array(big_endian, "a").dtype == np.float64
    with pytest.raises(TypeError, match="complex"):
        real_array(np.array([1j]), "a")


@pytest.mark.parametrize("value", [2.5, np.float64(-1.25), NAN, INF])
def test_a_float_is_the_number_its_array_is(value):
    assert same(outcome(real_number, value, "eta(1.0)"), outcome(real_number, np.array(value), "eta(1.0)"))
    assert type(real_number(value, "x")) is float


@pytest.mark.parametrize("pair", [(1.0, 2.0), (2.0, 1.0), (NAN, 1.0), (1.0, NAN), (-INF, INF), (INF, INF),
                                  (-INF, 0.0), (np.float64(0.5), np.float64(0.75)), (np.float64(1.0), 0.0)])
@pytest.mark.parametrize("allow_inf", [False, True])
def test_a_pair_of_floats_is_checked_as_its_list_is(pair, allow_inf):
    name = "measurement_interval(4, ys[4])"
    fast, general = outcome(as_interval, pair, name, allow_inf), outcome(as_interval, list(pair), name, allow_inf)
    assert fast == general or (fast[0] == "ok" and same(fast, general))
    if fast[0] == "ok":
        assert all(type(x) is float for x in fast[1])


def test_eta_values_are_checked_as_before_whatever_their_type():
    assert eval_eta(lambda x: np.cbrt(x) + x, 8.0) == 10.0
    assert type(eval_eta(lambda x: np.float64(x), 2)) is float
    assert eval_eta(lambda x: np.array([x]), 2) == 2.0                 # a one-element array, as float() takes it
    with pytest.raises(ValueError, match=r"eta\(2.0\) returned NaN"):
        eval_eta(lambda x: NAN, 2)
    with pytest.raises(TypeError, match="real"):
        eval_eta(lambda x: 1j, 2)
    with pytest.raises(TypeError, match=r"eta\(2.0\) must be a real number"):
        eval_eta(lambda x: "1", 2)
