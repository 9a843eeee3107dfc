# omnidso — the two commands a user needs are `make demo` and `make test`.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
DEMO_DIR ?= $(BUILD_DIR)/demo

.PHONY: all deps configure build demo test test-all test-slurm bench clean test-asan test-asan-ci test-tsan fuzz

all: build

deps:
	@bash tools/install_deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) --parallel $(JOBS)

# Fast tests only; end-to-end runs carry the ctest label `slow`.
test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure --parallel $(JOBS) --label-exclude slow

test-all: build
	@cd $(BUILD_DIR) && ctest --output-on-failure --parallel $(JOBS)

# `omnidso ablate --executor slurm` through a real single-node Slurm that the test starts
# (installs slurm-wlm, slurmdbd, munge, mariadb-server and parallel; run as root).
test-slurm: build
	@bash tools/install_deps.sh slurm
	@cd $(BUILD_DIR) && ctest --output-on-failure -R '^SlurmClusterTest\.'

bench: build
	@$(BUILD_DIR)/benchmarks/omnidso_benchmarks $(BENCH_ARGS)

demo: build
	@bash tools/demo.sh $(BUILD_DIR) $(DEMO_DIR)

clean:
	@rm -rf $(BUILD_DIR)

# Sanitizer trees (docs/architecture.md, "Sanitizers and fuzzing"): -O1 with line tables and
# assertions on; Eigen, Ceres and OpenCV come from Debian uninstrumented. Warnings are
# enforced by the Release tree (sanitizers make GCC's flow analysis report false ones).
SANITIZER_CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1" \
  -DOMNIDSO_BUILD_BENCHMARKS=OFF -DOMNIDSO_WERROR=OFF
ASAN_DIR ?= build-asan
TSAN_DIR ?= build-tsan
FUZZ_DIR ?= build-fuzz
# The real-time mode's threads: the mapping worker's tests, then the odometry end to end with
# mapping in its own thread (`omnidso run --threads 2`) on a short sequence rendered by the
# TSan build (the renderer's threads too), one sample per pixel. The 150-frame ctest form
# (RealTimeMode, label `slow`) renders 4 samples per pixel under TSan before the odometry
# starts (≈ 1.8 s of CPU a frame): it did not finish in 36 min on the shared machine.
TSAN_TESTS ?= MappingWorker|TaskPool|WindowSolverDeterminism|OnComputeThreads
TSAN_FRAMES ?= 80

# Eigen turns its "glibc malloc is 16-byte aligned" assumption off under __SANITIZE_ADDRESS__
# and then frees with its own header-offset allocator, while Debian's uninstrumented Ceres
# allocates the same matrices (e.g. GradientChecker::ProbeResults) with plain malloc: freeing
# them in our code read 8 bytes before the block. Restore the release ABI (Eigen still asserts
# that every block it gets is 16-byte aligned; assertions are on in these trees).
ASAN_EIGEN_ABI = -DEIGEN_MALLOC_ALREADY_ALIGNED=1

# AddressSanitizer + UndefinedBehaviorSanitizer, first report fatal, on the fast tests.
test-asan: deps
	@cmake -S . -B $(ASAN_DIR) $(SANITIZER_CMAKE_FLAGS) \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer $(ASAN_EIGEN_ABI)" >/dev/null
	@cmake --build $(ASAN_DIR) --parallel $(JOBS)
	@cd $(ASAN_DIR) && ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	  UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure --parallel $(JOBS) --label-exclude 'slow|fuzz'

# The CI form of test-asan (.ci/run; docs/performance.md, "Reliability"): the same sanitizers
# on the suites of every reader and the bad-input corpus (core: datasets, trajectories,
# pcalib/vignette, images; cameras: calibration files; tools: --config, the real executable on
# the corpus, the fuzzing findings) and a short odometry run; the residuals, backend and
# frontend suites stay in test-asan (left out to keep the build small).
# ctest's `<suite>_NOT_BUILT` placeholders stand for the suites left out. Also left out: the
# calibration's numerical tests (synthetic recovery, the ξ valley, determinism, model fitting:
# ≈ 390 s of CPU under the sanitizers, no file reading); they run in `make test` and
# `make test-asan`.
ASAN_CI_DIR ?= build-asan-ci
ASAN_CI_SUITES = omnidso_core_tests omnidso_cameras_tests omnidso_tools_tests
ASAN_CI_EXCLUDE = _NOT_BUILT$$|^CalibrationSyntheticValleyTest\.|^CalibrationDeterminismTest\.|/CalibrationSyntheticTest\.|^ModelFittingTest\.
ASAN_CI_FRAMES ?= 40
ASAN_RUNTIME_OPTIONS = ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
  UBSAN_OPTIONS=print_stacktrace=1
