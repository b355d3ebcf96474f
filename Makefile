# vastray: `make demo` and `make test` work on a fresh Debian 12 machine.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
DEMO_DIR ?= $(BUILD_DIR)/demo

.PHONY: all deps configure build test test-asan demo bench-import bench-accuracy bench-scaling bench-load fuzz fuzz-smoke clean format

all: build

deps:
	bash scripts/install-deps.sh

configure: deps
	@if [ ! -f $(BUILD_DIR)/build.ninja ]; then cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo; fi

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Unit and integration tests (GPU tests run on lavapipe when no GPU is present). Tests
# labelled `long` are excluded; the multi-million-triangle runs live in bench/.
test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -LE long

# libFuzzer run (FUZZ_SECONDS per target, default 30) of the importers, the package reader, the
# chunk decoder and the HTTP JSON bodies, ASan + UBSan, in build-fuzz/ (clang); not part of
# `make test` (a second, sanitizer build: ~5 minutes on 2 cores); CI runs fuzz-smoke below.
fuzz: deps
	bash scripts/fuzz.sh

# What CI runs after `make test` (.ci/run): every fuzz target for 15 s from the seeds, and the
# parser and package unit tests built with ASan + UBSan, both in build-fuzz/ (docs/HARDENING.md).
fuzz-smoke: deps
	FUZZ_SECONDS=15 bash scripts/fuzz.sh

test-asan: deps
	bash scripts/asan-tests.sh

demo: build
	bash scripts/demo.sh $(BUILD_DIR)/vastray $(DEMO_DIR)

bench-import: build
	bash bench/import_throughput.sh $(BUILD_DIR)

# Load test of `vastray serve` with ghz and wrk (docs/generated/load_test.md); tools:
# bash scripts/install-bench-tools.sh; knobs in bench/load/run.sh.
bench-load: build
	bash bench/load/run.sh $(BUILD_DIR)

# Time against error of the streaming renderer (docs/ACCURACY.md); knobs in bench/accuracy/run.sh.
bench-accuracy: build
	bash bench/accuracy/run.sh $(BUILD_DIR)

# Import and render scaling on this machine, Embree in the same run (docs/generated/scaling_dev.md,
# docs/scaling/*.png); knobs in bench/scaling_dev.sh.
bench-scaling: build
	bash bench/scaling_dev.sh $(BUILD_DIR)

format:
	find core streamer cli tests bench -name '*.cpp' -o -name '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
