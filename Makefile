# Hexapod gait adaptation workspace. Every target bootstraps what it needs (scripts/bootstrap.sh
# is idempotent and a few seconds when nothing changed).
SHELL := /bin/bash
ENV := source scripts/env.sh
PYTEST_ARGS ?=

.PHONY: all bootstrap build demo demo-navigate test test-unit test-integration lint format bench bench-gait bench-sim \
        bench-map bench-adapt bench-bridge bench-navigate bench-firmware pictures clean

all: build

bootstrap:
	@bash scripts/bootstrap.sh

build:
	@bash scripts/bootstrap.sh --force-build

demo: bootstrap
	@$(ENV) && python scripts/demo.py

# A robot with two dead legs walks to three goals through the ROS graph, recorded to MCAP.
demo-navigate: bootstrap
	@$(ENV) && python scripts/demo_navigate.py

# The firmware module's STM32F407 cross build first (its flash and RAM as BENCH lines; the host
# build is part of the colcon build), then every test; the 25 slowest are listed at the end (where
# CI's time goes).
test: bootstrap
	@$(MAKE) -s -C firmware arm BUILD=$(CURDIR)/build/hexapod_firmware_arm
	@$(ENV) && python scripts/run_tests.py --durations=25 $(PYTEST_ARGS)

test-unit: bootstrap
	@$(ENV) && python -m pytest hexapod_util/test hexapod_description/test hexapod_gait/test hexapod_sim/test hexapod_bridge/test hexapod_adapt/test hexapod_navigation/test $(PYTEST_ARGS)

test-integration: bootstrap
	@$(ENV) && python -m pytest tests $(PYTEST_ARGS)

# The packages' lint tests (ament_flake8, ament_pep257, copyright, xmllint); `make test` runs them too.
lint: bootstrap
	@$(ENV) && python -m pytest -m linter $(PYTEST_ARGS)

# The formatter configured to the ROS 2 style (ruff.toml): fixes what the lint tests report, bar
# wording (docstring mood, over-long text), and adds missing copyright headers.
format: bootstrap
	@$(ENV) && ruff format . && ruff check --fix . && \
	  python scripts/copyright_check.py --fix hexapod_util hexapod_description hexapod_gait hexapod_sim \
	    hexapod_bridge hexapod_adapt hexapod_navigation hexapod_msgs && \
	  python scripts/copyright_check.py --fix --license MIT scripts tests studies

bench: bootstrap
	@$(ENV) && python scripts/bench.py all

# Explicit targets: make applies no pattern rule to a .PHONY target.
BENCH_AREAS := gait sim map adapt bridge navigate firmware
$(addprefix bench-,$(BENCH_AREAS)): bench-%: bootstrap
	@$(ENV) && python scripts/bench.py $*

# Footfall diagrams of the presets (and, with the simulator, measured ones and a walk GIF).
pictures: bootstrap
	@$(ENV) && python scripts/pictures.py --out docs/img

clean:
	rm -rf build install log .pytest_cache
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
