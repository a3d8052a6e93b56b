#!/bin/busybox sh
# /init of the emulated two-node NUMA machine that scripts/numa-vm/run.sh boots. It runs the
# suite's placement scenarios and sends each result file, with a snapshot of where the running
# suite's pages are (/proc/PID/maps, numa_maps, pagemap), to the host over the second serial port
# between "@@begin NAME@@" and "@@end NAME@@" lines; the host (check.py) judges them. The guest's
# own verdict (every run exited 0, every snapshot was taken) leaves through isa-debug-exit:
# QEMU exits with status 1 for "all ran", 3 for "something did not".
/bin/busybox --install -s /bin
export PATH=/bin LD_LIBRARY_PATH=/lib/x86_64-linux-gnu
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
stty -F /dev/ttyS1 raw -echo
exec 3>/dev/ttyS1
verdict=0
say() { echo "numa-vm guest: $*"; }
say "init started $(cut -d' ' -f1 /proc/uptime) s after the kernel"

. /guest-lib.sh
send_nodes
if /suite info --json > /tmp/info.json 2> /tmp/info.err; then send info/json /tmp/info.json; else say "suite info failed: $(cat /tmp/info.err)"; verdict=1; fi

# Base pages first: every page is placed on its own, so the checks can be exact. 48 MiB of
# triad is three 16 MiB arrays: larger than a thread's 8 MiB stack, which must not pass for one.
echo never > /sys/kernel/mm/transparent_hugepage/enabled
scenario local2 48 --threads=2 --pin=compact --placement=local
scenario node1 48 --threads=1 --pin=0 --placement=node:1
scenario remote 48 --threads=1 --pin=0 --placement=remote
scenario interleave 48 --threads=1 --pin=0 --placement=interleave
scenario pin1 48 --threads=1 --pin=1 --placement=local
# Then Debian's default, transparent huge pages always: placement in 2 MiB units, larger arrays.
echo always > /sys/kernel/mm/transparent_hugepage/enabled
scenario thp-local2 96 --threads=2 --pin=compact --placement=local
scenario thp-interleave 96 --threads=1 --pin=0 --placement=interleave

echo "$verdict" > /tmp/verdict
send guest/verdict /tmp/verdict
exec 3>&-  # the last close of the port waits until everything is sent
say "verdict $verdict, $(cut -d' ' -f1 /proc/uptime) s after the kernel started"
printf "\\$verdict" | dd of=/dev/port bs=1 seek=244 count=1 2>/dev/null
# Not reached when isa-debug-exit is present; without it, end the machine anyway.
poweroff -f
