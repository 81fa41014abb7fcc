# PartSLAM — top-level driver. Every target installs missing system packages first.
BUILD ?= build
JOBS ?= $(shell nproc)
WERROR ?= $(if $(PARTSLAM_WERROR),$(PARTSLAM_WERROR),OFF)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DPARTSLAM_WERROR=$(WERROR)
# make sanitize: ASan + UBSan (float-cast-overflow too, no recovery: any report fails its test) over the ctest
# suite, built with GCC into its own tree at -O1 without debug information (reports name functions) and with
# assertions on (Eigen's off: EIGEN_NO_DEBUG), without the Python module (it would need the ASan runtime preloaded
# into the interpreter), the benchmarks and the tools, which the suite does not run; the tests labelled compile-only
# (they compile headers and run nothing of ours) are left to make test, and the 42 tests of
# tests/long-under-sanitizers.txt (over 10 s each there, most of the time) to make sanitize-long.
SANITIZE_BUILD ?= build-sanitize
SANITIZE_FLAGS ?= -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -DEIGEN_NO_DEBUG" -DPARTSLAM_SANITIZE=ON \
  -DPARTSLAM_BUILD_PYTHON=OFF -DPARTSLAM_BUILD_BENCHMARKS=OFF -DPARTSLAM_BUILD_TOOLS=OFF -DPARTSLAM_WERROR=$(WERROR)
# The one suppression (scripts/lsan.supp): libfontconfig's cache, which cairo's text rendering leaves allocated.
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1:check_initialization_order=1:strict_init_order=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/scripts/lsan.supp:print_suppressions=0
# make fuzz: the libFuzzer targets of fuzz/, built with clang (coverage, ASan, UBSan) into their own tree with only
# the libraries they read through, each run FUZZ_SECONDS (fuzz/run.sh).
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 30
FUZZ_FLAGS ?= -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_CXX_FLAGS_FUZZ="-O1 -gline-tables-only" -DPARTSLAM_FUZZ=ON \
  -DPARTSLAM_BUILD_TESTS=OFF -DPARTSLAM_BUILD_PYTHON=OFF -DPARTSLAM_BUILD_BENCHMARKS=OFF -DPARTSLAM_BUILD_TOOLS=OFF \
  -DPARTSLAM_WERROR=OFF

.PHONY: all deps build demo test sanitize sanitize-long fuzz bench results raw-logs held-out relocalisation locate-check slam-bench slam-stress slam-resolution readme-usage design-layers clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	./$(BUILD)/partslam demo

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) $(SANITIZE_FLAGS) > /dev/null
	@cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	$(SANITIZE_ENV) bash scripts/sanitize-tests.sh $(SANITIZE_BUILD) short $(JOBS)

sanitize-long: deps
	@cmake -S . -B $(SANITIZE_BUILD) $(SANITIZE_FLAGS) > /dev/null
	@cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	$(SANITIZE_ENV) bash scripts/sanitize-tests.sh $(SANITIZE_BUILD) long $(JOBS)

fuzz: deps
	@CXX=clang++ cmake -S . -B $(FUZZ_BUILD) $(FUZZ_FLAGS) > /dev/null
	@FUZZ_BUILD=$(FUZZ_BUILD) FUZZ_SECONDS=$(FUZZ_SECONDS) JOBS=$(JOBS) bash fuzz/run.sh

bench: build
	@for b in $(BUILD)/bench_*; do echo "== $$b"; $$b; done

results: build
	bash scripts/make-results.sh

raw-logs: build
	bash scripts/make-raw-logs.sh

# Buildings not in ../shared (docs/NOTES.md): HELDOUT=DIR holds their files (scripts/held-out.sh says which).
held-out: build
	@test -n "$(HELDOUT)" || { echo "make held-out: set HELDOUT=DIR, the folder of scripts/held-out.sh's files" >&2; exit 2; }
	bash scripts/held-out.sh "$(HELDOUT)"

relocalisation: build
	bash scripts/make-relocalisation.sh

locate-check: build
	bash scripts/check-locate-stored.sh

slam-bench: build
	bash scripts/slam-bench.sh

slam-stress: build
	bash scripts/slam-stress.sh

slam-resolution: build
	bash scripts/slam-resolution.sh

# docs/USAGE.md's usage block, rewritten from `partslam CMD --help` (the ctest readme.usage checks they agree).
readme-usage: build
	/usr/bin/python3 scripts/readme-usage.py $(BUILD)/partslam docs/USAGE.md

# docs/DESIGN.md's layers block, rewritten from scripts/check-layers.sh (the ctest design.layers_are_current).
design-layers:
	/usr/bin/python3 scripts/design_layers.py docs/DESIGN.md src

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD) $(FUZZ_BUILD)
