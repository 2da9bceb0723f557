"""The reliability suite (issue 7): the numerical core measured against independent computations.

* `random_systems`: seeded random systems of five kinds (control.drss), box and CZ noises, four regimes;
* `oracle`: exact interval hulls of filtered and smoothed ranges by a trajectory LP solved with HiGHS,
  validated against vertex enumeration (`test_oracle`);
* `compare`: the three exact estimators' hulls (plain and certified) scored against the oracle;
* `rescaling`: random CZs re-represented by 1e±12 scalings of rows, factors and coordinates;
* `witness`: certified supports against feasible points;
* `concurrency`: threads, pickling, and the Monte Carlo guard;
* `reduced_filter_trials`: seeded trials of the reduced classical filter, the true state in every posterior;
* `bad_input`: one probe per public entry point and bad value, refused at the door naming the argument;
* `block_assembly`: the trajectory set's former block-by-block assembly, the reference of the current one.

The tests in ``tests/reliability/`` are the small version run by ``make test``; ``benchmarks/reliability.py`` (``make
reliability``) is the large one.
"""
