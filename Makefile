# The two commands of the README: `make run` and `make test`. Each sets up what it needs
# from nothing (a virtualenv in .venv, pinned Python and npm packages, the built phone app,
# Debian's Chromium and WebKitGTK for the browser tests, Debian's PostgreSQL server and nginx
# for the replica and cluster tests) and is safe to run again.

PYTHON ?= python3
NPM ?= npm
VENV := .venv
BIN := $(VENV)/bin
INSTALLED := $(VENV)/.installed
FRONTEND := frontend
NODE_MODULES := $(FRONTEND)/node_modules/.installed
APP := $(FRONTEND)/dist/index.html
APP_SOURCES := $(shell find $(FRONTEND)/src $(FRONTEND)/public -type f 2>/dev/null) \
	$(wildcard $(FRONTEND)/index.html $(FRONTEND)/vite.config.ts $(FRONTEND)/tsconfig*.json) \
	backend/limits.json shared_solver/drawing/palette.json
# The API's TypeScript types, generated from the app's own OpenAPI schema (what it is made of:
# the backend's and the solver's models). Committed. The build renews them first, unless
# RENEW_API_TYPES=no: `make test` builds with the committed copy while it checks that copy
# beside the build (tests/test_api_types.py), so a stale one fails instead of being renewed
# on the way.
API_TYPES := $(FRONTEND)/src/generated/openapi.ts
RENEW_API_TYPES ?= yes
API_SOURCES := $(shell find backend shared_solver -name '*.py' -o -name '*.json')
# uv, pinned: it installs the lock file (make test, make run) and writes it (make lock).
UV_VERSION := 0.13.9
# Bytecode caches are written even where the environment turns them off
# (PYTHONDONTWRITEBYTECODE): pytest then rewrites the tests' asserts once rather than in
# every process of every run (collecting the solver's tests took 5.7 s, then 2.6 s).
unexport PYTHONDONTWRITEBYTECODE
# Root needs no sudo (CI, containers); anyone else gets asked once.
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)

.PHONY: run run-cluster test suite suite-working suite-waiting system-packages test-solver test-backend test-app lint typecheck api-types-check frontend-test screenshots browser webkit postgres nginx bench bench-api bench-camera bench-reanchor bench-taps bench-load bench-suggest bench-network bench-slow-phone bench-real bench-all docs-figures demo lock clean

run: $(INSTALLED) $(APP)
	$(BIN)/python -m backend

# The production topology on this machine: nginx (HTTPS) -> 2 replicas -> PostgreSQL
# (deploy/cluster.py; python -m deploy.cluster --help for its options). Ctrl+C stops it.
run-cluster: $(INSTALLED) $(APP) postgres nginx
	$(BIN)/python -m deploy.cluster $(ARGS)

# The whole suite on both cores (pytest-xdist: each worker starts its own servers and browsers
# on free ports, so two browser tests may run at once). Scheduling: --dist worksteal, since
# the default hands each worker long runs of tests up front and cannot take them back: one
# worker then ran the browser tests alone for the last 400 s (1212 s in all, against 851 s
# with worksteal, 2308 tests on a quiet machine; three workers: 958 s). The set-up runs side
# by side where it can: the Python and npm packages and the Debian ones (those one at a time:
# apt holds a lock); the committed API types are checked beside the build, which uses them
# as they are (15 s and 19 s one after the other); then the checks (lint, mypy, the app's
# types and unit tests) run beside the suite, in the time its browsers and servers leave the
# cores idle.
test:
	$(MAKE) --no-print-directory -j3 $(INSTALLED) $(NODE_MODULES) system-packages
	$(MAKE) --no-print-directory -j2 api-types-check $(APP) RENEW_API_TYPES=no
	$(MAKE) --no-print-directory -j4 suite lint typecheck frontend-test RENEW_API_TYPES=no

# The pytest suite but tests/test_api_types.py, which api-types-check ran beside the build
# (make test runs this beside the checks, once the app is built). The project's own
# modules are compiled first, for the same reason as the packages: the suite starts many
# Python processes (a server for each browser test, replicas, benchmarks). The tests marked
# `waits` (a phone cut off for 30 s, a server restarted, a throttled link: about 280 s of
# worker time on 2 min of CPU) run in a lane of their own beside the two workers, which
# frees a worker while they wait (docs/browsers.md: little saved, the suite is CPU-bound).
SUITE = $(BIN)/python -m pytest -q --ignore=tests/test_api_types.py

