"""Bad arguments to `setsmooth.analysis` fail at the door, naming the argument."""

import numpy as np
import pytest

import setsmooth as ss
from setsmooth import analysis


@pytest.mark.parametrize("call, error, message", [
    (lambda: analysis.observability_decomposition([[1j]], [[1.0]]), TypeError, "A must be real"),
    (lambda: analysis.observability_decomposition([[1.0, 2.0]], [[1.0]]), ValueError, "A must be square"),
    (lambda: analysis.observability_decomposition(np.eye(2), [[np.nan, 0.0]]), ValueError, "C contains NaN"),
    (lambda: analysis.observability_decomposition(np.eye(2), [[1.0, 0.0]], n_o=1), ValueError, "n_o is only"),
    (lambda: analysis.observability_index([[1.0, 2.0]], [[1.0, 0.0]]), ValueError, "A must be square"),
    (lambda: analysis.is_marginally_stable([[1.0, 2.0]]), ValueError, "M must be square"),
    (lambda: analysis.upsilon_inf([[1.0, 2.0]]), ValueError, "A_obar must be square"),
    (lambda: analysis.oit_diameter_bound(np.eye(2), [[1.0]], [[1.0, 0.0]], 1, 1, 1), ValueError, "B must have shape"),
    (lambda: analysis.oit_diameter_bound([[1, 1], [0, 1]], [[1], [1]], [[1, 0]], 1, 1, 1.5), ValueError, "delta"),
    (lambda: analysis.oit_diameter_bound([[1, 1], [0, 1]], [[1], [1]], [[1, 0]], "x", 1, 1), TypeError, "W"),
    (lambda: analysis.minimize_oit_diameter_bound([[1, 1], [0, 1]], [[1], [1]], [[1, 0]], 1, 1, delta_max=0),
     ValueError, "delta_max must be at least mu - 1 = 1"),
    (lambda: analysis.hausdorff_distance(ss.Box([0], [1]), ss.Box([0, 0], [1, 1])), ValueError, "same dimension"),
    (lambda: analysis.hausdorff_distance(ss.Box([0], [1]), ss.Box([0], [1]), norm=1), ValueError, "norm must be 2 or inf"),
    (lambda: analysis.check_egregium(np.eye(2), [[1.0, 0.0]], ss.Box([0, 0], [1, 1]), ss.Box([0, 0], [1, 1]),
                                     decomposition="P"), TypeError, "decomposition must be"),
    (lambda: analysis.random_observable_system(np.random.default_rng(0), 0, 1, 1), ValueError, "n must be a positive"),
])
def test_bad_arguments_are_named(call, error, message):
    with pytest.raises(error, match=message):
        call()
