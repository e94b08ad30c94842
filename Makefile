# Every target builds its own virtual environment first, so a fresh machine with only
# Python 3 and make is enough.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp
PIP    := $(BIN)/python -m pip --disable-pip-version-check -q

.PHONY: install demo test bench lint clean

install: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip
	$(PIP) install -e '.[test,dev]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/contactres demo --out contactres-demo

test: $(STAMP)
	$(BIN)/python -m pytest -q

# Every benchmarks/bench_*.py, even after a failure; ends with a one-line verdict and fails if
# any target was missed.
bench: $(STAMP)
	@$(BIN)/python benchmarks/run_all.py

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks scripts
	$(BIN)/ruff format --check src tests benchmarks scripts

clean:
	rm -rf $(VENV) contactres-demo .pytest_cache .ruff_cache
