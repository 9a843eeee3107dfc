# omnidso — the two commands a user needs are `make demo` and `make test`.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
DEMO_DIR ?= $(BUILD_DIR)/demo

.PHONY: all deps configure build demo test test-all test-slurm bench clean

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
