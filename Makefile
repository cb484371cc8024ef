# rbcflow — two commands do everything (README.md):
#   make reproduce   the study's runs from the current commit, its figures, paper/report/   (QUICK=1: CI parameters)
#   make test        unit tests and quick experiment checks, Release and sanitized builds
# and the evidence behind every u_num (start ensembles, Δt/h refinement, error against run time,
# the stability map), hours of independent cases on GNU parallel here or over SSH, or a Slurm array:
#   make evidence    every case, then reference-data/uncertainty/ and paper/evidence/
# Missing Debian packages are installed first (as root; apt-get update, then only what is absent).

BUILD      ?= build
BUILD_SAN  ?= build-sanitize
BUILD_FUZZ ?= build-fuzz
FUZZ_SECONDS ?= 120
JOBS       ?= $(shell nproc)
QUICK      ?= 0
ONLY       ?=      # "exp ...": these experiments only (report in results/report/, not paper/report/)
COLLECT    ?= 0    # 1: run no case, write the report from the cases finished so far (after a Slurm array)

DEB_PACKAGES := cmake make g++ pkg-config git libeigen3-dev libgsl-dev libfftw3-dev libgtest-dev \
                libbenchmark-dev gnuplot-nox libcli11-dev libtomlplusplus-dev nlohmann-json3-dev parallel \
                python3-vtk9
FUZZ_PACKAGES := clang libomp-dev   # make fuzz only

# The experiments, in the order of the study's Section 3 (stability_map is ours, not the study's).
EXPERIMENTS := channel_flow single_cell_migration four_cells_vs_disks cell_free_layer stability_map constriction

.PHONY: all deps build build-runs test test-release test-sanitize reproduce evidence evidence-cases bench fuzz clean

all: build

deps:
	@missing=""; \
	for p in $(DEB_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "rbcflow: installing missing Debian packages:$$missing"; \
	  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing; \
	else echo "rbcflow: all Debian packages present"; fi

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j $(JOBS)

# Only the programs the runs use (reproduce, evidence): a clean clone builds no tests or benchmark.
build-runs: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j $(JOBS) --target $(EXPERIMENTS) rbcflow

test: test-release test-sanitize

# The longest tests start first (both test targets): on a clean clone ctest has no times of its
# own yet, so build folder $(1) is given one CI run's (tests/ctest_cost_data.txt, "name runs
# seconds", each test's time in the build where it is longer); ctest keeps its own from then on.
# Measured: the 120 s reproduce test, started last by default, ran 40 s alone on two cores.
seed_costs = mkdir -p $(1)/Testing/Temporary && { [ -f $(1)/Testing/Temporary/CTestCostData.txt ] || cp tests/ctest_cost_data.txt $(1)/Testing/Temporary/CTestCostData.txt; }

# Tests run $(JOBS) at a time with one OpenMP thread each: two 2-thread test processes on two
# cores made threads wait at barriers for each other's time slices (measured: a 62 s test took
# over 7 min). Tests that set a thread count themselves keep it.
test-release: build
	$(call seed_costs,$(BUILD))
	cd $(BUILD) && OMP_NUM_THREADS=1 ctest --output-on-failure -j $(JOBS)

# Debug build with AddressSanitizer and UndefinedBehaviorSanitizer: the unit tests (the
# experiment-level tests, named *Experiment*, run in the Release build only). Without GCC's
# variable tracking: the sanitizers' reports keep their files and lines, and the build, the largest
# part of CI, compiles each file 17–24 % faster (measured on its two longest files).
test-sanitize: deps
	cmake -S . -B $(BUILD_SAN) -DCMAKE_BUILD_TYPE=Debug -DRBCFLOW_SANITIZE=ON -DCMAKE_CXX_FLAGS=-fno-var-tracking
	cmake --build $(BUILD_SAN) -j $(JOBS) --target unit_tests rbcflow
	$(call seed_costs,$(BUILD_SAN))
	cd $(BUILD_SAN) && OMP_NUM_THREADS=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS) -E Experiment

# libFuzzer on each kind of input (tests/fuzz/fuzz_inputs.hpp: scene files, --set values,
# checkpoints) for FUZZ_SECONDS each (clang, ASan + UBSan, its own build folder). Inputs that crash
# or hang are written to $(BUILD_FUZZ)/<kind>-crash-* / -timeout-*; each one found goes into
# tests/fuzz/regressions/<kind>/ (replayed by the unit tests).
FUZZ_KINDS := scene_text set_values checkpoint
fuzz:
	@missing=""; for p in $(FUZZ_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing; fi
	cmake -S . -B $(BUILD_FUZZ) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DRBCFLOW_FUZZ=ON
	cmake --build $(BUILD_FUZZ) -j $(JOBS) $(addprefix --target fuzz_,$(FUZZ_KINDS))
	set -e; for kind in $(FUZZ_KINDS); do \
	  mkdir -p $(BUILD_FUZZ)/corpus/$$kind tests/fuzz/regressions/$$kind; \
	  case $$kind in scene_text) seeds="tests/fuzz/seeds_$$kind paper/method/scenes experiments/channel_flow" ;; *) seeds=tests/fuzz/seeds_$$kind ;; esac; \
	  $(BUILD_FUZZ)/bin/fuzz_$$kind -max_total_time=$(FUZZ_SECONDS) -timeout=20 -rss_limit_mb=4096 \
	    -artifact_prefix=$(BUILD_FUZZ)/$$kind- $(BUILD_FUZZ)/corpus/$$kind $$seeds tests/fuzz/regressions/$$kind; \
	done

# Interruptible: Ctrl-C, then the same command continues (paper/make_report.sh).
reproduce: build-runs
	QUICK=$(QUICK) ONLY="$(strip $(ONLY))" COLLECT=$(COLLECT) BUILD=$(BUILD) JOBS=$(JOBS) bash paper/make_report.sh reproduce $(EXPERIMENTS)

evidence: build-runs
	ONLY="$(strip $(ONLY))" COLLECT=$(COLLECT) BUILD=$(BUILD) JOBS=$(JOBS) bash paper/make_report.sh evidence $(EXPERIMENTS)

# The evidence's cases, "experiment case" per line, for other engines (paper/running_at_scale.md).
evidence-cases:
	@$(MAKE) --no-print-directory build >&2
	@for e in $(EXPERIMENTS); do \
	  if $(BUILD)/bin/$$e --help | grep -q -- --list-cases; then $(BUILD)/bin/$$e --list-cases | sed "s/^/$$e /"; \
	  elif [ $$e != channel_flow ]; then echo "$$e -"; fi; done

bench: build
	$(BUILD)/bin/bench_channel

clean:
	rm -rf $(BUILD) $(BUILD_SAN) results
