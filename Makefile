# resal: `make all` rebuilds every table and figure; `make test` sets itself up and runs the suite.
PYTHON ?= python3
SHELL  := /bin/bash
# pipefail: a failing pip fails the recipe, though its output is filtered
.SHELLFLAGS := -o pipefail -c
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
LOCK   := requirements.lock
# make test runs the suite on one pytest-xdist worker per core, each test file whole on one worker (its module
# fixtures computed once); TEST_WORKERS=0 runs it in this process
TEST_WORKERS ?= auto
# pip-tools for `make lock`, in a virtualenv of its own (inside .venv) so that it adds nothing to the tested one
LOCKTOOLS := $(VENV)/lock-tools
PIPTOOLS  := pip-tools==7.6.2

.PHONY: setup lock all test lint bench stress golden coverage clean

# `make setup` always reinstalls (what the lock check asks for when .venv drifted); the other targets set up only
# when requirements.lock or pyproject.toml changed since the last setup
setup:
	@rm -f $(STAMP)
	@$(MAKE) --no-print-directory $(STAMP)

# The locked versions, every file's hash checked (requirements.lock: runtime and test dependencies, the build
# backend included), then resal itself, editable, no dependency resolved, built by the locked setuptools.
$(STAMP): pyproject.toml $(LOCK)
	@test -x $(BIN)/python || { echo "creating the virtual environment $(VENV) (first run only)"; \
	  $(PYTHON) -m venv $(VENV); }
	@echo "installing the $$(grep -c '^[a-zA-Z]' $(LOCK)) locked dependencies of $(LOCK) into $(VENV)" \
	  "(a first run downloads them: a minute or two; later runs only when the lock changes)"
	$(BIN)/python -m pip install --progress-bar on --disable-pip-version-check --require-hashes -r $(LOCK) \
	  | { grep -v '^Requirement already satisfied' || true; }
	$(BIN)/python -m pip install -q --no-deps --no-build-isolation -e .
	@touch $(STAMP)

# Rewrites requirements.lock from pyproject.toml's ranges, each pin the version installed in .venv today (its
# `pip freeze` as constraints: nothing moves that you did not move), with the hashes of every file of that version.
# To move a version: `.venv/bin/pip install -U NAME` (or edit pyproject.toml's range), `make lock`, then run the
# suite (`make test`) and the golden check (`make golden`, then `git diff tests/golden`: any number that moved must
# be understood) before committing the lock: it records what the tests and the goldens were made with.
lock:
	@test -x $(BIN)/python || { echo "no $(VENV): run make setup first" >&2; exit 2; }
	@test -x $(LOCKTOOLS)/bin/pip-compile || { $(BIN)/python -m venv $(LOCKTOOLS) \
	  && $(LOCKTOOLS)/bin/python -m pip install -q '$(PIPTOOLS)'; }
	$(BIN)/python -m pip freeze --all --exclude-editable | grep -v '^pip==' > $(VENV)/installed.txt
	CUSTOM_COMPILE_COMMAND="make lock" $(LOCKTOOLS)/bin/pip-compile -q --extra test --generate-hashes \
	  --allow-unsafe --strip-extras --no-emit-index-url --no-emit-find-links --no-emit-trusted-host \
	  -c $(VENV)/installed.txt -o $(LOCK) pyproject.toml

all: $(STAMP)
	$(BIN)/resal reproduce --all

# the lock check first: one line, exit 2, when .venv's versions are not requirements.lock's
# Python's bytecode cache on for the suite (PYTHONDONTWRITEBYTECODE, set in some containers and CI images, unset
# for it): the suite starts hundreds of `resal` processes, and each would compile every module of resal again
# (0.2 s a process, 3 s a worker's collection); the caches go to the gitignored __pycache__ folders. OpenBLAS on
# one thread in each worker unless OPENBLAS_NUM_THREADS says otherwise (a worker per core already: more threads
# only contend); tests/test_golden_stability.py runs the goldens under the other threading and another kernel.
test: $(STAMP)
	@$(BIN)/python tests/lockcheck.py $(LOCK)
	$(BIN)/ruff check .
	env -u PYTHONDONTWRITEBYTECODE OPENBLAS_NUM_THREADS=$${OPENBLAS_NUM_THREADS:-1} \
	  $(BIN)/python -m pytest -n $(TEST_WORKERS) --dist loadfile

lint: $(STAMP)
	$(BIN)/ruff check .

bench: $(STAMP)
	$(BIN)/resal bench

stress: $(STAMP)
	$(BIN)/resal stress

# re-measure the coverage of every interval `resal fit` prints (about 30 min on two cores): fit/coverage.json
coverage: $(STAMP)
	$(BIN)/python -m reproductions.coverage

golden: $(STAMP)
	$(BIN)/python -m reproductions.golden

clean:
	rm -rf results build *.egg-info .pytest_cache .ruff_cache .hypothesis
