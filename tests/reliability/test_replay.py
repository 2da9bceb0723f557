"""Every incident of the replay corpus (`replay.py`, ``cases/``) against its stored exact answer."""

from __future__ import annotations

import numpy as np
import pytest

from .replay import corpus, load, replay

#: Plain hulls within this fraction of the unit (width plus noise scale) of the exact hull; the
#: reliability runs' target.
PLAIN_TOL = 1e-6

#: Certified hulls enclose the exact hull up to this fraction of the unit (the oracle's own
#: accuracy), and are within PLAIN_TOL of it.
ENCLOSE_TOL = 1e-9


def test_the_corpus_is_not_empty():
    assert len(corpus()) >= 5


@pytest.mark.parametrize("path", corpus(), ids=lambda p: p.stem)
def test_an_incident_replays_to_its_exact_answer(path):
    incident = load(path)
    plain_lo, plain_hi, cert_lo, cert_hi = replay(incident)
    unit = incident.unit
    assert np.all(np.abs(plain_lo - incident.lo) <= PLAIN_TOL * unit), incident.history
    assert np.all(np.abs(plain_hi - incident.hi) <= PLAIN_TOL * unit), incident.history
    assert np.all(cert_lo <= incident.lo + ENCLOSE_TOL * unit), incident.history
    assert np.all(cert_hi >= incident.hi - ENCLOSE_TOL * unit), incident.history
    assert np.all(incident.lo - cert_lo <= PLAIN_TOL * unit), incident.history
    assert np.all(cert_hi - incident.hi <= PLAIN_TOL * unit), incident.history
