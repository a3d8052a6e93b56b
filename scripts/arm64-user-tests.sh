#!/usr/bin/env bash
# The aarch64 build's own tests on this x86-64 host, part of `make test-arm64`:
#   1. its disassembly (tests/arm64/disasm_test.py): the nt stores, the SVE twins, peak-flops' FMAs;
#   2. its unit tests under QEMU's user-mode emulation, on a Neoverse N1 model (NEON only) and on
#      QEMU's max CPU with 256-bit SVE, so both the NEON loops and their SVE twins verify. By
#      default the registry's walk (every kernel verified at a tiny size) and the engine's and
#      stream kernels' tests; FULL=1 adds the FEM, MPM, SFC and mesh kernels' own tests (tens of
#      minutes under emulation).
# Usage: scripts/arm64-user-tests.sh [BUILD-ARM64]. Exit 0: passed, or skipped with the reason
# printed; 1: a check failed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build-arm64}
start=$SECONDS
skip() { echo "arm64 user tests: SKIPPED: $*"; exit 0; }
[ -x "$build/suite" ] && [ -x "$build/tests/suite_tests" ] || skip "no aarch64 build in $build (make build-arm64)"
emulator=$(command -v qemu-aarch64-static || command -v qemu-aarch64 || true)
[ -n "$emulator" ] || skip "qemu-aarch64(-static) not found (scripts/install-deps.sh arm64 installs qemu-user-static)"
objdump=$(command -v aarch64-linux-gnu-objdump || true)
[ -n "$objdump" ] || skip "aarch64-linux-gnu-objdump not found (binutils-aarch64-linux-gnu)"

/usr/bin/python3 "$root/tests/arm64/disasm_test.py" "$build/suite" "$objdump" | tail -n 1

# QEMU's user mode implements neither perf_event_open nor mbind: the tests that count events or
# bind pages run in the emulated machine of scripts/arm64-vm/ instead (its checks 1 to 4).
needs_kernel='TeamCountersTest.FirstTouchOfNPagesCountsAtLeastNPageFaults:TeamCountersTest.MigrationsAreZeroWhenPinnedAndCountedWhenTheThreadMoves:TeamCountersTest.HardwareEventsAreUnavailableWithTheReasonWithoutAPmu:InstrumentRun.PinnedRunCountsNoMigrationsAndNoFaultsInTheTimedRepetitions:InstrumentList.ListCountersSaysWhatCanBeCountedHere:Placement.HistogramFindsEveryTouchedPageOnItsNode'
filter='AllKernels/Registry.*:RegistryContents.*:CpuModel.*:Stats.*:ChoiceTable.*:Plan.*:PlanParams.*:PlanVariants.*:Pinning.*:Placement.*:Topology.*:Counter*:Energy*:Instrument*:Perf*:Powercap.*:TeamCountersTest.*'
[ "${FULL:-0}" = 1 ] && filter='*'
filter="$filter-$needs_kernel"
export SUITE_TEST_EMULATOR=$emulator
for cpu in neoverse-n1 max,sve256=on; do
    log=$build/user-tests-${cpu%%,*}.log
    if QEMU_CPU=$cpu "$emulator" -cpu "$cpu" "$build/tests/suite_tests" --gtest_filter="$filter" \
        --gtest_brief=1 > "$log" 2>&1; then
        echo "arm64 user tests on $cpu: $(grep -Eo '[0-9]+ tests? from [0-9]+ test suites? ran' "$log" | head -n 1), all passed ($((SECONDS - start)) s)"
    else
        grep -E '^\[  FAILED  \]' "$log" | head -n 20
        echo "arm64 user tests on $cpu: FAILED (whole log: $log)" >&2
        exit 1
    fi
done
