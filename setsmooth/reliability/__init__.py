"""The reliability suite (issue 7): the numerical core measured against independent computations.

* `random_systems`: seeded random systems of five kinds (control.drss), box and CZ noises, four regimes;
* `oracle`: exact interval hulls of filtered and smoothed ranges by a trajectory LP solved with HiGHS,
  validated against vertex enumeration (`test_oracle`);
* `compare`: the three exact estimators' hulls (plain and certified) scored against the oracle;
* `rescaling`: random CZs re-represented by 1e±12 scalings of rows, factors and coordinates;
* `witness`: certified supports against feasible points;
* `concurrency`: threads, pickling, and the Monte Carlo guard.

The tests in ``tests/reliability/`` are the small version run by ``make test``; ``benchmarks/reliability.py`` (``make
reliability``) is the large one.
"""