suite:
	$(BIN)/python -m compileall -q -j 2 backend shared_solver deploy testbed benchmarks docsgen
	$(MAKE) --no-print-directory -j2 suite-working suite-waiting

suite-working:
	$(SUITE) -n 2 --dist worksteal -m "not waits"

suite-waiting:
	$(SUITE) -p no:cacheprovider -m waits

system-packages:
	@$(MAKE) --no-print-directory browser
	@$(MAKE) --no-print-directory webkit
	@$(MAKE) --no-print-directory postgres
	@$(MAKE) --no-print-directory nginx

# Faster subsets for a change to one layer; `make test` stays the whole suite.
# The solver: its lint, types and tests on both cores (pytest-xdist).
test-solver: $(INSTALLED)
	$(BIN)/ruff check shared_solver tests/solver
	$(BIN)/mypy shared_solver tests/solver
	$(BIN)/python -m pytest -q -n 2 --dist worksteal tests/solver

# The service: its tests on SQLite and PostgreSQL, the cluster behind nginx included.
test-backend: $(INSTALLED) postgres nginx
	$(BIN)/ruff check backend deploy tests/backend
	$(BIN)/mypy backend deploy tests/backend
	$(BIN)/mypy tests/backend/conftest.py
	$(BIN)/python -m pytest -q -n 2 --dist worksteal tests/backend tests/test_docs_generated.py

# The phone app: its types and unit tests, the build, and the two phones in both browsers.
test-app: $(INSTALLED) api-types-check frontend-test $(APP) browser webkit
	$(BIN)/python -m pytest -q tests/e2e

api-types-check: $(INSTALLED) $(NODE_MODULES)
	$(BIN)/python -m pytest -q tests/test_api_types.py

lint: $(INSTALLED)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

# pyproject's files, then the two conftest.py it leaves out: pytest imports each as the
# module conftest, and mypy checks one module of a name per run.
typecheck: $(INSTALLED)
	$(BIN)/mypy
	$(BIN)/mypy tests/conftest.py
	$(BIN)/mypy tests/backend/conftest.py

# The app's unit tests. Its types are checked by its build (`npm run build` runs tsc first),
# which every source change makes again: checking them here too cost make test 15 s of CPU.
frontend-test: $(NODE_MODULES) $(APP)
	cd $(FRONTEND) && $(NPM) test

# Debian's Chromium, which the end-to-end tests drive (Playwright's own download fails here).
browser:
	@command -v chromium >/dev/null || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq chromium )

# Debian's WebKitGTK for the WebKit end-to-end tests (testbed/browser/webkit_phone.py):
# WebKitWebDriver (webkit2gtk-driver, which brings MiniBrowser) and the virtual X server
# the browser draws on (xvfb).
webkit:
	@( command -v WebKitWebDriver && command -v Xvfb ) >/dev/null || ( $(SUDO) apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq webkit2gtk-driver xvfb )

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

# The README's screenshots: the two-phone, layout and guidance browser tests take them
# (artifacts/screenshots/), then they are halved and saved as JPEG in docs/screenshots/.
screenshots: $(INSTALLED) $(APP) browser
	rm -rf artifacts/screenshots
	$(BIN)/python -m pytest -q tests/e2e/test_two_phones.py tests/e2e/test_layout.py tests/e2e/test_guided_tapping.py \
		tests/e2e/test_hall_in_app.py tests/e2e/test_live_view.py tests/e2e/test_live_view_hall.py \
		tests/e2e/test_languages.py
	$(BIN)/python -m testbed.screenshots artifacts/screenshots docs/screenshots

bench: $(INSTALLED)
	$(BIN)/python benchmarks/solver.py

bench-api: $(INSTALLED)
	$(BIN)/python benchmarks/api.py

bench-camera: $(INSTALLED)
	$(BIN)/python benchmarks/camera_checks.py

# The live view's anchor: frames matched to the photo on rendered halls, and the drift
# (docs/reanchor-benchmark.md).
bench-reanchor: $(INSTALLED)
	$(BIN)/python benchmarks/reanchor.py

# The taps' precision, held out: two phones in Chromium on a live server (docs/tap-precision.md).
bench-taps: $(INSTALLED) $(APP) browser
	$(BIN)/python benchmarks/taps.py

