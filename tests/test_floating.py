"""The error constants of binary64 arithmetic bound what a floating-point sum loses."""

from fractions import Fraction

import numpy as np

from setsmooth.floating import gamma


def test_gamma_bounds_the_error_of_a_float_sum():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(1000) * 10.0 ** rng.integers(-8, 8, 1000)
    exact = sum(Fraction(v) for v in x)
    assert abs(Fraction(float(np.sum(x))) - exact) <= Fraction(float(gamma(1000) * np.abs(x).sum()))
