# PartSLAM — top-level driver. Every target installs missing system packages first.
BUILD ?= build
JOBS ?= $(shell nproc)
WERROR ?= $(if $(PARTSLAM_WERROR),$(PARTSLAM_WERROR),OFF)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DPARTSLAM_WERROR=$(WERROR)

.PHONY: all deps build demo test bench results raw-logs relocalisation clean

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

bench: build
	@for b in $(BUILD)/bench_*; do echo "== $$b"; $$b; done

results: build
	bash scripts/make-results.sh

raw-logs: build
	bash scripts/make-raw-logs.sh

relocalisation: build
	bash scripts/make-relocalisation.sh

clean:
	rm -rf $(BUILD)
