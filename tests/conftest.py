"""Test-wide settings.

Hypothesis draws its examples deterministically (``derandomize=True``): the suite is a fixed set of
checks that gives the same verdict on every machine, so a red CI always means a change broke something.
Explore new examples locally with ``pytest --hypothesis-profile=explore``.
"""

from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile("deterministic")
