# Two entry points: `make demo` (set up, solve the thesis PZT taxel) and `make test`.
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
	$(VENV)/bin/taxel solve thesis-pzt-single-2d
	$(VENV)/bin/taxel solve thesis-pzt-3x3-2d

test: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/pytest -q $(PYTEST_ARGS)

bench: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/python benchmarks/taxel_2d.py

.PHONY: setup demo test bench
