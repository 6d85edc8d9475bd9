# Two commands do all set-up on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# the tests', the cluster's and the lab's extras (pytest, mypy, playwright, dask, optuna ...):
# `make test` and `make install-dev` only
DEV_STAMP := $(VENV)/.installed-dev
# the penalty ground's MuJoCo engine plugin (sim_core/model/ground.py), compiled against the
# installed mujoco wheel's headers and library
PLUGIN := sim_core/model/libpenalty_ground.so
API_PORT ?= 8000
VIEWER_PORT ?= 8080

# bash for `wait -n` in `run`
SHELL := /bin/bash

.PHONY: install install-dev plugin run test lint typecheck bench screenshot clean

# setuptools' editable build tells, as a Python warning, that a folder named like a package
# may shadow it ("Editable installation." and a box of `!!`, then the line that warned): the
# build backend inherits this filter, which matches that message only. pip's other notices
# about setuptools are grepped out; a failed install still says so and stops make.
QUIET_BUILD := PYTHONWARNINGS="ignore:Editable installation"

# What running needs, and no more (the image installs the same: Dockerfile).
$(STAMP): pyproject.toml
	@echo "insect-gait: installing into $(VENV) (first time ~1-3 min: MuJoCo, numba, viser) ..."
	@$(PYTHON) -m venv $(VENV)
	@$(BIN)/pip install --quiet --disable-pip-version-check --upgrade pip
	@$(QUIET_BUILD) $(BIN)/pip install --quiet --disable-pip-version-check -e . 2>&1 | grep -v -i setuptools || true
	@$(BIN)/python -c "import sim_core, server, web" || { echo "insect-gait: install failed" >&2; exit 1; }
	@touch $(STAMP)
	@echo "insect-gait: installed."

$(DEV_STAMP): $(STAMP)
	@echo "insect-gait: installing the test, cluster and lab extras (pytest, mypy, playwright, dask, optuna) ..."
	@$(QUIET_BUILD) $(BIN)/pip install --quiet --disable-pip-version-check -e '.[dev,cluster,lab]' 2>&1 | grep -v -i setuptools || true
	@$(BIN)/python -c "import pytest, mypy, playwright, optuna" || { echo "insect-gait: install failed" >&2; exit 1; }
	@touch $(DEV_STAMP)

$(PLUGIN): sim_core/model/penalty_ground.c sim_core/model/ground_build.py $(STAMP)
	@echo "insect-gait: compiling the paper's ground (a MuJoCo plugin) ..."
	@$(BIN)/python -m sim_core.model.ground_build $(PLUGIN)

install: $(STAMP) $(PLUGIN)

install-dev: $(DEV_STAMP) $(PLUGIN)

plugin: $(PLUGIN)

# Both servers in the background; Ctrl-C (or TERM) stops both and the recipe exits 0, quietly.
# (The old `trap 'kill 0' ...` sent TERM to its own shell from inside the TERM trap, which
# recursed until the shell crashed: "make: *** [run] Segmentation fault".) If one server exits
# by itself, the other is stopped and its status is the recipe's.
run: $(STAMP) $(PLUGIN)
	@echo "API:    http://127.0.0.1:$(API_PORT)/docs"
	@echo "Viewer: http://127.0.0.1:$(VIEWER_PORT)"
	@$(BIN)/insect-gait api --host 127.0.0.1 --port $(API_PORT) & api=$$!; \
	$(BIN)/insect-gait viewer --host 127.0.0.1 --port $(VIEWER_PORT) \
		--api-url http://127.0.0.1:$(API_PORT) & viewer=$$!; \
	stop() { trap '' INT TERM; kill -TERM $$api $$viewer 2>/dev/null; wait 2>/dev/null; }; \
	trap 'stop; exit 0' INT TERM; \
	wait -n; status=$$?; stop; exit $$status

test: $(DEV_STAMP) $(PLUGIN)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/lint-imports
	$(BIN)/pytest

lint: $(DEV_STAMP)
	$(BIN)/ruff check . && $(BIN)/ruff format --check .

typecheck: $(DEV_STAMP)
	$(BIN)/mypy

bench: $(STAMP) $(PLUGIN)
	$(BIN)/insect-gait bench

# Refresh the README's screenshot (make test writes it to out/ only, leaving the tree clean).
screenshot: $(DEV_STAMP) $(PLUGIN)
	CI=true $(BIN)/pytest -q tests/web/test_viewer_browser.py -k renders
	cp out/viewer.png docs/figures/viewer.png

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache $(PLUGIN)
