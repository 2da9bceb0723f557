"""Bad input at the door: every public entry point that takes numbers refuses a bad value with a
ValueError/TypeError/IndexError whose message names the argument as the user passed it (issue 7).

The probes, one call with one bad argument each, are `setsmooth.reliability.bad_input.PROBES`;
`benchmarks/bad_input_census.py` classifies the same probes.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from setsmooth.reliability.bad_input import PROBES, Probe


@pytest.mark.parametrize("p", PROBES, ids=[p.id for p in PROBES])
def test_bad_input_is_refused_naming_the_argument(p: Probe):
    with warnings.catch_warnings():
        # A complex value cast to float warns and drops its imaginary part: that is acceptance.
        warnings.simplefilter("error", np.exceptions.ComplexWarning)
        with pytest.raises(p.exc) as info:
            p.call()
    assert re.search(p.names, str(info.value)), f"message does not name the argument: {info.value}"


def test_probe_ids_are_unique():
    ids = [p.id for p in PROBES]
    assert len(ids) == len(set(ids))
