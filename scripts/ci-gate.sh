#!/usr/bin/env bash
# The CI gate's small configurations, in one place (.github/workflows/gate.yml, docs/results-tools.md
# and results/baseline/README.md refer to this file). Run from the top of the tree after
# `make build` (the deterministic one builds the valgrind twin it needs).
#   scripts/ci-gate.sh timing OUT.json          # timed, one thread, about 20 s
#   scripts/ci-gate.sh deterministic OUT.json   # under valgrind's callgrind, exact counts, about 15 s
# The baselines in results/baseline/ were written by these same commands.
#
# Timing sizes sit well inside a cache level or far past the last one, never on an edge: at an
# edge a point flips between two levels from run to run (a 4 MiB latency point on a VM whose
# measured last level moves between 6 and 19 MiB changed 12x between unchanged runs). 8 KiB is
# a quarter of the smallest L1 data cache in use; 128 KiB is 4x an L1 of 32 KiB and a fifth of
# an L2 of 640 KiB or more; 256 MiB is 13x the largest last level measured on the CI VM. After
# the run, the sizes are checked against this machine's measured caches and any size within 2x
# of an edge is named on stderr (the gate still runs: the baseline's sizes must stay fixed).
set -euo pipefail
if [ $# -ne 2 ] || { [ "$1" != timing ] && [ "$1" != deterministic ]; }; then
  echo "usage: scripts/ci-gate.sh timing|deterministic OUT.json" >&2
  exit 2
fi
BUILD=${BUILD:-build}
PYTHON=${PYTHON:-/usr/bin/python3}
case "$1" in
  timing)
    sizes=8KiB,128KiB,256MiB
    ./suite --kernel=triad,add,latency --pattern=sequential,random --sizes="$sizes" --threads=1 --quiet --out="$2"
    # Where this machine's caches really end (a probe of about 2 s), against the sizes used.
    probe=$(mktemp)
    trap 'rm -f "$probe"' EXIT
    if ./suite info --probe --json > "$probe" 2>/dev/null; then
      "$PYTHON" - "$probe" "$sizes" <<'EOF' || true
import json, sys
m = json.load(open(sys.argv[1])).get("caches_measured") or {}
edges = [l["capacity_bytes"] for l in m.get("levels", []) if l.get("capacity_bytes")]
units = {"KiB": 1 << 10, "MiB": 1 << 20, "GiB": 1 << 30}
for s in sys.argv[2].split(","):
    n = int(s[:-3]) * units[s[-3:]]
    for e in edges:
        # footprints of the gated kernels: triad and add touch three arrays of this total size
        if e / 2 < n < e * 2:
            print(f"ci-gate: size {s} is within 2x of a measured cache edge ({e / 1024:.0f} KiB) on this machine: "
                  f"its timings may flip between levels; gate on a runner whose caches clear it", file=sys.stderr)
EOF
    fi
    ;;
  deterministic)
    # valgrind 3.19 cannot decode AVX-512: the x86-64-v3 build (SUITE_V3 names another one).
    twin=${SUITE_V3:-$BUILD/suite-x86-64-v3}
    if [ -z "${SUITE_V3:-}" ] && [ ! -x "$twin" ]; then
      command -v valgrind > /dev/null || { echo "ci-gate: the deterministic gate needs valgrind (apt-get install valgrind, or make test-deps)" >&2; exit 2; }
      # Configured after valgrind was installed, so that the twin's target exists.
      cmake -S . -B "$BUILD" > /dev/null
      cmake --build "$BUILD" -j "$(nproc)" --target suite-x86-64-v3
    fi
    "$twin" deterministic --kernel=triad,add,latency --pattern=sequential,random \
      --sizes=16KiB,1MiB,16MiB --out="$2"
    ;;
esac