bench-load: $(INSTALLED) $(APP) postgres nginx
	$(BIN)/python benchmarks/load.py

bench-suggest: $(INSTALLED)
	$(BIN)/python benchmarks/suggestions.py

# The solver on real calibrated photographs (tests/data/real_cameras/): a few minutes.
bench-real: $(INSTALLED)
	$(BIN)/python benchmarks/real_cameras.py $(ARGS)

# The app on a venue's network: two phones in Chromium, loopback and an emulated congested
# venue, in one run (docs/network-benchmark.md).
bench-network: $(INSTALLED) $(APP) browser
	$(BIN)/python benchmarks/network.py

# The app on a slow phone: one phone in Chromium with its CPU throttled 4x, against the same
# runs unthrottled, in one run: a photo tappable, a tap painted, the JavaScript fetched
# (docs/slow-phone.md).
bench-slow-phone: $(INSTALLED) $(APP) browser
	$(BIN)/python benchmarks/slow_phone.py

# Every benchmark above at one commit (a tree with uncommitted changes is refused), each
# writing its report in docs/, then the figures of the README and docs/ from the reports,
# failed targets as FAIL (docsgen/figures.py). Long (each report gives its run's time): on a
# quiet machine.
bench-all: $(INSTALLED)
	$(BIN)/python -m docsgen.figures --run

# Only the figures of the README and docs/, from the reports already in docs/
# (tests/test_docs_generated.py fails when they differ).
docs-figures: $(INSTALLED)
	$(BIN)/python -m docsgen.figures

demo: $(INSTALLED)
	$(BIN)/python -m testbed.demo

# Every package from the lock file, hashes checked. The app is not installed: the .pth file
# puts the repository root on the virtualenv's path (backend/, shared_solver/, and testbed/,
# the scenes the tests, benchmarks and demo share).
# uv installs them (the same lock, hashes required): 10 s from nothing, where pip took 53.
# Compiled to bytecode as they are installed: uv writes none by default, and where Python is
# told not to write any (PYTHONDONTWRITEBYTECODE, set on this machine), every process would
# compile its imports again: a server started in 3.4 s instead of 1.8.
$(INSTALLED): pyproject.toml requirements/test.txt
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet uv==$(UV_VERSION)
	$(BIN)/uv pip install --quiet --require-hashes --no-deps --compile-bytecode \
		-r requirements/test.txt --python $(BIN)/python
	$(BIN)/python -c "import pathlib, site; pathlib.Path(site.getsitepackages()[0], 'buddy-search-root.pth').write_text(str(pathlib.Path.cwd()) + '\\n')"
	touch $(INSTALLED)

$(NODE_MODULES): $(FRONTEND)/package.json $(FRONTEND)/package-lock.json
	cd $(FRONTEND) && $(NPM) ci --no-audit --no-fund
	touch $(NODE_MODULES)

ifneq ($(RENEW_API_TYPES),no)
$(API_TYPES): $(API_SOURCES) | $(INSTALLED) $(NODE_MODULES)
	$(BIN)/python -m backend.openapi | (cd $(FRONTEND) && $(NPM) run --silent api-types)
endif

$(APP): $(NODE_MODULES) $(APP_SOURCES) $(API_TYPES)
	cd $(FRONTEND) && $(NPM) run build

# The Python lock files, from pyproject.toml: every transitive package with its hashes, for
# every platform (requirements/test.txt for make, runtime.txt, its subset, for the image).
# Run after changing a dependency; uv, pinned, lives in a throwaway virtualenv.
lock:
	rm -rf .venv-lock && $(PYTHON) -m venv .venv-lock
	.venv-lock/bin/python -m pip install --quiet uv==$(UV_VERSION)
	.venv-lock/bin/uv pip compile pyproject.toml --extra test --generate-hashes --universal \
		--python-version 3.11 --quiet -o requirements/test.txt
	.venv-lock/bin/uv pip compile pyproject.toml --generate-hashes --universal \
		--python-version 3.11 --quiet -c requirements/test.txt -o requirements/runtime.txt
	rm -rf .venv-lock

clean:
	rm -rf $(VENV) var artifacts .pytest_cache .ruff_cache .mypy_cache .hypothesis \
		$(FRONTEND)/node_modules $(FRONTEND)/dist
