# resal: `make all` rebuilds every table and figure; `make test` sets itself up and runs the suite.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: setup all test lint bench stress golden clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q -e '.[test]'
	@touch $(STAMP)

all: $(STAMP)
	$(BIN)/resal reproduce --all

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest

lint: $(STAMP)
	$(BIN)/ruff check .

bench: $(STAMP)
	$(BIN)/resal bench

stress: $(STAMP)
	$(BIN)/resal stress

golden: $(STAMP)
	$(BIN)/python -m reproductions.golden

clean:
	rm -rf results build *.egg-info .pytest_cache .ruff_cache .hypothesis
