# The two commands of the README: `make run` and `make test`. Everything else is a helper.
BUILD ?= build
ARCH ?= native
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps run-deps test-deps configure build run plots examples test install test-numa test-arm64 build-arm64 arm64-deps test-sanitize test-mutants clean bench-deps bench-vs bench-noise bench-gate bench-gate-reach bench-spmv bench-fem bench-mpm bench-mpm-implicit bench-mpi

# CMake's generated makefiles run make within make: without this each step says which directory it
# enters and leaves.
MAKEFLAGS += --no-print-directory
# The plots need Debian's matplotlib: /usr/bin/python3, not whatever python3 comes first on PATH.
PYTHON ?= $(shell test -x /usr/bin/python3 && echo /usr/bin/python3 || echo python3)
PLOTS ?= results/plots

all: build

deps:
	@scripts/install-deps.sh build

run-deps:
	@scripts/install-deps.sh run

test-deps:
	@scripts/install-deps.sh test

# Configured every time, so ARCH=... and CMAKE_FLAGS=... take effect on an existing build too.
# Quiet but for what is left out of the build and why (suite-mpi without MPI, say); everything
# when the configure fails.
configure:
	@out=$$(cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DSUITE_ARCH=$(ARCH) $(CMAKE_FLAGS) 2>&1) || { echo "$$out"; exit 1; }; \
	  echo "$$out" | grep -E '^-- suite(-mpi| matrix): not built' || true

# Everything: the program, the tests, the x86-64-v3 twin for valgrind, suite-gbench, the fuzz targets.
build: deps configure
	cmake --build $(BUILD) -j $(JOBS)

# Installs into $(PREFIX): bin/suite (and suite-mpi, the valgrind twin where built), share/suite
# (plot scripts, JSON schema, Chart.js), the man page and the docs; see docs/install.md.
PREFIX ?= /usr/local
install: deps configure
	@probe="$(PREFIX)/.suite-install-probe.$$$$"; \
	  if ! mkdir -p "$(PREFIX)" 2>/dev/null || ! : > "$$probe" 2>/dev/null; then \
	    echo "make install: PREFIX=$(PREFIX) cannot be written by this user; give a PREFIX you may write, e.g. PREFIX=$$HOME/.local, or run as root" >&2; exit 2; fi; \
	  rm -f "$$probe"
	cmake --build $(BUILD) -j $(JOBS) --target suite_installables
	cmake --install $(BUILD) --prefix "$(PREFIX)"

# The default sweep, its sizes taken from the caches this process really gets (--probe-caches): a
# table on the console, results/latest.json, and its figures in $(PLOTS)/; then this machine's
# measured ceilings (results/roofline.json, about 20 s on 2 cores) and the sweep placed on them
# (results/roofline-latest.json and its figure). Builds the program only.
run: run-deps configure
	@cmake --build $(BUILD) -j $(JOBS) --target suite suite_link
	./suite --probe-caches --out=results/latest.json
	@$(MAKE) plots
	./suite roofline --out=results/roofline.json
	./suite roofline --place=results/latest.json --ceilings=results/roofline.json --out=$(PLOTS)/roofline-latest.json

# The committed example results, made again by this build so that they cannot go stale
# (tests/examples_test.py holds them valid and comparable with a fresh run): this machine's
# default sweep, without --probe-caches so that its sizes follow the caches hwloc reports and a
# fresh run meets every role; and two stand-ins for machines whose caches differ, the same sweep on
# synthetic topologies (the sizes follow their caches; the timings are this machine's), for the
# tests of suite compare by cache role.
EXAMPLE ?= results/examples/kvm-2core-default.json
ROLE_FIXTURES = tests/fixtures/results
examples: run-deps configure
	@cmake --build $(BUILD) -j $(JOBS) --target suite suite_link
	./suite --quiet --out=$(EXAMPLE)
	HWLOC_SYNTHETIC="pack:1 l3:1(size=4MiB) l2:2(size=256KiB) l1d:1(size=16KiB) core:1 pu:1" \
	  ./suite --pin=none --reps=3 --min-time=0.01 --quiet --out=$(ROLE_FIXTURES)/roles-small-caches.json
	HWLOC_SYNTHETIC="pack:1 l3:1(size=16MiB) l2:4(size=1MiB) l1d:1(size=48KiB) core:1 pu:1" \
	  ./suite --pin=none --reps=3 --min-time=0.01 --quiet --out=$(ROLE_FIXTURES)/roles-big-caches.json

