# Two commands do all set-up on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# the penalty ground's MuJoCo engine plugin (sim_core/model/ground.py), compiled against the
# installed mujoco wheel's headers and library
PLUGIN := sim_core/model/libpenalty_ground.so
API_PORT ?= 8000
VIEWER_PORT ?= 8080

# bash for `wait -n` in `run`
SHELL := /bin/bash

.PHONY: install plugin run test lint typecheck bench screenshot clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[dev,cluster]'
	touch $(STAMP)

$(PLUGIN): sim_core/model/penalty_ground.c sim_core/model/ground_build.py $(STAMP)
	$(BIN)/python -m sim_core.model.ground_build $(PLUGIN)

install: $(STAMP) $(PLUGIN)

plugin: $(PLUGIN)

# Both servers in the background; Ctrl-C (or TERM) stops both and the recipe exits 0, quietly.
# (The old `trap 'kill 0' ...` sent TERM to its own shell from inside the TERM trap, which
# recursed until the shell crashed: "make: *** [run] Segmentation fault".) If one server exits
# by itself, the other is stopped and its status is the recipe's.
run: $(STAMP) $(PLUGIN)
	@echo "API:    http://127.0.0.1:$(API_PORT)/docs"
	@echo "Viewer: http://127.0.0.1:$(VIEWER_PORT)"
	@$(BIN)/insect-gait api --host 127.0.0.1 --port $(API_PORT) & api=$$!; \
	$(BIN)/insect-gait viewer --host 127.0.0.1 --port $(VIEWER_PORT) & viewer=$$!; \
	stop() { trap '' INT TERM; kill -TERM $$api $$viewer 2>/dev/null; wait 2>/dev/null; }; \
	trap 'stop; exit 0' INT TERM; \
	wait -n; status=$$?; stop; exit $$status

test: $(STAMP) $(PLUGIN)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/pytest

lint: $(STAMP)
	$(BIN)/ruff check . && $(BIN)/ruff format --check .

typecheck: $(STAMP)
	$(BIN)/mypy

bench: $(STAMP) $(PLUGIN)
	$(BIN)/insect-gait bench

# Refresh the README's screenshot (make test writes it to out/ only, leaving the tree clean).
screenshot: $(STAMP) $(PLUGIN)
	CI=true $(BIN)/pytest -q tests/web/test_viewer_browser.py -k renders
	cp out/viewer.png docs/figures/viewer.png

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache $(PLUGIN)
