# Two entry points: `make demo` (set up, run the main job, build the report) and `make test`
# (the fast tier: every test not marked slow, on two workers: under 5 minutes on 2 cores); `make test-all` runs
# every test, slow ones too (CI runs it); `make docs` builds the documentation site into
# docs/_build/html (warnings are errors).
PY ?= python3
VENV := .venv
STAMP := $(VENV)/.installed

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -e '.[test,docs]'
	touch $(STAMP)

setup: $(STAMP)

demo: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/taxel demo --out out/demo

# the fast tier on two workers (pytest-xdist); a file's tests stay on one worker, in order
# (the README's blocks build on each other's folders)
test: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/pytest -q -m "not slow" -n 2 --dist loadfile $(PYTEST_ARGS)

# every test, slow ones too (CI), on the same two workers: the slow tier grew by the 3D skin, the
# surface map, the friction solve and the press reference (measured file by file with -n 2 --dist loadfile)
test-all: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/pytest -q -n 2 --dist loadfile $(PYTEST_ARGS)

docs: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/sphinx-build -W --keep-going -q -b html docs docs/_build/html
	@echo "open docs/_build/html/index.html"

lint: $(STAMP)
	.ci/lint-imports
	$(VENV)/bin/ruff check --select F .

bench: $(STAMP)
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/python benchmarks/taxel_2d.py
	MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 $(VENV)/bin/python benchmarks/default_mesh.py

.PHONY: setup demo test test-all docs lint bench
