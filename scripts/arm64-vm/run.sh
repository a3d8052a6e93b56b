#!/usr/bin/env bash
# `make test-arm64`: the aarch64 build of the suite on an emulated Arm machine whose PMU counts
# instructions exactly (QEMU TCG with -icount shift=0, two NUMA nodes), so that the counters are
# held to a known answer (docs/counters-energy.md#emulated-arm-pmu). Packs the cross-built suite
# and its unit tests, their arm64 libraries and Debian's arm64 busybox into an initramfs, boots
# Debian's arm64 kernel once per CPU (neoverse-n1; max with 256-bit SVE; FULL=1 adds SVE at 128
# and 512 bits), and has check.py judge what the guest (init.sh) sends back.
# Exit 0: passed, or skipped where it cannot run (printed with the reason); 1: a check failed.
# Environment: SUITE_ARM64_BUILD (the aarch64 build folder, default build-arm64, made by `make
# build-arm64`), ARM64_VM_DIR (cache and work folder, default build-arm64-vm), ARM64_VM_TIMEOUT
# (seconds each machine may run, default 300), FULL=1.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${ARM64_VM_DIR:-$root/build-arm64-vm}
build=${SUITE_ARM64_BUILD:-$root/build-arm64}
timeout_s=${ARM64_VM_TIMEOUT:-300}
start=$SECONDS
name=test-arm64
. "$here/../numa-vm/vm-lib.sh"

case "$(uname -m)" in
    aarch64) tools=; meta=linux-image-arm64; bb_pkg=busybox-static ;;
    *) tools=aarch64-linux-gnu-; meta=linux-image-arm64:arm64; bb_pkg=busybox-static:arm64 ;;
esac
command -v qemu-system-aarch64 > /dev/null || skip "qemu-system-aarch64 is missing (Debian: qemu-system-arm)"
for tool in cpio gzip /usr/bin/python3 "${tools}readelf" "${tools}objdump"; do
    command -v "$tool" > /dev/null || fail "$tool is missing: run scripts/install-deps.sh arm64"
done
[ -x "$build/suite" ] || skip "no aarch64 build at $build/suite: make build-arm64 first (SUITE_ARM64_BUILD names another)"
mkdir -p "$work"

# 1. Debian's arm64 kernel and its static busybox, fetched once; nothing is installed.
vmlinuz=$(fetch_kernel "$meta") || skip "no kernel cached in $work/kernel and Debian's could not be fetched"
busybox=$work/busybox/busybox
[ -x "$busybox" ] || fetch_from_deb "$bb_pkg" ./bin/busybox "$work/busybox" ||
    skip "no arm64 busybox cached in $work/busybox and Debian's could not be fetched"
step "kernel $(basename "$vmlinuz"), busybox $(file -b "$busybox" | cut -d, -f2)"

# 2. The initramfs: busybox, the suite and its unit tests, each library they need (the loader
# too), resolved from their dynamic sections as the loader would, in the multiarch folders.
libdirs="/lib/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu /lib /usr/lib"
needed() { "${tools}readelf" -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }
interp() { "${tools}readelf" -l "$1" | sed -n 's/.*Requesting program interpreter: \(.*\)\]/\1/p'; }
declare -A packed=()
pack_libs() {  # pack_libs ELF: the libraries it needs, and theirs
    local lib dir found
    for lib in $(needed "$1"); do
        [ -n "${packed[$lib]:-}" ] && continue
        found=
        for dir in $libdirs; do [ -e "$dir/$lib" ] && found=$dir/$lib && break; done
        [ -n "$found" ] || fail "$lib, which $(basename "$1") needs, is in none of $libdirs (scripts/install-deps.sh arm64)"
        packed[$lib]=$found
        mkdir -p "$work/initramfs$(dirname "$found")"
        cp -L "$found" "$work/initramfs$found"
        pack_libs "$found"
    done
}
rm -rf "$work/initramfs"
mkdir -p "$work/initramfs"/{bin,dev,proc,sys,tmp}
cp "$busybox" "$work/initramfs/bin/busybox"
programs=("$build/suite")
[ -x "$build/tests/suite_tests" ] && programs+=("$build/tests/suite_tests")
for p in "${programs[@]}"; do
    cp "$p" "$work/initramfs/$(basename "$p")"
    pack_libs "$p"
    loader=$(interp "$p")
    mkdir -p "$work/initramfs$(dirname "$loader")"
    cp -L "$loader" "$work/initramfs$loader"
done
# The kernels check 1 walks in the guest (as gtest names them: - becomes _).
echo copy scale add triad sin_add load store latency peak_flops > "$work/initramfs/registry-kernels"
install -m 755 "$here/init.sh" "$work/initramfs/init"
cp "$here/../numa-vm/guest-lib.sh" "$work/initramfs/guest-lib.sh"
pack_initramfs "$work/initramfs" "$work/initrd.gz"
# The loops the counts are held to: the suite's disassembly, read on the host.
"${tools}objdump" -d --no-show-raw-insn -C "$build/suite" > "$work/suite.dis"

# 3. The machines: node 0 = CPU 0 + 1 GiB, node 1 = CPU 1 + 1 GiB, distance 21. -icount shift=0
# makes the instruction count exact (and one emulated instruction one ns of the guest's clock);
# it runs both CPUs on one host thread.
run_machine() {  # run_machine TAG CPU CHECKS
    local log=$work/console-$1.log status=0
    timeout "$timeout_s" qemu-system-aarch64 -nodefaults -M virt -cpu "$2" -accel tcg -icount shift=0 -m 2G -smp 2 \
        -object memory-backend-ram,id=m0,size=1G -object memory-backend-ram,id=m1,size=1G \
        -numa node,nodeid=0,cpus=0,memdev=m0 -numa node,nodeid=1,cpus=1,memdev=m1 -numa dist,src=0,dst=1,val=21 \
        -kernel "$vmlinuz" -initrd "$work/initrd.gz" \
        -append "console=ttyAMA0 quiet panic=-1 numa_balancing=disable suite.cpu=$1 suite.checks=$3" \
        -display none -monitor none -serial "file:$log" -no-reboot || status=$?
    step "$1 ($2): machine exited with status $status"
    [ "$status" = 124 ] && { tail -n 20 "$log"; fail "the $1 machine did not finish within ${timeout_s} s (ARM64_VM_TIMEOUT)"; }
    [ "$status" = 0 ] || { tail -n 20 "$log"; fail "the $1 machine stopped with QEMU status $status"; }
}
machines=(n1 sve256)
run_machine n1 neoverse-n1 all
run_machine sve256 max,sve256=on kernels
if [ "${FULL:-0}" = 1 ]; then
    run_machine sve128 max,sve128=on kernels
    run_machine sve512 max,sve512=on kernels
    machines+=(sve128 sve512)
fi

# 4. The judgement, on the host.
logs=()
for m in "${machines[@]}"; do logs+=("$m=$work/console-$m.log"); done
/usr/bin/python3 "$here/check.py" --disassembly "$work/suite.dis" "${logs[@]}" ||
    fail "see the FAIL lines above (guest consoles: $work/console-*.log)"
echo "test-arm64: PASS in $((SECONDS - start)) s"
