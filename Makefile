# The two quick-start commands: `make demo` (set up, run `robokit validate`) and
# `make test` (set up, run the whole test suite). One environment, .venv: robokit is installed
# into it once (editable) and again only when pyproject.toml changes; each extra a target needs is
# added next to it, once (.venv/.extra-NAME), without reinstalling robokit. The installer's progress
# shows: uv's when uv is on PATH (or named: `make test UV=/path/to/uv`), pip's otherwise (or with
# `make test UV=`). uv installs the same packages as pip (.ci/uv_pip.py hands it pip's configuration
# and pip's choice among indexes, and has it write the .pyc files pip writes), faster: `make test-env`
# in a fresh clone, caches empty, took 56 s with uv (54 s of CPU) against 93 s with pip (75 s of CPU)
# on 2 cores busy with other work (load average 3.3-4.3).
# Sizes (measured: pip download of the same requirements, Python 3.11, x86-64 Linux): the core
# install downloads about 325 MB and makes a 1.3 GB environment (most of it Pinocchio and the
# example-robot-data meshes); `make test` adds every extra: about 700 MB of downloads in all and a
# 2.7 GB environment (pybullet, from the test extra, is 100 MB and 290 MB of these).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
UV     ?= $(shell command -v uv 2>/dev/null)
ifeq ($(strip $(UV)),)
PIP    := $(BIN)/python -m pip install --progress-bar on --disable-pip-version-check
else
PIP    := $(BIN)/python .ci/uv_pip.py $(UV)
endif
# two make commands at once (`make docs` while `make test` runs) take turns at installing
LOCK   := $(shell command -v flock >/dev/null 2>&1 && echo flock $(VENV)/.pip-lock)
# `make test PYTEST_ARGS=tests/ik` runs part of the suite
PYTEST_ARGS ?=

.PHONY: demo test test-env bench docs notebooks setup clean
.PRECIOUS: $(VENV)/.extra-%

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(PIP) --quiet --upgrade pip

# robokit itself (the core install), editable
$(VENV)/.installed: pyproject.toml | $(BIN)/python
	@echo "installing robokit into $(VENV) ..."
	$(LOCK) $(PIP) -e .
	touch $@

# one extra's packages (with the core requirements, so the installer keeps robokit's pins), robokit untouched
$(VENV)/.extra-%: $(VENV)/.installed .ci/extra_requirements.py
	@echo "adding robokit's '$*' extra to $(VENV) ..."
	$(BIN)/python .ci/extra_requirements.py $* > $@.txt
	$(LOCK) $(PIP) -r $@.txt
	touch $@

setup: $(VENV)/.installed

# what `make test` needs installed (.ci/run times it apart from the tests)
test-env: $(VENV)/.extra-all $(VENV)/.extra-test $(VENV)/.extra-docs $(VENV)/.extra-bench

demo: $(VENV)/.installed
	$(BIN)/robokit validate

# First every kernel the tests run is compiled into numba's on-disk cache (or, when it is there
# already, loaded: seconds), one process per core, each compiling different kernels: the course
# kernels (what `python -m robokit.kernels` compiles) and the analytic-IK kernels, compiled by
# solving poses (.ci/warm_kernels.py); otherwise, on a cold cache, both pytest workers compile the
# same kernels at the same time, twice the CPU for nothing.
# Not -q: pytest-xdist then prints the number of tests collected ("2 workers [N items]") and
# pytest its closing count ("N passed, M skipped in T s"), after the 20 slowest tests (CI's budget is
# 20 minutes on 2 cores: the list says where its time goes).
test: test-env
	$(BIN)/python .ci/warm_kernels.py
	$(BIN)/python -m pytest -n 2 --durations=20 $(PYTEST_ARGS)

bench: $(VENV)/.extra-all $(VENV)/.extra-bench
	$(BIN)/python -m benchmarks

docs: $(VENV)/.extra-docs
	$(BIN)/mkdocs build --strict

# As root (containers, CI images) JupyterLab refuses to start without --allow-root.
notebooks: $(VENV)/.extra-notebooks
	$(BIN)/jupyter lab $$( [ "$$(id -u)" = 0 ] && echo --allow-root ) notebooks/

clean:
	rm -rf $(VENV) build site *.egg-info
