# The two commands of the README, and a few helpers. Every target bootstraps itself.
SHELL := /bin/bash
.DEFAULT_GOAL := help
ENV := source tools/env.sh
PYTEST_ARGS ?=

.PHONY: help build test check lint warm demo demo-pocket bench figures constraints clean

help:
	@echo "make demo   - run the demo (bootstraps venv, ROS 2 Jazzy wheels, colcon build)"
	@echo "make demo-pocket - the pocket pipeline live: pdr-sim, bag_play, pocket_pdr, bag_record"
	@echo "make test   - ruff + the whole test suite (unit and multi-process integration)"
	@echo "make check  - ruff + the unit and property tests (src/*/test, no ROS processes)"
	@echo "make build  - bootstrap and build only"
	@echo "make bench  - run the benchmarks in test/benchmarks/ (on purpose, not in CI)"
	@echo "make figures - regenerate the PNGs of docs/img/"

build:
	@tools/bootstrap.sh

lint: build
	@$(ENV) && ruff check src test tools

# Two workers (CI has two cores); a test module stays on one worker, so its module-scoped
# fixtures are built once. The numba kernels are compiled before the workers start.
PYTEST_PARALLEL := -n 2 --dist loadfile

warm: build
	@$(ENV) && tools/warm_kernels.sh

test: lint warm
	@$(ENV) && python -m pytest $(PYTEST_PARALLEL) $(PYTEST_ARGS)

check: lint warm
	@$(ENV) && python -m pytest $(PYTEST_PARALLEL) $(wildcard src/*/test) $(PYTEST_ARGS)

demo: warm
	@$(ENV) && tools/demo.sh

demo-pocket: build
	@$(ENV) && tools/demo_pocket.sh

figures: build
	@$(ENV) && tools/doc_figures.sh

bench: build
	@$(ENV) && pip install -q --disable-pip-version-check -r tools/requirements-bench.in \
	  -c tools/constraints.txt && for b in test/benchmarks/bench_*.py; do python "$$b"; done

constraints:
	@python3 -m venv /tmp/pdr-constraints-venv && /tmp/pdr-constraints-venv/bin/pip install -q -r tools/requirements.in -r tools/requirements-bench.in \
	  && (echo "# Exact versions of every Python package in the workspace venv (pip freeze of tools/requirements.in)."; \
	      echo "# Regenerate: make constraints (includes tools/requirements-bench.in)"; /tmp/pdr-constraints-venv/bin/pip freeze) > tools/constraints.txt

clean:
	rm -rf build install log
