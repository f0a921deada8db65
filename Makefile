# Thin wrapper over CMake. On a fresh Debian 12 as root: `make demo` or `make test`.
BUILD    ?= build
JOBS     ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps print-deb-packages configure build debug asan fuzz test test-only bench demo smoke format clean

all: build

# Every build and run dependency, from Debian's packages only. Safe to re-run.
DEB_PACKAGES := build-essential cmake pkg-config git jq shellcheck ca-certificates \
	file time python3 clang-format ccache \
	libeigen3-dev libopencv-dev libopencv-contrib-dev libopenimageio-dev openimageio-tools libopenexr-dev \
	libcli11-dev nlohmann-json3-dev libtbb-dev libembree-dev \
	libgtest-dev libgmock-dev googletest libbenchmark-dev \
	glslang-tools libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
	libtomlplusplus-dev libssl-dev liblcms2-dev libsqlite3-dev sqlite3 libzip-dev zip libqhull-dev libpng-dev zlib1g-dev \
	clang libclang-rt-14-dev gnuplot-nox snakemake slurm-wlm munge \
	blender-data opencv-doc

deps:
	@if [ "$$(id -u)" -ne 0 ]; then echo "make deps: run as root (apt-get install)"; exit 2; fi
	@missing=$$(for p in $(DEB_PACKAGES); do \
		dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || echo $$p; \
	done); \
	if [ -n "$$missing" ]; then \
		echo "make deps: installing:" $$missing; \
		export DEBIAN_FRONTEND=noninteractive; \
		apt-get update -q && apt-get install -y -q --no-install-recommends $$missing; \
	else echo "make deps: all Debian packages present"; fi

# The package list, for tests/setup/deps_test.sh (every command the scripts run comes from one).
print-deb-packages:
	@echo $(DEB_PACKAGES)

configure:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

debug:
	$(MAKE) build BUILD=build-debug CMAKE_FLAGS="-DCMAKE_BUILD_TYPE=Debug"

# AddressSanitizer + UndefinedBehaviorSanitizer build and suite. The CLI scripts' hang guard is
# 1500 s here, not 300: the tools run 3-10x slower under ASan + UBSan, and badinput_files_test
# already takes 180 s unsanitised at load 14 on 2 cores. Allocation stacks use the fast
# (frame-pointer) unwinder: the slow one deadlocks in Mesa's llvmpipe, whose JIT allocates inside
# libgcc's __register_frame while holding the unwinder's own lock (GlesHarness.* hung there).
# Mesa's one leak is kept out in lib/gles/harness.cpp, OpenImageIO's by fuzz/lsan.supp.
asan:
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DINLIGHT_SANITIZE=address,undefined \
		-DINLIGHT_BUILD_BENCH=OFF -DINLIGHT_CLI_TEST_TIMEOUT_S=1500 $(CMAKE_FLAGS)
	cmake --build build-asan -j $(JOBS)
	cd build-asan && ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=1 \
		LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp ctest --output-on-failure -j $(JOBS) -LE slow

# libFuzzer harnesses, one per loader (docs/fuzzing.md), built with clang, ASan and UBSan in
# build-fuzz, then each run for FUZZ_SECONDS (two at a time, nice 10). The 10-minute runs:
# make fuzz FUZZ_SECONDS=600.
FUZZ_SECONDS ?= 30
fuzz:
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Fuzz -DINLIGHT_FUZZ=ON \
		-DINLIGHT_BUILD_BENCH=OFF $(CMAKE_FLAGS)
	cmake --build build-fuzz -j $(JOBS) --target inlight_fuzzers
	./fuzz/run.sh build-fuzz $(FUZZ_SECONDS)

test: deps build test-only

# ctest lists skipped tests without a reason: skip_reasons.sh prints each one's from its output,
# then ctest's summary line again; the exit code is ctest's.
test-only:
	cd $(BUILD) && { ctest --output-on-failure -j $(JOBS); echo $$? > ctest.rc; } 2>&1 | tee ctest.log
	@$(CURDIR)/tests/skip_reasons.sh $(BUILD)/ctest.log $(BUILD)/Testing/Temporary/LastTest.log
	@exit $$(cat $(BUILD)/ctest.rc)

bench: build
	./pipelines/bench.sh $(BUILD)

demo: deps build
	INLIGHT_BIN=$(BUILD)/bin ./pipelines/demo.sh out

smoke: build
	INLIGHT_BIN=$(BUILD)/bin ./pipelines/demo.sh out

format:
	find apps lib tests -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-debug build-asan build-fuzz
