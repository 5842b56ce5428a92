# The README's two commands: `make demo` and `make test`. Both install missing Debian packages first.
BUILD_DIR ?= build
ASAN_DIR  ?= build-asan
JOBS      ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build build-cli build-asan demo test test-unit test-asan accuracy soak bench fuzz clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# Only what the demo runs: the mocaplabel binary and the libraries it links, not the tests and benchmarks.
build-cli: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target mocaplabel

build-asan: deps
	@cmake -S . -B $(ASAN_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DMOCAP_SANITIZE=ON \
	  -DBUILD_BENCHMARKS=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(ASAN_DIR) -j $(JOBS)

demo: build-cli
	scripts/demo.sh $(BUILD_DIR)/src/cli/mocaplabel demo-out

# The accuracy sweeps (label "accuracy": the validator's must-shows on simulated sessions, minutes of
# CPU each) run in `make accuracy`, before an accuracy claim is made, and the long recordings (label
# "soak": a minute or more of wall time each) in `make soak`; neither is part of every `make test`.
test-unit: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) -LE 'accuracy|soak'

accuracy: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) -L accuracy

soak: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) -L soak

# Unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (end-to-end runs excluded: slow).
# Tests that render through EGL (in process, or in the mocaplabel processes they start) run without LeakSanitizer: Mesa's llvmpipe keeps process-lifetime
# allocations made from JIT code and unloaded driver modules, which LeakSanitizer cannot attribute to a
# library and so cannot suppress. AddressSanitizer and UBSan still check them. (Selected by test binary.)
EGL_TESTS = ^(render_egl_test|label_test|labeller_test|validate_egl_test|pipeline_run_test|pipeline_cli_test|export_[a-z0-9]+_test)/
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Numeric sweeps that take minutes each at -O0 under the sanitizers (Eigen loops over real point clouds)
# and add no code path the binary's other cases do not run: they run in test-unit only. (TableTest: a
# 2.4 m table top filling a 640x480 depth image, about 9 min of CPU per case under the sanitizers; the
# cone and box cases run the same observability code there.) The Slurm
# cluster's tests (label slurm) run once, in test-unit: they start daemons, not our code.
ASAN_SKIP = TableTest\.|Icp\.ConvergesFromKnownOffsetsOnANoiselessBox|MilkRealData\.|TumFr1Desk\.|ObjectTracker\.AcquiresThenTracksAStaticObjectWhileTheCameraMoves|PointGrid\.NearestMatchesBruteForce|Kinect2Export\.BopDepthInTheColourImageAgreesWithTheTruth
test-asan: build-asan
	$(SAN_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS) -LE 'e2e|slow|slurm' -E '$(EGL_TESTS)|$(ASAN_SKIP)'
	$(SAN_ENV) ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
	  ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS) -R '$(EGL_TESTS)' -E '$(ASAN_SKIP)'

test: test-unit test-asan

bench: build
	@for b in $(BUILD_DIR)/bench/bench_*; do echo "== $$b"; $$b; done

# Every fuzzer of tests/fuzz (docs/fuzzing.md) for FUZZ_SECONDS each, JOBS at a time, with clang++; the
# corpora grow and stay in $(BUILD_DIR)/tests/fuzz/work/<name>/corpus, crash reproducers beside them.
FUZZ_SECONDS ?= 300
fuzz: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target mocap_fuzz_prereqs
	FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_JOBS=$(JOBS) FUZZ_KEEP_CORPUS=1 tests/fuzz/fuzz.sh $(BUILD_DIR) all

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR)
