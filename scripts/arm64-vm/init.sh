#!/bin/busybox sh
# /init of the emulated aarch64 machine that scripts/arm64-vm/run.sh boots (QEMU, -icount
# shift=0: the PMU's instruction count is exact). The kernel command line says which CPU it is
# (suite.cpu=n1, sve256, ...) and which checks to run (suite.checks=all or kernels). Every file
# goes to the host over the one serial port between "@@begin NAME@@" and "@@end NAME@@" lines;
# scripts/arm64-vm/check.py judges them. The guest's own verdict (every run finished) is the
# section guest/verdict; then the machine powers off.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
echo 1 > /proc/sys/kernel/printk  # only emergencies between the data lines
stty -F /dev/ttyAMA0 raw -echo
exec 3>/dev/ttyAMA0
verdict=0
say() { echo "arm64-vm guest: $*"; }
arg() { tr ' ' '\n' < /proc/cmdline | sed -n "s/^suite\.$1=//p"; }
cpu=$(arg cpu) checks=$(arg checks)
say "init started $(cut -d' ' -f1 /proc/uptime) s after the kernel; cpu $cpu, checks $checks"
. /guest-lib.sh

# run NAME ARGS...: one suite command; its status, stderr and result file (--out=/tmp/NAME.json
# where it writes one) go to the host. A failure is judged there (some are meant to fail).
run() {
    name=$1
    shift
    /suite "$@" > "/tmp/$name.stdout" 2> "/tmp/$name.stderr"
    echo $? > "/tmp/$name.status"
    for f in status stderr json; do [ -f "/tmp/$name.$f" ] && send "$name/$f" "/tmp/$name.$f"; done
    rm -f "/tmp/$name.json"
}

