#!/usr/bin/env bash
# `make test-numa`: proves placement and pinning on an emulated two-node NUMA machine. Fetches
# Debian's kernel (cached), builds a portable suite, packs it with busybox into an initramfs,
# boots QEMU (software emulation, one CPU and 1 GiB per node, distance 21), and has check.py
# judge what the guest (init.sh) sends back. Exit 0: passed, or skipped where it cannot run at
# all (printed with the reason); 1: a check failed or the machine did not finish.
# Environment: JOBS (build jobs, default 2), SUITE_PORTABLE_BINARY (an x86-64-v3 build to use instead of building one), NUMA_VM_DIR (cache and work folder, default build-numa),
# NUMA_VM_TIMEOUT (seconds the machine may run, default 300).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${NUMA_VM_DIR:-$root/build-numa}
timeout_s=${NUMA_VM_TIMEOUT:-300}
start=$SECONDS

name=test-numa
. "$here/vm-lib.sh"

[ "$(uname -m)" = x86_64 ] || skip "the guest runs an x86-64 build of the suite, and this host is $(uname -m)"
for tool in qemu-system-x86_64 cpio gzip /bin/busybox /usr/bin/python3 ldd; do
    command -v "$tool" > /dev/null || fail "$tool is missing: run scripts/install-deps.sh test (qemu-system-x86, busybox-static, cpio)"
done
ldd /bin/busybox > /dev/null 2>&1 && fail "/bin/busybox is dynamically linked; the initramfs needs busybox-static's"

# 1. Debian's kernel, fetched once: the package linux-image-amd64 points at, only its vmlinuz kept.
vmlinuz=$(fetch_kernel linux-image-amd64) ||
    skip "no kernel cached in $work/kernel and Debian's could not be fetched (no apt, or no network)"
step "kernel $(basename "$vmlinuz")"

# 2. A portable build: under software emulation the guest CPU has AVX2 but no AVX-512, so the
# host's -march=native binary may not run there. Its own build folder leaves ./suite alone.
# The main build makes one already when valgrind is installed (suite-x86-64-v3, for the
# deterministic mode): SUITE_PORTABLE_BINARY names it, and saves a second build of everything.
if [ -n "${SUITE_PORTABLE_BINARY:-}" ] && [ -x "$SUITE_PORTABLE_BINARY" ]; then
    guest_suite=$SUITE_PORTABLE_BINARY
    step "using $guest_suite"
else
    cmake -S "$root" -B "$work/suite" -DCMAKE_BUILD_TYPE=Release -DSUITE_ARCH=x86-64-v3 -DSUITE_LINK_TOP=OFF -DSUITE_BUILD_TESTS=OFF > /dev/null
    cmake --build "$work/suite" -j "${JOBS:-2}" > "$work/build.log" 2>&1 || { tail -n 30 "$work/build.log"; fail "the portable build failed"; }
    guest_suite=$work/suite/suite
    step "suite built for x86-64-v3"
fi

# 3. The initramfs: busybox, the suite, every library ldd names (the dynamic loader too), /init.
rm -rf "$work/initramfs"
mkdir -p "$work/initramfs"/{bin,dev,proc,sys,tmp}
cp /bin/busybox "$work/initramfs/bin/busybox"
cp "$guest_suite" "$work/initramfs/suite"
for lib in $(ldd "$guest_suite" | awk '$2 == "=>" && $3 ~ /^\// { print $3 } $1 ~ /^\// { print $1 }'); do
    mkdir -p "$work/initramfs$(dirname "$lib")"
    cp -L "$lib" "$work/initramfs$lib"
done
install -m 755 "$here/init.sh" "$work/initramfs/init"
cp "$here/guest-lib.sh" "$work/initramfs/guest-lib.sh"
pack_initramfs "$work/initramfs" "$work/initrd.gz"

# 4. The machine: node 0 = CPU 0 + 1 GiB, node 1 = CPU 1 + 1 GiB, distance 21. No KVM: /dev/kvm on
# these hosts cannot run a guest. numa_balancing=disable: the pages seen are where the suite put
# them, not where the kernel later moved them. ttyS0 is the console, ttyS1 carries the results.
# thread=single: one host thread runs both vCPUs. With multi-threaded TCG a CI run's guest kernel
# died in do_user_addr_fault on code its own text patching (int3, as perf_event_open's static
# keys flip) had half rewritten: a race in the emulator's handling of code one vCPU modifies while
# the other runs it. Single-threaded TCG has no such race and costs about 7 s here (47 s against 40).
run_machine() {
    rm -f "$work/console.log" "$work/data.txt"
    status=0
    timeout "$timeout_s" qemu-system-x86_64 -nodefaults -accel tcg,thread=single -cpu max -m 2G -smp 2 \
        -object memory-backend-ram,id=m0,size=1G -object memory-backend-ram,id=m1,size=1G \
        -numa node,nodeid=0,cpus=0,memdev=m0 -numa node,nodeid=1,cpus=1,memdev=m1 -numa dist,src=0,dst=1,val=21 \
        -kernel "$vmlinuz" -initrd "$work/initrd.gz" -append "console=ttyS0 quiet panic=-1 numa_balancing=disable" \
        -display none -monitor none -serial "file:$work/console.log" -serial "file:$work/data.txt" \
        -no-reboot -device isa-debug-exit,iobase=0xf4,iosize=0x04 || status=$?
    step "machine exited with status $status"
}
run_machine
# A guest kernel panic is the emulator failing, not the suite: the guest never reached a verdict, so
# nothing was judged. It is said, and the machine is booted once more; a second panic fails the test.
if [ "$status" != 1 ] && [ "$status" != 3 ] && [ "$status" != 124 ] && grep -q 'Kernel panic' "$work/console.log"; then
    grep -m1 -B2 'Kernel panic' "$work/console.log" | sed 's/^/test-numa: guest console: /'
    echo "test-numa: the guest kernel panicked before any verdict (an emulator fault, not a claim); booting it once more"
    cp "$work/console.log" "$work/console-panic.log"
    run_machine
fi
case $status in
    1) ;;  # the guest wrote 0 to isa-debug-exit: everything ran
    3) echo "test-numa: the guest reports a failed run; its console:"; tail -n 40 "$work/console.log" ;;
    124) tail -n 40 "$work/console.log"; fail "the machine did not finish within ${timeout_s} s (NUMA_VM_TIMEOUT)" ;;
    *) tail -n 40 "$work/console.log"; fail "the machine stopped before the guest's verdict (QEMU status $status)" ;;
esac

# 5. The judgement, on the host.
/usr/bin/python3 "$here/check.py" "$work/data.txt" || fail "see the FAIL lines above (guest console: $work/console.log)"
[ "$status" = 1 ] || fail "the guest reports a failed run"
echo "test-numa: PASS in $((SECONDS - start)) s"
