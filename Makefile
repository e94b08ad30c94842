# Every target builds its own virtual environment first, so a fresh machine with only
# Python 3 and make is enough.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp
PIP    := $(BIN)/python -m pip --disable-pip-version-check -q
# The Python files of the docs (its Markdown pages are left to the writers: they align comments).
DOCS_PY := docs/conf.py docs/_ext docs/gallery docs/validation

.PHONY: install demo test bench lint docs clean

install: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip
	$(PIP) install -e '.[test,dev,docs,maps,afm,excel,peers]'
	@# orix (a test peer) compiles numba functions into a cache on first import: once here, in
	@# one process, rather than in a test worker (a minute of CPU) or in two at once.
	$(BIN)/python -c "import orix.crystal_map, orix.io, orix.plot"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/contactres demo --out contactres-demo

# The whole suite on every core (pytest-xdist). A test file runs on one worker (loadfile): its
# module fixtures are computed once, as in a serial run, and the memory-heavy tests of a file never
# run side by side. One BLAS thread per worker: more only oversubscribe the cores and spin
# (measured under load: the quartz static-limit test in tests/dynamic takes 4 s of CPU with one
# thread, 16-22 s with two). Bytecode is cached even where PYTHONDONTWRITEBYTECODE is set: without
# it each worker rewrote the asserts of every test file on each run (7 s of CPU each) and every
# command the tests start in a subprocess compiled the package again.
test: $(STAMP)
	PYTHONDONTWRITEBYTECODE= OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 \
		$(BIN)/python -m pytest -q -n auto --dist loadfile

# Every benchmarks/bench_*.py, even after a failure; ends with a one-line verdict and fails if
# any target was missed. Bytecode cached as for the tests: an installed package has its modules
# compiled (pip compiles a wheel's on install), so a run that compiled them again in each
# process timed what no user pays (~0.1 s a process for the modules qcm analyze imports).
bench: $(STAMP)
	@PYTHONDONTWRITEBYTECODE= $(BIN)/python benchmarks/run_all.py

# The documentation site: docs/_build/html/index.html. Any Sphinx warning fails the build.
docs: $(STAMP)
	$(BIN)/python -m sphinx -b html -W --keep-going -q -d docs/_build/doctrees docs docs/_build/html
	@echo "docs: docs/_build/html/index.html"

# ruff, then mypy on src/contactres (its settings: [tool.mypy] in pyproject.toml).
lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks scripts $(DOCS_PY)
	$(BIN)/ruff format --check src tests benchmarks scripts $(DOCS_PY)
	$(BIN)/mypy

clean:
	rm -rf $(VENV) contactres-demo .pytest_cache .ruff_cache .mypy_cache docs/_build docs/_generated docs/generated
