# The two commands a new user needs: `make run` and `make test`. Both install what they need.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
NPM_STAMP := node_modules/.installed
STATIC := backend/servodesk/static/index.html
FRONTEND_SOURCES := $(shell find frontend -type f -not -path '*/node_modules/*' 2>/dev/null) package.json
CHROMIUM := /usr/bin/chromium
# root installs Debian packages directly; anyone else through sudo
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: run test install lint typecheck pytest pytest-pool pytest-fuzz pytest-serial frontend \
	frontend-check api-check system-deps bench sim clean \
	pytest-realtime pytest-browser

# uv installs the pinned ranges of pyproject.toml into the venv (the same resolution as pip, in
# seconds instead of most of a minute); uv itself comes from PyPI into the venv first.
$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --disable-pip-version-check 'uv>=0.13,<0.14'
	$(BIN)/uv pip install --quiet --python $(BIN)/python -e '.[dev]'
	touch $(STAMP)

$(NPM_STAMP): package.json package-lock.json
	npm ci --no-audit --no-fund --loglevel=error
	touch $(NPM_STAMP)

$(STATIC): $(NPM_STAMP) $(FRONTEND_SOURCES)
	npm run build

install: $(STAMP) $(NPM_STAMP)

frontend: install $(STATIC)

# Debian's Chromium drives the end-to-end tests (Playwright never downloads a browser here);
# a CJK font renders the MDi's Chinese parameter names in its screenshots; tshark is the
# independent CANopen decoder the log tests compare against (wireshark-common asks a debconf
# question, hence noninteractive). WeasyPrint lays out the commissioning report's PDF with pango
# (the same font drives its Chinese names); poppler-utils (pdftotext, pdffonts, pdftoppm) is how
# the report tests read that PDF back.
system-deps:
	@test -x $(CHROMIUM) && fc-list | grep -qi microhei && command -v tshark >/dev/null && \
		command -v pdftotext >/dev/null && ldconfig -p | grep -q libpangoft2-1.0 || { \
		$(SUDO) apt-get update -qq && \
		$(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
			chromium fonts-liberation fonts-wqy-microhei tshark \
			libpango-1.0-0 libpangoft2-1.0-0 poppler-utils; }

run: frontend system-deps
	$(BIN)/servodesk serve --sim --bind 127.0.0.1 --port 8000

sim: install
	$(BIN)/servodesk-sim --node 1:mdi-s1c --node 2:kinco --node 3:cia402 --serve 127.0.0.1:29536

lint: install
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports  # the layers and import rules in pyproject.toml [tool.importlinter]
	npm run --silent lint
	npm run --silent format:check

typecheck: install
	$(BIN)/mypy
	npm run --silent typecheck

# The TypeScript client is generated from the backend's OpenAPI schema and must match it.
api-check: install
	$(BIN)/python -m servodesk.openapi > frontend/openapi.json
	npm run --silent gen:api
	git diff --exit-code -- frontend/openapi.json frontend/src/api/schema.d.ts || \
		{ echo "frontend/openapi.json or schema.d.ts is stale: commit the regenerated files"; exit 1; }

frontend-check: install
	npm run --silent test

# The Python tests. The pool: pytest-xdist, a worker per core, a test file per worker, for the
# tests that keep no real time of their own; beside it, the schema fuzzing in a process of its
# own (under xdist, schemathesis would run its operations as one item). Then, alone on the
# machine, the `realtime` tests (they keep millisecond time in the test process) and the
# browser tests (a page, a server and the drives' clock in three processes; two files at a
# time, beside two busy processes, starved the app's heartbeat). tests/conftest.py says which
# test is which.
pytest: install system-deps $(STATIC)
	$(MAKE) --no-print-directory -j2 --output-sync=target pytest-pool pytest-fuzz
	$(MAKE) --no-print-directory pytest-serial

# One worker more than cores: a pool test waits on its simulated drives much of its time.
POOL_WORKERS ?= $(shell echo $$(( $$(nproc) + 1 )))

pytest-pool: install system-deps $(STATIC)
	$(BIN)/pytest -n $(POOL_WORKERS) --dist loadfile -m "not serial and not fuzz"

pytest-fuzz: install
	$(BIN)/pytest -p no:xdist -m fuzz tests/backend/test_schemathesis.py

# one after the other even under `make -j`: each needs the machine to itself
pytest-serial: install
	$(MAKE) --no-print-directory pytest-realtime
	$(MAKE) --no-print-directory pytest-browser

pytest-realtime: install
	$(BIN)/pytest -p no:xdist -m "serial and not browser"

pytest-browser: install system-deps $(STATIC)
	$(BIN)/pytest -p no:xdist tests/e2e

# The Python and npm installs (and the page's build) side by side; then api-check, alone: it
# rewrites the generated client that the type check reads. Then the checks (eslint, tsc, mypy,
# Vitest: each one core at most) run beside the pool and the fuzzing, whose tests spend much of
# their time waiting on the simulated drives: together they keep both cores busy. Then the
# serial tests: the realtime ones alone, then the browser tests.
test:
	$(MAKE) --no-print-directory -j3 --output-sync=target install system-deps $(STATIC)
	$(MAKE) --no-print-directory api-check
	$(MAKE) --no-print-directory -j5 --output-sync=target \
		lint typecheck frontend-check pytest-pool pytest-fuzz
	$(MAKE) --no-print-directory pytest-serial

bench: install
	$(BIN)/python bench/sim_realtime.py
	$(BIN)/python bench/cli_startup.py
	$(BIN)/python bench/sdo_overhead.py
	$(BIN)/python bench/od_upload.py
	$(BIN)/python bench/log_decode.py
	$(BIN)/python bench/jog_stop.py
	$(BIN)/python bench/emcy_storm.py
	$(BIN)/python bench/scope_pipeline.py
	$(BIN)/python bench/sim_under_load.py
	$(BIN)/python bench/soak.py
	$(BIN)/python bench/realtime_under_load.py
	$(BIN)/python bench/hostile_inputs.py

clean:
	rm -rf $(VENV) node_modules backend/servodesk/static .mypy_cache .pytest_cache .ruff_cache \
		.import_linter_cache .grimp_cache
