# Two commands on a fresh machine:
#   make demo   -- create .venv, install workspace_sym, run the demo report
#   make test   -- create .venv, install with the test extra, run the whole suite
#   make test-fast -- the same less the tests marked slow, for the edit loop
#   make notebooks -- execute the notebooks and export them to build/notebooks/*.html
#   make docs  -- build the documentation site (API reference and guides) into build/docs/html
PYTHON ?= python3

# Every Python process the recipes start (pytest's workers, the CLI and notebook kernels the tests start, Dask's
# workers) keeps the bytecode of what it imports, in __pycache__ beside the sources (the venv's, the package's; git
# ignores them).  A machine that sets PYTHONDONTWRITEBYTECODE (as CI images often do) would otherwise compile SymPy
# and the rest from source in each of those processes: 2.3 s for `import sympy` against 0.6 s, and the suite's CPU
# time 959 s against 691 s (BENCHMARKS.md, "The test suite").
unexport PYTHONDONTWRITEBYTECODE
VENV ?= .venv
BIN := $(VENV)/bin
OUT ?= demo-report

.PHONY: demo test test-fast explore lint bench clean notebooks docs

# The venv gets uv (from PyPI, like everything else) and uv installs the package and its extras into it: the
# same packages as pip's, resolved and unpacked in parallel (the test extra in about 10 s where pip took about
# 90 s; BENCHMARKS.md, "The test suite").  pip stays in the venv for users who call it.
INSTALL := $(BIN)/uv pip install --quiet --python $(BIN)/python

# The venv is made without pip (ensurepip alone took 3 s of the suite's wall time) and uv is put in it by the
# interpreter's own pip (`pip --python`, pip 22.3 or later; else ensurepip, as before); uv then adds pip to the venv
# for users who call it.
$(BIN)/python:
	$(PYTHON) -m venv --without-pip $(VENV)

$(BIN)/uv: | $(BIN)/python
	$(PYTHON) -m pip --python $(BIN)/python install --quiet uv || \
		{ $(BIN)/python -m ensurepip --default-pip >/dev/null && $(BIN)/python -m pip install --quiet uv; }
	$(BIN)/uv pip install --quiet --python $(BIN)/python pip

$(VENV)/.installed: pyproject.toml | $(BIN)/uv
	$(INSTALL) -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/uv
	$(INSTALL) -e ".[test]"
	touch $@ $(VENV)/.installed

$(VENV)/.installed-docs: pyproject.toml | $(BIN)/uv
	$(INSTALL) -e ".[docs]"
	touch $@ $(VENV)/.installed

$(VENV)/.installed-bench: pyproject.toml | $(BIN)/uv
	$(INSTALL) -e ".[test,bench]"
	touch $@ $(VENV)/.installed $(VENV)/.installed-test

demo: $(VENV)/.installed
	$(BIN)/workspace-sym demo --out $(OUT)

# The suite runs its test files on every core (pytest-xdist, at most 4 workers; a file stays on one worker so its
# module fixtures are built once, the longest files first: conftest.py).  Extra pytest options:
# make test PYTEST_ARGS="--basetemp=/tmp/x/pytest-0"
XDIST := --numprocesses=auto --maxprocesses=4 --dist=loadfile --no-loadscope-reorder
test: $(VENV)/.installed-test lint
	$(BIN)/python -m pytest $(XDIST) $(PYTEST_ARGS)

# The edit loop: the suite less the tests marked slow (the industrial arms, the notebooks, mypy, the longest
# derivations and pavings that no property test draws), on the same workers.  `make test` stays the whole suite:
# run it before committing.
test-fast: $(VENV)/.installed-test lint
	$(BIN)/python -m pytest $(XDIST) -m "not slow" $(PYTEST_ARGS)

# Property tests with fresh random examples (the suite's own are the same on every run): a hunt, not a gate.
explore: $(VENV)/.installed-test
	HYPOTHESIS_PROFILE=explore $(BIN)/python -m pytest $(XDIST) -m "not slow" $(PYTEST_ARGS) \
		$$(grep -rl "@given" tests)

lint: $(VENV)/.installed-test
	$(BIN)/ruff check .

bench: $(VENV)/.installed-bench
	for script in benchmarks/bench_*.py; do $(BIN)/python $$script || exit 1; done

# Execute every notebook and export it to build/notebooks/NAME.html.  Results are displayed as MathML, which the
# browser renders itself: the pages read correctly offline (nbconvert's MathJax script is then simply not loaded).
notebooks: $(VENV)/.installed-test
	$(BIN)/jupyter nbconvert --to html --execute --ExecutePreprocessor.timeout=600 \
		--output-dir build/notebooks notebooks/*.ipynb

# The documentation site: the API reference from the numpydoc docstrings (autodoc, autosummary) and the guides of
# docs/ and the README (MyST) and the notebooks (myst-nb), executed when their code changed since the last build
# (a jupyter-cache in build/docs/), warnings and failing cells as errors.  About 80 s on two cores with the
# notebooks executed, 35 s when they are cached; open build/docs/html/index.html.
docs: $(VENV)/.installed-docs
	$(BIN)/python -m sphinx -W --keep-going -b html docs/site build/docs/html

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info .pytest_cache .hypothesis docs/site/api/generated
