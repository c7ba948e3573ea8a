# Two commands do everything on a fresh Debian bookworm machine:
#   make test        install what is missing, build, run every test
#   make reproduce   install what is missing, build, run the experiments, figures and report
BUILD ?= build
JOBS ?= 2
PYTHON ?= /usr/bin/python3

.PHONY: all deps configure build test reproduce bench clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=$(PYTHON) > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

reproduce: build
	@PHYSIK=$(BUILD)/physik PYTHON=$(PYTHON) bash scripts/reproduce.sh

bench: build
	@$(BUILD)/physik_bench
	@PYTHONPATH=$(BUILD)/python $(PYTHON) bench/bench_python.py --binary $(BUILD)/physik

clean:
	rm -rf $(BUILD)
