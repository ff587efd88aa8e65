# Two entry points: `make demo` (set up, run the main job, build the report) and `make test`.
PY ?= python3
VENV := .venv
STAMP := $(VENV)/.installed

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -e '.[test]'
	touch $(STAMP)

setup: $(STAMP)

demo: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/taxel demo --out out/demo

test: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/pytest -q $(PYTEST_ARGS)

lint: $(STAMP)
	.ci/lint-imports

bench: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/python benchmarks/taxel_2d.py
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/python benchmarks/default_mesh.py

.PHONY: setup demo test lint bench
