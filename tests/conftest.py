"""Test-wide settings.

Hypothesis draws its examples deterministically (``derandomize=True``): the suite is a fixed set of
checks that gives the same verdict on every machine, so a red CI always means a change broke something.
Explore new examples locally with ``pytest --hypothesis-profile=explore``.
"""

import importlib

import pytest
from hypothesis import settings

from setsmooth.runs import cli

settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile("deterministic")


@pytest.fixture
def figures(monkeypatch):
    """Import a figure script (or helper) of paper_figures/ by name (the paper-figure tests)."""
    monkeypatch.syspath_prepend(str(cli.find_figures_dir()))
    return importlib.import_module
