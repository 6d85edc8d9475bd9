# Two commands do all set-up on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
API_PORT ?= 8000
VIEWER_PORT ?= 8080

.PHONY: install run test lint typecheck bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[dev,cluster]'
	touch $(STAMP)

install: $(STAMP)

run: $(STAMP)
	@echo "API:    http://127.0.0.1:$(API_PORT)/docs"
	@echo "Viewer: http://127.0.0.1:$(VIEWER_PORT)"
	@trap 'kill 0' INT TERM EXIT; \
	$(BIN)/insect-gait api --host 127.0.0.1 --port $(API_PORT) & \
	$(BIN)/insect-gait viewer --host 127.0.0.1 --port $(VIEWER_PORT) & \
	wait

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/pytest

lint: $(STAMP)
	$(BIN)/ruff check . && $(BIN)/ruff format --check .

typecheck: $(STAMP)
	$(BIN)/mypy

bench: $(STAMP)
	$(BIN)/insect-gait bench

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache
