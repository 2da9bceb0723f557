"""The papers setsmooth implements: their references (`references`) and their example systems, one
definition for the figures, tests, benchmarks and docs (`smoothing_examples`, `rethinking_examples`)."""
