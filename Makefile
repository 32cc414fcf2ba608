# The two commands of the README: `make run` and `make test`. Each sets up what it needs
# from nothing (a virtualenv in .venv, pinned Python and npm packages, the built phone app,
# Debian's Chromium for the browser tests, Debian's PostgreSQL server for the replica
# tests) and is safe to run again.

PYTHON ?= python3
NPM ?= npm
VENV := .venv
BIN := $(VENV)/bin
INSTALLED := $(VENV)/.installed
FRONTEND := frontend
NODE_MODULES := $(FRONTEND)/node_modules/.installed
APP := $(FRONTEND)/dist/index.html
APP_SOURCES := $(shell find $(FRONTEND)/src $(FRONTEND)/public -type f 2>/dev/null) \
	$(wildcard $(FRONTEND)/index.html $(FRONTEND)/vite.config.ts $(FRONTEND)/tsconfig*.json)
# Root needs no sudo (CI, containers); anyone else gets asked once.
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)

.PHONY: run test lint typecheck frontend-test browser postgres bench bench-api bench-camera bench-load bench-suggest demo clean

run: $(INSTALLED) $(APP)
	$(BIN)/python -m backend

test: $(INSTALLED) lint typecheck frontend-test $(APP) browser postgres
	$(BIN)/python -m pytest

lint: $(INSTALLED)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

typecheck: $(INSTALLED)
	$(BIN)/mypy

frontend-test: $(NODE_MODULES)
	cd $(FRONTEND) && $(NPM) run typecheck && $(NPM) test

# Debian's Chromium, which the end-to-end tests drive (Playwright's own download fails here).
browser:
	@command -v chromium >/dev/null || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq chromium )

# Debian's PostgreSQL server binaries: the tests start their own throwaway server from them
# on a loopback port (tests/postgres.py); the package's own cluster is not used.
postgres:
	@ls /usr/lib/postgresql/*/bin/postgres >/dev/null 2>&1 || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq postgresql )

bench: $(INSTALLED)
	$(BIN)/python benchmarks/solver.py

bench-api: $(INSTALLED)
	$(BIN)/python benchmarks/api.py

bench-camera: $(INSTALLED)
	$(BIN)/python benchmarks/camera_checks.py

bench-load: $(INSTALLED)
	$(BIN)/python benchmarks/load.py --workers 2

bench-suggest: $(INSTALLED)
	$(BIN)/python benchmarks/suggestions.py

demo: $(INSTALLED)
	$(BIN)/python -m testbed.demo

# The .pth file puts the repository root on the virtualenv's path, for what runs here but
# never ships: testbed/, the scenes the tests, benchmarks and demo share.
$(INSTALLED): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	$(BIN)/python -c "import pathlib, site; pathlib.Path(site.getsitepackages()[0], 'buddy-search-root.pth').write_text(str(pathlib.Path.cwd()) + '\\n')"
	touch $(INSTALLED)

$(NODE_MODULES): $(FRONTEND)/package.json $(FRONTEND)/package-lock.json
	cd $(FRONTEND) && $(NPM) ci --no-audit --no-fund
	touch $(NODE_MODULES)

$(APP): $(NODE_MODULES) $(APP_SOURCES)
	cd $(FRONTEND) && $(NPM) run build

clean:
	rm -rf $(VENV) var artifacts .pytest_cache .ruff_cache .mypy_cache .hypothesis \
		$(FRONTEND)/node_modules $(FRONTEND)/dist
