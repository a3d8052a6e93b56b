# Shared by the /init of both emulated machines (scripts/numa-vm/init.sh: x86-64, and
# scripts/arm64-vm/init.sh: aarch64), which source it from the initramfs: sending files to the
# host, the snapshot of a running suite's pages, and the placement scenarios that
# scripts/numa-vm/check.py judges. The caller opens file descriptor 3 on the port that carries
# the results, and sets verdict=0; SCENARIO_MIN_TIME (seconds, default 1) is each run's --min-time;
# SCENARIO_SNAPSHOT=no runs each scenario without the snapshot (the result file only).

# send NAME FILE: one file to the host, between markers.
send() {
    echo "@@begin $1@@" >&3
    cat "$2" >&3
    echo "" >&3
    echo "@@end $1@@" >&3
}

# anon_pages PID: resident anonymous pages of the process, summed over its mappings.
anon_pages() {
    awk '{ for (i = 2; i <= NF; i++) if (substr($i, 1, 5) == "anon=") s += substr($i, 6) } END { print s + 0 }' \
        "/proc/$1/numa_maps" 2>/dev/null || echo 0
}

# snapshot PID DIR MINBYTES: the process's mappings and, for each private anonymous read-write
# mapping of at least MINBYTES (the arrays), the pagemap entry of every page (physical frame ->
# node is worked out on the host from the memory blocks of each node). Raw reads first, while
# the process runs; the conversion to text (slow under emulation) after it.
snapshot() {
    cat "/proc/$1/maps" > "$2/maps"
    awk '$2 == "rw-p" && $5 == "0" && NF == 5 { split($1, r, "-"); print r[1], r[2] }' "$2/maps" > "$2/vmas"
    while read -r lo hi; do
        [ $((0x$hi - 0x$lo)) -lt "$3" ] && continue
        dd if="/proc/$1/pagemap" of="$2/pm-$lo-$hi" bs=65536 iflag=skip_bytes,count_bytes,fullblock \
            skip=$((0x$lo / 4096 * 8)) count=$(((0x$hi - 0x$lo) / 4096 * 8)) 2>/dev/null
    done < "$2/vmas"
    cat "/proc/$1/numa_maps" > "$2/numa_maps"
    grep AnonHugePages "/proc/$1/smaps_rollup" > "$2/thp"
    # Each thread's allowed CPUs and the CPU it last ran on (field 39 of stat), from the kernel.
    for t in /proc/"$1"/task/*; do
        echo "${t##*/} $(awk '/^Cpus_allowed_list/ { print $2 }' "$t/status") $(awk '{ print $39 }' "$t/stat")"
    done > "$2/tasks"
}

# pagemap_text DIR: the raw pagemap reads as hexadecimal words, one "vma LO HI" line before each.
pagemap_text() {
    for f in "$1"/pm-*; do
        [ -f "$f" ] || continue
        range=${f##*/pm-}
        echo "vma ${range%-*} ${range#*-}"
        od -An -v -tx8 "$f"
    done > "$1/pagemap"
}

# scenario NAME SIZE_MIB SUITE-OPTIONS...: runs triad with those options in the background; once
# its arrays are all touched (resident anonymous pages reach the footprint and stay put for one
# poll) takes the snapshot, lets the run finish and sends everything.
scenario() {
    name=$1 mib=$2
    shift 2
    d=/tmp/$name
    mkdir -p "$d"
    /suite --kernel=triad --pattern=sequential --size="${mib}MiB" --min-time="${SCENARIO_MIN_TIME:-1}" --quiet --out="$d/result.json" "$@" \
        > "$d/stdout" 2> "$d/stderr" &
    pid=$!
    want=$((mib * 256 * 98 / 100)) prev=-1 taken=no
    [ "${SCENARIO_SNAPSHOT:-yes}" = no ] && taken="not asked" want=-1  # nothing to wait for
    while [ "$want" -ge 0 ] && kill -0 "$pid" 2>/dev/null; do
        n=$(anon_pages "$pid")
        if [ "$n" -ge "$want" ] && [ "$n" = "$prev" ]; then
            snapshot "$pid" "$d" $((mib * 1024 * 1024 / 3 * 9 / 10))
            # Still running after the reads: they saw the arrays, not a process tearing down.
            kill -0 "$pid" 2>/dev/null && taken=yes || taken="too late, the run had ended"
            break
        fi
        prev=$n
        sleep 0.1
    done
    wait "$pid"
    rc=$?
    say "$name: suite $* exited $rc, snapshot taken: $taken"
    [ "$rc" = 0 ] && { [ "$taken" = yes ] || [ "$taken" = "not asked" ]; } || verdict=1
    echo "$rc" > "$d/status"
    pagemap_text "$d"
    for f in status stderr result.json maps numa_maps thp tasks pagemap; do
        [ -f "$d/$f" ] && send "$name/$f" "$d/$f"
    done
}

# send_nodes: the kernel's own view of the machine, to hold the suite's topology against.
send_nodes() {
    for n in /sys/devices/system/node/node[0-9]*; do
        echo "$(basename "$n") cpus=$(cat "$n/cpulist") distance=$(cat "$n/distance" | tr ' ' ,) blocks=$(cd "$n" && ls -d memory[0-9]* | tr '\n' ' ')"
    done > /tmp/nodes
    echo "block_size_bytes=$(cat /sys/devices/system/memory/block_size_bytes)" >> /tmp/nodes
    echo "hpage_pmd_size=$(cat /sys/kernel/mm/transparent_hugepage/hpage_pmd_size)" >> /tmp/nodes
    echo "numa_balancing=$(cat /proc/sys/kernel/numa_balancing)" >> /tmp/nodes
    echo "thp_default=$(cat /sys/kernel/mm/transparent_hugepage/enabled)" >> /tmp/nodes
    send guest/nodes /tmp/nodes
}
