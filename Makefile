# The two quick-start commands: `make demo` (set up, run `robokit validate`) and
# `make test` (set up, run the whole test suite). Both create or reuse .venv and show
# pip's progress while installing (a cold install downloads about 1.5 GB of robot meshes).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PIP    := $(BIN)/python -m pip install --progress-bar on --disable-pip-version-check

.PHONY: demo test bench docs notebooks setup clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# One stamp per set of extras, so `make demo` installs only what robokit needs to run.
$(VENV)/.installed-%: pyproject.toml | $(BIN)/python
	@echo "installing robokit[$*] into $(VENV) ..."
	$(PIP) -e '.[$*]'
	touch $@

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	@echo "installing robokit into $(VENV) ..."
	$(PIP) -e .
	touch $@

setup: $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/robokit validate

test: $(VENV)/.installed-all,test,docs,bench
	$(BIN)/python -m pytest -n 2 -q

bench: $(VENV)/.installed-all,bench
	$(BIN)/python -m benchmarks

docs: $(VENV)/.installed-docs
	$(BIN)/mkdocs build --strict

# As root (containers, CI images) JupyterLab refuses to start without --allow-root.
notebooks: $(VENV)/.installed-notebooks
	$(BIN)/jupyter lab $$( [ "$$(id -u)" = 0 ] && echo --allow-root ) notebooks/

clean:
	rm -rf $(VENV) build site *.egg-info
