# The two commands of the README: `make run` and `make test`. Each sets up what it needs
# from nothing (a virtualenv in .venv, pinned packages) and is safe to run again.

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
INSTALLED := $(VENV)/.installed

.PHONY: run test lint typecheck bench bench-api demo clean

run: $(INSTALLED)
	$(BIN)/python -m backend

test: $(INSTALLED) lint typecheck
	$(BIN)/python -m pytest

lint: $(INSTALLED)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

typecheck: $(INSTALLED)
	$(BIN)/mypy

bench: $(INSTALLED)
	$(BIN)/python benchmarks/solver.py

bench-api: $(INSTALLED)
	$(BIN)/python benchmarks/api.py

demo: $(INSTALLED)
	$(BIN)/python -m shared_solver

$(INSTALLED): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(INSTALLED)

clean:
	rm -rf $(VENV) var artifacts .pytest_cache .ruff_cache .mypy_cache .hypothesis