# The machine as the guest sees it: CPU, the PMU's events, SVE's vector length, the NUMA nodes.
for key in 'CPU implementer' 'CPU part' Features; do grep -m1 "^$key" /proc/cpuinfo; done > /tmp/cpu
echo "sve_default_vector_length=$(cat /proc/sys/abi/sve_default_vector_length 2> /dev/null || echo none)" >> /tmp/cpu
send guest/cpu /tmp/cpu
for pmu in /sys/bus/event_source/devices/armv8*; do
    [ -d "$pmu/events" ] || continue
    for e in "$pmu"/events/*; do echo "${pmu##*/} ${e##*/} $(cat "$e")"; done
done > /tmp/pmu
send guest/pmu /tmp/pmu
send_nodes
if /suite info --json > /tmp/info.json 2> /tmp/info.err; then send info/json /tmp/info.json; else say "suite info failed: $(cat /tmp/info.err)"; verdict=1; fi
/suite list --json > /tmp/kernels.json && send guest/kernels /tmp/kernels.json

# 1. The kernels whose code differs by instruction set (the stream kernels, NEON or SVE, and
# peak-flops), every pattern and variant at its test size with 1 and 2 threads: the registry walk
# of the unit tests, run here on this CPU. The other kernels are plain C++, verified by the same
# walk under qemu-user; here it would take most of an hour.
if [ -x /suite_tests ]; then
    filter=
    for k in $(cat /registry-kernels); do filter="$filter:AllKernels/Registry.*/${k}_*"; done
    /suite_tests --gtest_filter="${filter#:}" --gtest_brief=1 \
        --gtest_output=json:/tmp/registry.json > /tmp/registry.out 2>&1
    echo $? > /tmp/registry.status
    send registry/status /tmp/registry.status
    send registry/json /tmp/registry.json
    tail -n 30 /tmp/registry.out > /tmp/registry.tail
    send registry/tail /tmp/registry.tail
fi

# 3. Instructions per element: copy, triad and add at two sizes, one pinned thread. The sizes
# give whole unrolled steps for both two- and three-array kernels (1.5 M and 3 M elements of copy,
# 1 M and 2 M of triad and add), and calls of over a million instructions: one emulated ms, so the
# runner times them one at a time (batch 1) at both sizes, and what a repetition costs besides its
# calls (the fork and join, the reads of the clock and the counters) weighs the same on both.
# libpfm4 names the Neoverse N1's events; the "max" CPU is no core it knows, so there the generic
# names encode the same two events. As root the count includes kernel mode (the timer interrupts);
# the user-mode count (:u) beside it is the loop's. QEMU's instruction counter under -icount is the
# machine's, not the CPU's: while CPU 1 runs (its timer ticks) its instructions count on CPU 0 too,
# so CPU 1 is offline for these runs.
if [ "$cpu" = n1 ]; then ipc_events=INST_RETIRED,CPU_CYCLES,INST_RETIRED:u; else ipc_events=instructions,cycles,instructions:u; fi
# 512-bit SVE does a call in fewer instructions: twice the sizes keep it over a million.
sizes=24MiB,48MiB
[ "$cpu" = sve512 ] && sizes=48MiB,96MiB
echo 0 > /sys/devices/system/cpu/cpu1/online
for k in copy triad add; do
    run "ipe-$k" --kernel=$k --pattern=sequential --sizes=$sizes --threads=1 --pin=0 --reps=3 \
        --counters=$ipc_events --quiet --out="/tmp/ipe-$k.json"
done
echo 1 > /sys/devices/system/cpu/cpu1/online

if [ "$checks" = all ]; then
    # 4. Multiplexing: ten events on the PMU's seven counters, against the same ten read five at a
    # time (no multiplexing). Only the instruction and cycle counts are non-zero under QEMU, so
    # the ten are those two under five names each. peak-flops: a long repetition (about 40 M
    # instructions), over which the kernel rotates the events many times.
    mux=instructions,INST_RETIRED,arm_n1::INST_RETIRED,PERF_COUNT_HW_INSTRUCTIONS,INST_RETIRED:u
    mux2=cycles,CPU_CYCLES,arm_n1::CPU_CYCLES,PERF_COUNT_HW_CPU_CYCLES,CPU_CYCLES:u
    peak="--kernel=peak-flops --isa=scalar --size=3000000 --threads=1 --pin=0 --reps=5 --quiet"
    run mux-10 $peak --counters=$mux,$mux2 --out=/tmp/mux-10.json
    run mux-5a $peak --counters=$mux --out=/tmp/mux-5a.json
    run mux-5b $peak --counters=$mux2 --out=/tmp/mux-5b.json
    # The same with repetitions of about 1 M instructions (1 emulated ms), shorter than the 4 ms
    # rotation: an event may be off the PMU for a whole repetition, which then has no value for it.
    short="--kernel=triad --size=768KiB --threads=1 --pin=0 --reps=20 --quiet"
    run muxs-10 $short --counters=$mux,$mux2 --out=/tmp/muxs-10.json
    run muxs-5a $short --counters=$mux --out=/tmp/muxs-5a.json
    run muxs-5b $short --counters=$mux2 --out=/tmp/muxs-5b.json

    # 5. Events this PMU does not implement: a raw one the kernel would open (it reads 0 on QEMU)
    # and a generic one the kernel maps to it.
    run absent --kernel=triad --size=96KiB --threads=1 --pin=0 --reps=2 \
        --counters=INST_RETIRED,L1D_CACHE_REFILL,L1-dcache-load-misses --quiet --out=/tmp/absent.json

    # 6. Migrations and page faults inside the timing, pinned, 1 and 2 threads.
    run quiet1 --kernel=triad --size=768KiB --threads=1 --pin=0 --reps=5 \
        --counters=cpu-migrations,page-faults,INST_RETIRED --quiet --out=/tmp/quiet1.json
    run quiet2 --kernel=triad --size=768KiB --threads=2 --pin=compact --reps=5 \
        --counters=cpu-migrations,page-faults,INST_RETIRED --quiet --out=/tmp/quiet2.json

    # 2. Pinning and first-touch placement on the two nodes: test-numa's scenarios with base
    # pages, at 30 MiB (three 10 MiB arrays, larger than a thread's 8 MiB stack), judged from the
    # result files. The snapshot of page frames stays test-numa's: under aarch64 emulation it
    # takes longer than the runs, which would have to last minutes for it.
    echo never > /sys/kernel/mm/transparent_hugepage/enabled
    SCENARIO_MIN_TIME=0.05 SCENARIO_SNAPSHOT=no
    scenario local2 30 --threads=2 --pin=compact --placement=local
    scenario node1 30 --threads=1 --pin=0 --placement=node:1
    scenario remote 30 --threads=1 --pin=0 --placement=remote
    scenario interleave 30 --threads=1 --pin=0 --placement=interleave
    scenario pin1 30 --threads=1 --pin=1 --placement=local
fi

echo "$verdict" > /tmp/verdict
send guest/verdict /tmp/verdict
exec 3>&-
say "verdict $verdict, $(cut -d' ' -f1 /proc/uptime) s after the kernel started"
poweroff -f
