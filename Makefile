# robomill — every entry point a user needs. `make all` and `make test` work on a fresh clone.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.robomill-installed
JOBS ?= 2
SNAKEMAKE := $(BIN)/snakemake
CHAPTER ?=
# numba's compiled kernels: one cache per virtual environment (robomill.kernels), compiled at
# `make venv`, shared by the workflow's jobs, the tests and the benchmarks
export NUMBA_CACHE_DIR ?= $(abspath $(VENV))/numba-cache

.PHONY: all test test-fast test-cluster report bench plan-check learn-round lock lint fmt why explore kernel clean venv \
	notebooks

all: $(STAMP)
	$(SNAKEMAKE) -j$(JOBS) --rerun-incomplete all

venv: $(STAMP)

# (Re)create the environment when it is missing or environment.lock / pyproject.toml changed.
$(STAMP): environment.lock pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --disable-pip-version-check "$$(grep -E '^uv==' environment.lock | cut -d' ' -f1)"
	# bytecode compiled at install: imports stay fast even where PYTHONDONTWRITEBYTECODE is set
	$(BIN)/uv pip sync -q --compile-bytecode --python $(BIN)/python environment.lock
	$(BIN)/uv pip install -q --python $(BIN)/python --no-deps -e .
	# and robomill's own modules (an editable install leaves them as source; where
	# PYTHONDONTWRITEBYTECODE is set every process would compile them again)
	$(BIN)/python -m compileall -q src
	# and the numba kernels, once, into the environment's cache (robomill.kernels)
	$(BIN)/python -m robomill.kernels
	$(BIN)/python -m ipykernel install --sys-prefix --name robomill --display-name "robomill (.venv)" >/dev/null
	@touch $(STAMP)

kernel: $(STAMP)

# One BLAS/OpenMP thread in each test worker: the $(JOBS) workers already fill the cores, and a
# thread pool per worker only oversubscribes them (the unit tests on 2 cores: 2 min 18 s and
# 244 CPU s with the pools, 2 min 07 s and 221 CPU s without; Snakemake sets each job's own).
TEST_ENV = OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1

# Every test but the predict-then-cut ones (make plan-check) in one session on one worker per
# job slot (pytest-xdist, whole modules per worker): the end-to-end pipeline, browser and
# cluster tests and the installed wheel's (marker wheel: the wheel is built once, for both its
# tests) first, the unit tests last, filling both workers' ends (the tiny study and its plan
# are built once for both workers; the order is tests/conftest.py's). The same tests and
# assertions as one run.
test: $(STAMP)
	$(TEST_ENV) $(BIN)/python -m pytest -q -n $(JOBS) --dist loadscope --no-loadscope-reorder --durations=10 -m "not predict_cut"

test-fast: $(STAMP)
	$(TEST_ENV) $(BIN)/python -m pytest -q -n $(JOBS) -m "not pipeline and not browser and not cluster and not wheel"

test-cluster: $(STAMP)
	$(BIN)/python -m pytest -q -m cluster

report: $(STAMP)
	$(SNAKEMAKE) -j$(JOBS) --rerun-incomplete all
	$(SNAKEMAKE) --report results/report.html

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py --out results/benchmarks
	$(BIN)/python benchmarks/performance_md.py results/benchmarks/summary.csv docs/performance.md

# Regenerate the pinned, hashed lock from pyproject.toml (needs network access to PyPI).
UV ?= $(shell command -v uv || echo $(BIN)/uv)
# the plan checked through the next run's files on two studies: pooled out-of-sample coverage;
# then cuts predicted with `robomill predict` and cut on the virtual cell (marker predict_cut);
# the same loop again on the cell's richer truth of the robot's modes (the eigenproblem law)
plan-check: $(STAMP)
	$(BIN)/python benchmarks/plan_coverage.py --out results/benchmarks
	$(BIN)/python benchmarks/plan_coverage.py --out results/benchmarks/robot_modes_eigen \
		--overlay benchmarks/robot_modes_eigen.yaml
	$(BIN)/python -m pytest -q -rxX -m predict_cut

# a learn round on the default study and the narrowing of the binding interval it measured
learn-round: $(STAMP)
	$(BIN)/python benchmarks/learn_round.py --out results/benchmarks

lock:
	$(UV) pip compile pyproject.toml --extra dev --excludes environment.excludes --generate-hashes --universal --python-version 3.11 -q -o environment.lock

# Chapter notebooks: the pipeline runs notebooks/<name>.ipynb, built with jupytext from the
# percent-format source notebooks/src/<name>.py (edit the source, then `make notebooks`, commit both;
# tests/test_notebooks.py checks that each pair holds the same cells).
NOTEBOOK_SRC := $(wildcard notebooks/src/*.py)
NOTEBOOKS := $(patsubst notebooks/src/%.py,notebooks/%.ipynb,$(NOTEBOOK_SRC))
notebooks: $(NOTEBOOKS)

notebooks/%.ipynb: notebooks/src/%.py | $(STAMP)
	$(BIN)/jupytext --quiet --update --to ipynb --set-kernel python3 --output $@ $<

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(SNAKEMAKE) --lint

fmt: $(STAMP)
	$(BIN)/ruff check --fix .
	$(BIN)/ruff format src tests workflow/scripts benchmarks
	$(BIN)/snakefmt Snakefile workflow/rules

# Why would a target rerun? `make why` or `make why TARGET=ch2`
TARGET ?= all
why: $(STAMP)
	@$(SNAKEMAKE) -n $(TARGET) 2>&1 | $(BIN)/python -m robomill.pipeline.why

# Jupyter Lab on notebooks/explore.ipynb, or `make explore CHAPTER=ch2` on a copy of the
# chapter notebook with this run's artefact paths injected as parameters
explore: $(STAMP)
	$(BIN)/python -m robomill.pipeline.explore $(CHAPTER)

clean:
	rm -rf results .snakemake
