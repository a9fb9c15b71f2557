# seapass: everything goes through a local virtual environment in .venv
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= results
# test processes (pytest-xdist): one per core on the 2-core CI machine; TEST_WORKERS=0 runs serially
TEST_WORKERS ?= 2

.PHONY: run test lint typecheck bench bench-scale docs install browser clean

$(STAMP): pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else "seapass needs Python >= 3.11")'
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[test,dask,mujoco,docs,explore]"
	@touch $(STAMP)

install: $(STAMP)

## main job: rebuild the paper's tables, figures and report
run: $(STAMP)
	$(BIN)/seapass reproduce --out $(OUT)

## whole test suite: lint, format, types, tests
test: $(STAMP) browser lint typecheck
	$(BIN)/python -m pytest -p no:cacheprovider -n $(TEST_WORKERS)

lint: $(STAMP)
	$(BIN)/ruff check src tests $(wildcard benchmarks)
	$(BIN)/ruff format --check src tests $(wildcard benchmarks)

typecheck: $(STAMP)
	$(BIN)/mypy

# headless Chromium for the report test (Debian's package; needs root and apt)
browser:
	@command -v chromium >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing Debian's chromium for the report test"; \
	    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null) \
	      || echo "warning: could not install chromium; the browser test will be skipped"; \
	  else echo "note: chromium not found and cannot be installed here; the browser test will be skipped"; fi; }

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py

## Dask scale-out table (LocalCluster of 1, 2, 4, ... workers up to the cores) into docs/benchmarks.md
bench-scale: $(STAMP)
	$(BIN)/python benchmarks/bench_scaling.py --write-docs

docs: $(STAMP)
	$(BIN)/mkdocs build --strict --site-dir site

clean:
	rm -rf $(VENV) site .pytest_cache .mypy_cache .ruff_cache
