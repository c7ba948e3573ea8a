# Two commands do everything on a fresh Debian bookworm machine:
#   make test        install what is missing, build, run every test
#   make reproduce   install what is missing, build the command line, run the experiments,
#                    figures and report
# and one more, which CI runs after make test (.ci/run):
#   make sanitize    the core, CLI and fuzzer tests on an AddressSanitizer +
#                    UndefinedBehaviorSanitizer build (build-sanitize/), the fuzzer with fewer cases
# and before them, `make check-format`: every C++ file as .clang-format writes it (`make format`
# rewrites them). `make build-cli` builds the command line alone (build/physik).
#
# Debian packages come in sets (scripts/install-deps.sh): what compiling needs is installed first;
# what only running needs (MuJoCo's samples, matplotlib; for the tests Blender and Chromium) is
# installed in the background while the build compiles, and waited for before anything runs.
BUILD ?= build
JOBS ?= 2
PYTHON ?= /usr/bin/python3
DEPS_LOG = $(BUILD)/deps-background.log

# PCH=ON or OFF: precompiled headers (CMakeLists.txt PHYSIK_PCH; docs/DESIGN.md "The build"), passed
# to a build folder's configure; empty keeps the folder's setting (a new folder: CMakeLists' default)
PCH ?=
pch_arg = $(if $(PCH),-DPHYSIK_PCH=$(PCH))

SANITIZE_BUILD ?= build-sanitize
SANITIZE_FUZZ_CASES ?= 600
# -O1 -g1 (line tables): the sanitized build compiles in about half the time of -O2 -g (measured
# per file: 22 s against 46 s for physik/engine/articulated_body.cpp), and its reports still name
# the function and line
SANITIZE_CXX_FLAGS ?= -O1 -g1 -DNDEBUG
# halt on the first report; the uninstrumented libraries (MuJoCo, Ceres, glog) may keep memory
# until exit, so leaks are not errors
SANITIZE_ENV = ASAN_OPTIONS=halt_on_error=1:detect_leaks=0:abort_on_error=0 \
	UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

# a new build folder uses Ninja where it is installed (the build set installs it): Ninja starts a
# layer's files while the layers below still compile, where the Makefile generator waits for each
# library; a folder keeps the generator it was configured with
generator = $(if $(wildcard $(1)/CMakeCache.txt),,$(if $(shell command -v ninja),-G Ninja))

# build $(1) (targets; all if empty) in $(2) while the Debian sets $(3) install in the background,
# then wait for them
define build_beside_deps
	@bash scripts/install-deps.sh --start $(2)/deps-background.log $(3)
	@cmake --build $(2) -j $(JOBS) $(if $(1),--target $(1))
	@bash scripts/install-deps.sh --wait $(2)/deps-background.log
endef

.PHONY: all deps configure build build-cli test reproduce bench bench-count clean sanitize \
	format check-format build-times

all: build

# every set at once, in the foreground
deps:
	@bash scripts/install-deps.sh

configure:
	@bash scripts/install-deps.sh build
	@cmake -S . -B $(BUILD) $(call generator,$(BUILD)) -DCMAKE_BUILD_TYPE=Release $(pch_arg) \
		-DPython3_EXECUTABLE=$(PYTHON) > /dev/null

build: configure
	$(call build_beside_deps,,$(BUILD),run test)

# the experiments need only the command-line program (not the tests, benchmarks or Python module)
build-cli: configure
	$(call build_beside_deps,physik_cli,$(BUILD),run)

# the configure after the build finds what the background install brought (Blender's tests)
test: configure
	$(call build_beside_deps,,$(BUILD),run test)
	@cmake $(BUILD) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

reproduce: build-cli
	@PHYSIK=$(BUILD)/physik PYTHON=$(PYTHON) JOBS=$(JOBS) bash scripts/reproduce.sh

bench: configure
	$(call build_beside_deps,physik_bench physik_python,$(BUILD),run)
	@$(BUILD)/physik_bench
	@PYTHONPATH=$(BUILD)/python $(PYTHON) bench/bench_python.py --binary $(BUILD)/physik

# instructions per bone-step, counted by callgrind on the chains (bench/bench_count.py): a count,
# not a time, so that a change is judged the same on a busy machine; table on stdout, rows in
# $(BUILD)/bench_count/
bench-count: configure
	$(call build_beside_deps,physik_count,$(BUILD),test)
	@$(PYTHON) bench/bench_count.py --binary $(BUILD)/physik_count --out $(BUILD)/bench_count

# where a clean build's time goes, per target and per file, without ccache (build-times/)
build-times:
	@bash scripts/install-deps.sh build
	@JOBS=$(JOBS) PYTHON=$(PYTHON) bash scripts/build_times.sh

sanitize:
	@bash scripts/install-deps.sh build
	@cmake -S . -B $(SANITIZE_BUILD) $(call generator,$(SANITIZE_BUILD)) \
		-DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHYSIK_SANITIZE=ON \
		-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SANITIZE_CXX_FLAGS)" \
		-DPHYSIK_CORE_SUITE_ONLY=ON $(pch_arg) \
		-DPHYSIK_FUZZ_CASES=$(SANITIZE_FUZZ_CASES) -DPython3_EXECUTABLE=$(PYTHON) > /dev/null
	$(call build_beside_deps,,$(SANITIZE_BUILD),run)
	@cd $(SANITIZE_BUILD) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS)

check-format:
	@bash scripts/install-deps.sh format
	@bash scripts/check-format.sh

format:
	@git ls-files '*.cpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD)
