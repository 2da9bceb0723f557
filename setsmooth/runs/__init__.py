"""Runs: reproducible Monte Carlo (`montecarlo`), its optional Dask cluster backend (`dask_cluster`) and
the command line that regenerates the paper figures (`cli`). Nothing is imported here: the command line
starts without CVXPY, SciPy and the solvers, and the core never imports Dask."""
