# Two entry points: `make test` and `make figures`. Both create .venv when it is missing (so does
# `make docs`, which builds the documentation site).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs

.PHONY: test figures examples bench reliability docs clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev,dask]"
	touch $(STAMP)

# One BLAS thread per test worker: two workers already fill the two cores, and OpenBLAS's own threads
# spinning against them made a 150 x 204 least-squares solve take 0.3-2.7 s instead of milliseconds.
test: $(STAMP)
	OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 $(PY) -m pytest -n 2 -q tests setsmooth --doctest-modules

# The examples two at a time (each with one BLAS thread), each one's output printed whole when it ends;
# any failure fails the target (xargs exits non-zero), after the others have finished.
examples: $(STAMP)
	@printf '%s\n' examples/*.py | xargs -P 2 -I{} sh -c 'out=$$(MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 \
	  $(PY) "$$1" 2>&1); rc=$$?; printf "== %s\n%s\n" "$$1" "$$out"; exit $$rc' sh {}

figures: examples
	MPLBACKEND=Agg $(PY) -m setsmooth figures

bench: $(STAMP)
	$(PY) benchmarks/bench_support.py

$(DOCS_STAMP): $(STAMP) pyproject.toml
	$(PY) -m pip install --quiet -e ".[docs]"
	touch $(DOCS_STAMP)

# The documentation site (Sphinx; warnings are errors) into docs/_build/html. The gallery shows the
# examples' figures from docs/gallery/images/, so nothing is executed here.
docs: $(DOCS_STAMP)
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

# The large reliability run of issue 7 (>= 250 random systems x 4 regimes x 3 estimators; long).
reliability: $(STAMP)
	$(PY) benchmarks/reliability.py --workers 2

clean:
	rm -rf $(VENV) paper_figures/out examples/out .pytest_cache .hypothesis docs/_build docs/api/generated docs/api/namespace.rst docs/gallery/generated
