# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# The two commands of the README: `make run` and `make test`. Both install missing Debian
# packages first, then configure and build in Release.

BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=

.PHONY: all deps configure build run test sanitize sanitize-build tsan bench fuzz format tidy clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	./$(BUILD_DIR)/ramiform demo --out out

# ctest's summary line comes before its list of skipped tests (those that need ../shared/data);
# repeat it last so that it ends the output. Only the CLI and the test programs are built (the
# benchmarks are built by `make bench`).
test: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target ramiform_test_programs
	@cd $(BUILD_DIR) && { ctest --output-on-failure -j $(JOBS) --timeout 600 > ctest.log 2>&1; \
	  rc=$$?; cat ctest.log; grep -E '^[0-9]+% tests passed' ctest.log | tail -1; exit $$rc; }

sanitize: sanitize-build
	cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS) --timeout 1200

# Only the build of `make sanitize` (CI runs the tests within its time budget:
# scripts/sanitize_tests.sh).
sanitize-build: deps
	@cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAMIFORM_SANITIZE=ON \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DRAMIFORM_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-sanitize -j $(JOBS)

# ThreadSanitizer over the test suite (docs/reliability.md). The parallel layer runs on
# std::thread here, because Debian's oneTBB is not instrumented and TSan cannot see its
# synchronization; the chunks, and so every result, are the same as with oneTBB.
tsan: deps
	@cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAMIFORM_TSAN=ON \
	  -DRAMIFORM_BUILD_BENCH=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build build-tsan -j $(JOBS) --target ramiform_test_programs
	cd build-tsan && TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
	  ctest --output-on-failure -j $(JOBS) --timeout 1800

# The Google Benchmarks, then (when OpenVDB is installed: scripts/install-deps.sh --bench) the
# OpenVDB comparison on a 1500-segment tree with 4 mm twigs at a voxel equal to the twig radius.
bench:
	@bash scripts/install-deps.sh --bench
	@$(MAKE) --no-print-directory build
	@for b in $(BUILD_DIR)/bench/ramiform_bench_*; do \
	  case $$b in *_openvdb) continue ;; esac; echo "== $$b"; $$b; done
	@if [ -x $(BUILD_DIR)/bench/ramiform_bench_openvdb ]; then \
	  ./$(BUILD_DIR)/ramiform generate $(BUILD_DIR)/bench/tree1500.json --segments 1500 \
	    --tip-radius 0.004 --trunk-length 1 --seed 1 >/dev/null && \
	  echo "== $(BUILD_DIR)/bench/ramiform_bench_openvdb tree1500.json 0.004" && \
	  ./$(BUILD_DIR)/bench/ramiform_bench_openvdb $(BUILD_DIR)/bench/tree1500.json 0.004; fi

# The libFuzzer harnesses of fuzz/ (docs/fuzzing.md): clang 14 with ASan + UBSan in build-fuzz,
# then every harness for FUZZ_SECONDS on its corpus, FUZZ_PARALLEL at a time; new inputs go to
# build-fuzz/fuzz-work/, findings to build-fuzz/fuzz-findings/ (the checked-in corpus is only read).
# FUZZ_ONLY="mesh_off curve2" runs only those harnesses; FUZZ_RUNS=N stops each after N executions.
FUZZ_SECONDS ?= 60
FUZZ_PARALLEL ?= 1
fuzz:
	@bash scripts/install-deps.sh --fuzz
	@cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DRAMIFORM_FUZZ=ON -DRAMIFORM_BUILD_BENCH=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build build-fuzz -j $(JOBS) --target ramiform_fuzzers
	@FUZZ_ONLY="$(FUZZ_ONLY)" FUZZ_RUNS="$(FUZZ_RUNS)" bash fuzz/run_fuzzers.sh build-fuzz $(FUZZ_SECONDS) $(FUZZ_PARALLEL)

format:
	@find include src apps tests bench tools -name '*.h' -o -name '*.cpp' | xargs clang-format -i

tidy: configure
	@find src apps -name '*.cpp' | xargs clang-tidy -p $(BUILD_DIR) --quiet

clean:
	rm -rf $(BUILD_DIR) build-sanitize build-tsan out