test-asan-ci: deps
	@cmake -S . -B $(ASAN_CI_DIR) $(SANITIZER_CMAKE_FLAGS) \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer $(ASAN_EIGEN_ABI)" >/dev/null
	@cmake --build $(ASAN_CI_DIR) --parallel $(JOBS) --target omnidso $(ASAN_CI_SUITES)
	@cd $(ASAN_CI_DIR) && $(ASAN_RUNTIME_OPTIONS) \
	  ctest --output-on-failure --parallel $(JOBS) --label-exclude 'slow|fuzz' --exclude-regex '$(ASAN_CI_EXCLUDE)'
	@rm -rf $(ASAN_CI_DIR)/odometry-check && mkdir -p $(ASAN_CI_DIR)/odometry-check
	@$(ASAN_RUNTIME_OPTIONS) $(ASAN_CI_DIR)/tools/omnidso synth --frames $(ASAN_CI_FRAMES) --samples 1 \
	  --out $(ASAN_CI_DIR)/odometry-check/sequence --quiet
	@$(ASAN_RUNTIME_OPTIONS) $(ASAN_CI_DIR)/tools/omnidso run $(ASAN_CI_DIR)/odometry-check/sequence \
	  --out $(ASAN_CI_DIR)/odometry-check/run --quiet
	@$(ASAN_RUNTIME_OPTIONS) $(ASAN_CI_DIR)/tools/omnidso eval --format tum \
	  --gt $(ASAN_CI_DIR)/odometry-check/sequence/groundtruth.txt \
	  --est $(ASAN_CI_DIR)/odometry-check/run/frames.txt

# ThreadSanitizer on the threaded tests; tools/tsan.supp silences uninstrumented libraries only.
TSAN_RUNTIME_OPTIONS = TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$(CURDIR)/tools/tsan.supp"
test-tsan: deps
	@cmake -S . -B $(TSAN_DIR) $(SANITIZER_CMAKE_FLAGS) \
	  -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" >/dev/null
	@cmake --build $(TSAN_DIR) --parallel $(JOBS) --target omnidso omnidso_frontend_tests \
	  omnidso_core_tests omnidso_backend_tests
	@cd $(TSAN_DIR) && $(TSAN_RUNTIME_OPTIONS) \
	  ctest --output-on-failure --parallel $(JOBS) -R '$(TSAN_TESTS)'
	@rm -rf $(TSAN_DIR)/realtime-check && mkdir -p $(TSAN_DIR)/realtime-check
	@$(TSAN_RUNTIME_OPTIONS) $(TSAN_DIR)/tools/omnidso synth --frames $(TSAN_FRAMES) --samples 1 \
	  --out $(TSAN_DIR)/realtime-check/sequence --quiet
	@$(TSAN_RUNTIME_OPTIONS) $(TSAN_DIR)/tools/omnidso run $(TSAN_DIR)/realtime-check/sequence \
	  --threads 2 --out $(TSAN_DIR)/realtime-check/run --quiet
	@$(TSAN_RUNTIME_OPTIONS) $(TSAN_DIR)/tools/omnidso run $(TSAN_DIR)/realtime-check/sequence \
	  --compute-threads 2 --out $(TSAN_DIR)/realtime-check/compute-threads --quiet

# libFuzzer on every reader, 60 s each (clang; ctest label `fuzz`, not part of `make test`).
fuzz:
	@bash tools/install_deps.sh --fuzz
	@cmake -S . -B $(FUZZ_DIR) $(SANITIZER_CMAKE_FLAGS) -DCMAKE_CXX_COMPILER=clang++ \
	  -DOMNIDSO_BUILD_TESTS=OFF -DOMNIDSO_BUILD_FUZZERS=ON \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all" >/dev/null
	@cmake --build $(FUZZ_DIR) --parallel $(JOBS) --target omnidso_fuzzers
	@cd $(FUZZ_DIR) && ctest --output-on-failure --parallel $(JOBS) --label-regex fuzz
