# Two entry points: `make run` (the main job) and `make test` (the test suite).
# Both create or refresh the virtual environment first.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: run test venv lint clean

venv: $(STAMP)

# torch==2.13.0 first: the CPU build these machines carry; a looser spec pulls several GB.
$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q torch==2.13.0
	$(PY) -m pip install -q -e '.[dev]'
	@echo "compiling a unit network's training steps (numba, cached; a few seconds, once)"
	$(PY) -c "from anytip.train.compiled_steps import compile_now; compile_now()"
	touch $(STAMP)

run: $(STAMP)
	$(VENV)/bin/anytip

test: $(STAMP)
	bash scripts/system-deps.sh
	$(PY) -m pytest -n 2 -q

lint: $(STAMP)
	$(VENV)/bin/ruff check research tests

clean:
	rm -rf $(VENV) build research/*.egg-info
