# Two commands do everything on a fresh Debian bookworm machine:
#   make test        install what is missing, build, run every test
#   make reproduce   install what is missing, build, run the experiments, figures and report
# and one more, which CI runs after make test (.ci/run):
#   make sanitize    the core, CLI and fuzzer tests on an AddressSanitizer +
#                    UndefinedBehaviorSanitizer build (build-sanitize/), the fuzzer with fewer cases
# and before them, `make check-format`: every C++ file as .clang-format writes it (`make format`
# rewrites them).
BUILD ?= build
JOBS ?= 2
PYTHON ?= /usr/bin/python3

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

.PHONY: all deps configure build build-cli test reproduce bench bench-count clean sanitize format check-format

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=$(PYTHON) > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# the experiments need only the command-line program (not the tests, benchmarks or Python module)
build-cli: configure
	@cmake --build $(BUILD) -j $(JOBS) --target physik_cli

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

reproduce: build-cli
	@PHYSIK=$(BUILD)/physik PYTHON=$(PYTHON) bash scripts/reproduce.sh

bench: build
	@cmake --build $(BUILD) -j $(JOBS) --target physik_bench
	@$(BUILD)/physik_bench
	@PYTHONPATH=$(BUILD)/python $(PYTHON) bench/bench_python.py --binary $(BUILD)/physik

# instructions per bone-step, counted by callgrind on the chains (bench/bench_count.py): a count,
# not a time, so that a change is judged the same on a busy machine; table on stdout, rows in
# $(BUILD)/bench_count/
bench-count: configure
	@cmake --build $(BUILD) -j $(JOBS) --target physik_count
	@$(PYTHON) bench/bench_count.py --binary $(BUILD)/physik_count --out $(BUILD)/bench_count

sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHYSIK_SANITIZE=ON \
		-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SANITIZE_CXX_FLAGS)" \
		-DPHYSIK_CORE_SUITE_ONLY=ON \
		-DPHYSIK_FUZZ_CASES=$(SANITIZE_FUZZ_CASES) -DPython3_EXECUTABLE=$(PYTHON) > /dev/null
	@cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	@cd $(SANITIZE_BUILD) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS)

check-format: deps
	@bash scripts/check-format.sh

format:
	@git ls-files '*.cpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD)
