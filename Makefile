# The two commands of the README: `make run` and `make test`. Each sets up what it needs
# from nothing (a virtualenv in .venv, pinned Python and npm packages, the built phone app,
# Debian's Chromium for the browser tests, Debian's PostgreSQL server and nginx for the
# replica and cluster tests) and is safe to run again.

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

.PHONY: run run-cluster test lint typecheck frontend-test browser postgres nginx bench bench-api bench-camera bench-load demo clean

run: $(INSTALLED) $(APP)
	$(BIN)/python -m backend

# The production topology on this machine: nginx (HTTPS) -> 2 replicas -> PostgreSQL
# (deploy/cluster.py; python -m deploy.cluster --help for its options). Ctrl+C stops it.
run-cluster: $(INSTALLED) $(APP) postgres nginx
	$(BIN)/python -m deploy.cluster $(ARGS)

test: $(INSTALLED) lint typecheck frontend-test $(APP) browser postgres nginx
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
# on a loopback port (deploy/postgres.py); the package's own cluster is not used.
postgres:
	@ls /usr/lib/postgresql/*/bin/postgres >/dev/null 2>&1 || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq postgresql )

# Debian's nginx, which make run-cluster, the cluster tests and the load benchmark run as a
# plain process with deploy/nginx.conf; the package's own service is not used.
nginx:
	@command -v nginx >/dev/null || test -x /usr/sbin/nginx || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq nginx )

bench: $(INSTALLED)
	$(BIN)/python benchmarks/solver.py

bench-api: $(INSTALLED)
	$(BIN)/python benchmarks/api.py

bench-camera: $(INSTALLED)
	$(BIN)/python benchmarks/camera_checks.py

bench-load: $(INSTALLED) $(APP) postgres nginx
	$(BIN)/python benchmarks/load.py

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
