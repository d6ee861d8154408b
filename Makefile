# Two commands set up everything: `make run` and `make test`.
VENV ?= .venv
PYTHON ?= python3
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: run test bench clean screenshots

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

run: $(STAMP)
	$(VENV)/bin/tabletop run --config config.yaml $(ARGS)

# The suite runs in two worker processes (pytest-xdist), one per core of the target machine.
test: $(STAMP)
	$(PY) -m pytest -n 2

bench: $(STAMP)
	for b in bench/*.py; do echo "== $$b"; $(PY) $$b | tail -n 1; done

clean:
	rm -rf $(VENV) build *.egg-info

# README pictures, made by the installation itself (headless runs with snapshots).
screenshots: $(STAMP)
	$(PY) -m tabletop.screenshots --out docs/screenshots