# The figures of results/latest.json (or RESULT=...), in $(PLOTS)/; the last line names them.
RESULT ?= results/latest.json
plots:
	@files="$$($(PYTHON) plots/plot.py $(RESULT) --out $(PLOTS))" && \
	  echo "figures of $(RESULT) in $(PLOTS)/: $$(for f in $$files; do printf '%s ' "$$(basename "$$f")"; done)"

test: test-deps build
	cd $(BUILD) && ctest --output-on-failure -j 2
	@JOBS=$(JOBS) SUITE_PORTABLE_BINARY=$(BUILD)/suite-x86-64-v3 scripts/numa-vm/run.sh
	@$(MAKE) test-arm64

# aarch64, cross-built from x86-64 with Debian's cross compiler (cmake/toolchain-aarch64.cmake) into
# $(ARM64_BUILD)/: the program and its unit tests, for ARMv8.2-A (Neoverse N1 and later; SVE is
# chosen at run time where the CPU has it). Left out of the cross build: suite-mpi, suite-gbench
# and the fuzz targets (the x86 build tests them). On an Arm host no cross build is needed:
# `make run` and `make test` build natively, as on x86-64.
ARM64_BUILD ?= build-arm64
ARM64_ARCH ?= armv8.2-a
arm64-deps:
	@scripts/install-deps.sh arm64
build-arm64: arm64-deps
	@out=$$(cmake -S . -B $(ARM64_BUILD) -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64.cmake -DCMAKE_BUILD_TYPE=Release \
	  -DSUITE_ARCH=$(ARM64_ARCH) -DSUITE_LINK_TOP=OFF -DSUITE_WITH_MPI=OFF \
	  -DSUITE_BUILD_GBENCH=OFF -DSUITE_FUZZ=OFF $(CMAKE_FLAGS) 2>&1) || { echo "$$out"; exit 1; }
	cmake --build $(ARM64_BUILD) -j $(JOBS) --target suite suite_tests

# Placement and pinning on an emulated two-node NUMA machine (QEMU); its files go to build-numa/.
test-numa: test-deps
	@JOBS=$(JOBS) scripts/numa-vm/run.sh

# The aarch64 build on an emulated Arm machine whose PMU counts instructions exactly (QEMU,
# -icount): every kernel verifies on a Neoverse N1 and on a CPU with 256-bit SVE, placement on two
# nodes, and the counters held to known answers (docs/counters-energy.md#the-emulated-arm-pmu-make-test-arm64).
# FULL=1 adds SVE at 128 and 512 bits. Then the build's disassembly and its unit tests under
# QEMU's user mode, on the N1 and with SVE (scripts/arm64-user-tests.sh; FULL=1: all of them).
# About 6 minutes after the cross build; the VM's files go to build-arm64-vm/.
FULL ?= 0
test-arm64: test-deps build-arm64
	@FULL=$(FULL) SUITE_ARM64_BUILD=$(ARM64_BUILD) scripts/arm64-vm/run.sh
	@FULL=$(FULL) scripts/arm64-user-tests.sh $(ARM64_BUILD)

# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer, in its own build
# folder (the binary the end-to-end tests run is the sanitized one too). Any report fails the test.
SANITIZE_FLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
test-sanitize: test-deps
	cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSUITE_ARCH=$(ARCH) -DSUITE_LINK_TOP=OFF \
	  -DCMAKE_CXX_FLAGS="$(SANITIZE_FLAGS)" -DCMAKE_EXE_LINKER_FLAGS="$(SANITIZE_FLAGS)" > /dev/null
	cmake --build build-sanitize -j $(JOBS)
	cd build-sanitize && ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j 2

