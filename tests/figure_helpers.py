"""What every paper-figure test shares besides the ``figures`` fixture (tests/conftest.py): its outputs."""

from __future__ import annotations

import json


def written(out, name):
    """The JSON a figure script wrote to ``out``, after checking that its PNG is a real image."""
    assert (out / f"{name}.png").stat().st_size > 10_000
    return json.loads((out / f"{name}.json").read_text())
