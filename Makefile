# airwake — setup, build, tests, benchmarks and the demo, from a fresh Debian 12 machine.
# Every target installs what it needs (`setup`): Debian packages with apt-get when
# missing, then a Python venv with the package installed editable.

SHELL := /bin/bash
.DEFAULT_GOAL := help

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
AIRWAKE := $(VENV)/bin/airwake
VENV_STAMP := $(VENV)/.installed
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
# arm-none-eabi toolchain for the Teensy images, valgrind for instruction counts,
# teensy-loader-cli for `make flash`, chromium(-driver) for the report's browser test,
# clang + libclang-rt-14-dev (libFuzzer, ASan/UBSan runtimes) for the fuzz targets that
# `make test` runs (tests/link/test_fuzz_smoke.py; firmware/mk/fuzz.mk).
APT_PACKAGES := gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi \
                valgrind teensy-loader-cli gcc chromium chromium-driver clang libclang-rt-14-dev
# worksteal: a worker that runs out of tests takes some of the other's, so the long ones
# (the demo test alone is 1.5-2.5 min) end less unevenly (fresh clone: 12:53 against 13:25)
PYTEST_ARGS ?= -n 2 --dist worksteal
BOARD ?=

.PHONY: help setup apt venv warm gen test test-c test-py firmware native flash bench lint demo sim clean \
        docs-screenshots

help:
	@echo "make demo      SIL ship-airwake flight -> recording -> model report"
	@echo "make test      everything CI runs: C tests (ASan/UBSan) and pytest"
	@echo "make firmware  Teensy 3.2 images for every board (build/teensy32)"
	@echo "make native    native (SIL) board executables (build/native)"
	@echo "make flash BOARD=losa   flash one board with teensy_loader_cli"
	@echo "make bench     performance figures (airwake bench --json)"
	@echo "make gen       regenerate protocol code, docs and vectors"
	@echo "make lint      ruff"

# setup ends by compiling the numba kernels the demo's steps use (on flights of seconds):
# the first process that needs a kernel compiles it into its on-disk cache, later ones load
setup: apt venv native warm

apt:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "setup: installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi

venv: $(VENV_STAMP)

WARM_STAMP := build/.kernels-compiled
warm: $(WARM_STAMP)

$(WARM_STAMP): $(VENV_STAMP) | native
	$(PY) -m hil_sim.boards.demo --warm
	@touch $@

$(VENV_STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	@touch $@

gen: apt venv
	$(PY) protocol/codegen/generate.py

# (not `setup`: the suite compiles the kernels it uses itself, the warm-up would add minutes)
test: apt venv test-c test-py

test-c: apt
	$(MAKE) -C firmware test

# the wall-clock tests (real daemons and boards timed in real time) run after the parallel
# suite, two at a time: beside CPU-heavy tests on the other worker their timing assertions
# starve, beside each other (mostly waiting on real time) they do not (5:30 -> 3:30)
test-py: venv native
	$(PY) -m pytest $(PYTEST_ARGS) -m "not wall_clock"
	$(PY) -m pytest $(PYTEST_ARGS) -m wall_clock

firmware: apt
	$(MAKE) -C firmware teensy32

native: apt
	$(MAKE) -C firmware native

flash: firmware
	@test -n "$(BOARD)" || { echo "usage: make flash BOARD=losa|marker|rover|base"; exit 2; }
	@test -f build/teensy32/$(BOARD).hex || { echo "no image build/teensy32/$(BOARD).hex"; exit 2; }
	teensy_loader_cli --mcu=mk20dx256 -w -v build/teensy32/$(BOARD).hex

bench: setup native
	$(AIRWAKE) bench --json

lint: venv
	$(VENV)/bin/ruff check host hil_sim tests protocol

demo: setup native
	$(PY) -m hil_sim.boards.demo

# docs/img/daemon-live-page.png: the daemon's live page on a SIL flight, in headless Chromium
docs-screenshots: apt venv native
	AIRWAKE_DOCS_SCREENSHOT=1 $(PY) -m pytest tests/sil/test_sil_live_page.py -q

clean:
	rm -rf build