# The mutation check: each bug of tests/mutants/mutants.txt planted in turn in a copy of the tree
# (build-mutants/), built, and its tests run; fails if a mutant survives (docs/development.md#mutants).
# Not part of `make test`: one to two hours. MUTANTS_FLAGS passes options, e.g. "--only gate --keep", "--list".
MUTANTS_FLAGS ?=
test-mutants: test-deps
	JOBS=$(JOBS) ARCH=$(ARCH) CMAKE_FLAGS="$(CMAKE_FLAGS)" $(PYTHON) scripts/mutants.py $(MUTANTS_FLAGS)

bench-deps:
	@scripts/install-deps.sh bench

# The suite against likwid-bench's assembly and plain C loops, interleaved on this machine (about
# 10 minutes): ratios on the console and in results/bench/vs_likwid.{json,md}; then every
# sequential stream kernel against the best of likwid-bench, STREAM's loops and glibc's memcpy and
# memset (about 6 minutes), in results/bench/vs_peers.{json,md}. BENCH_FLAGS=--quick checks in
# seconds that it all runs.
BENCH_FLAGS ?=
bench-vs: bench-deps build
	/usr/bin/python3 bench/vs_likwid.py --suite ./suite --ref $(BUILD)/ref_random --out results/bench $(BENCH_FLAGS)
	/usr/bin/python3 bench/vs_peers.py --suite ./suite --ref $(BUILD)/ref_stream --out results/bench $(BENCH_FLAGS)

# The noise floor of bench-vs at 1 GiB: the suite and likwid-bench each against itself (about 12
# minutes), to results/bench/aa_noise.{json,md}.
bench-noise: bench-deps build
	/usr/bin/python3 bench/aa_noise.py --suite ./suite --out results/bench $(BENCH_FLAGS)

# The timing gate's false alarms and reach on 12 fresh reruns of the CI recipe, 20 s apart (about
# 15 minutes; run it on a quiet machine), to results/bench/gate_noise.{json,md}.
bench-gate: build
	/usr/bin/python3 bench/gate_noise.py --suite ./suite --runs 12 --out results/bench $(BENCH_FLAGS)

# The history gate with six runs of history (issue 53): 37 runs of triad and copy at 64 KiB and
# 64 MiB (about 2 minutes), their 36 pairs unchanged and slowed 1.25x, 1.5x and 2x, to
# results/bench/gate_reach.{json,md}.
bench-gate-reach: build
	/usr/bin/python3 bench/gate_reach.py --suite ./suite --out results/bench $(BENCH_FLAGS)

# The fem SpMV against Eigen's sparse matrix-vector product on the same matrix, interleaved (the
# thesis mesh, hilbert, 1 thread; a few minutes, most of it assembly). BENCH_FLAGS passes options,
# e.g. BENCH_FLAGS="--ordering=natural,hilbert,rcm --threads=2 --json=results/bench/spmv_eigen.json".
bench-spmv: bench-deps build
	$(BUILD)/suite-spmv-eigen $(BENCH_FLAGS)

# The fem kernels by ordering (about 25 minutes): SpMV against the triad bound, time against the
# file's order, simulated misses; to results/bench/fem_orderings.{json,md}. BENCH_FLAGS=--quick.
bench-fem: build
	/usr/bin/python3 bench/fem_orderings.py --out results/bench $(BENCH_FLAGS)

# The MPM by particle and grid order (about 50 minutes: the dam break by particle order, window by
# window, the kernels, and --sort-every=auto against the best fixed K of a sweep on the natural and
# Hilbert grids): results/bench/mpm_orders.{json,md} and mpm_flow.png.
bench-mpm: build
	/usr/bin/python3 bench/mpm_orders.py --out results/bench $(BENCH_FLAGS)

# Implicit MPM by grid order (about 20 minutes: a step split into assembly, CG solve and the rest,
# CHOLMOD beside CG): results/bench/mpm_implicit.{json,md}.
bench-mpm-implicit: build
	/usr/bin/python3 bench/mpm_implicit.py --out results/bench $(BENCH_FLAGS)

# Distributed SpMV (suite-mpi, 1 and 2 ranks) against the threaded one on the same cores, curve and
# METIS partitions (a few minutes): results/bench/fem_dist.{json,md}.
bench-mpi: build
	/usr/bin/python3 bench/fem_dist.py --out results/bench $(BENCH_FLAGS)

clean:
	rm -rf $(BUILD) build-sanitize suite
