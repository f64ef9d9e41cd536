# Two commands set everything up on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
DEMO_DIR ?= demo-output

.PHONY: demo test bench stress clean clean-jit

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.stamp-install: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	touch $@

$(VENV)/.stamp-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test]"
	touch $@ $(VENV)/.stamp-install

$(VENV)/.stamp-bench: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test,bench]"
	touch $@ $(VENV)/.stamp-test $(VENV)/.stamp-install

demo: $(VENV)/.stamp-install
	$(BIN)/meshwright demo $(DEMO_DIR)

test: $(VENV)/.stamp-test
	$(BIN)/python -m pytest -q

bench: $(VENV)/.stamp-bench
	$(BIN)/python benchmarks/delaunay2d.py
	$(BIN)/python benchmarks/quality2d.py
	$(BIN)/python benchmarks/quad2d.py
	$(BIN)/python benchmarks/delaunay3d.py
	$(BIN)/python benchmarks/quality3d.py
	$(BIN)/python benchmarks/default_size.py
	$(BIN)/python benchmarks/grading2d.py
	$(BIN)/python benchmarks/frontal2d.py
	$(BIN)/python benchmarks/quad_domains.py
	$(BIN)/python benchmarks/scale2d.py
	$(BIN)/python benchmarks/compile2d.py

# Random domains through every 2-D method, triangles and quads (scripts/stress2d.py); failures become reproducers
# under tests/regressions/ that `make test` replays.  STRESS_COUNT domains per run.
STRESS_COUNT ?= 2000
STRESS_SEED ?= 0
STRESS_JOBS ?= 1
stress: $(VENV)/.stamp-test
	$(BIN)/python scripts/stress2d.py --all-methods --count $(STRESS_COUNT) --seed $(STRESS_SEED) --jobs $(STRESS_JOBS)

# Numba's on-disk cache is keyed by each function's own file: after editing a kernel that
# other modules call (e.g. tri/_kernel2d.py), drop the cache so callers are recompiled.
clean-jit:
	find src -name '*.nbi' -delete -o -name '*.nbc' -delete

clean:
	rm -rf $(VENV) $(DEMO_DIR) .pytest_cache .hypothesis
	find src -name '*.nbi' -delete -o -name '*.nbc' -delete
