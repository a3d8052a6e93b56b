#!/usr/bin/env bash
# The CI gate's small configurations, in one place (the workflow in docs/ci-workflow.yml, the
# docs/results-tools.md and results/baseline/README.md refer to this file). Run from the top of the tree after
# a build.
#   scripts/ci-gate.sh timing OUT.json          # timed, one thread, about 10 s
#   scripts/ci-gate.sh deterministic OUT.json   # under valgrind's callgrind, exact counts, about 15 s
# The baselines in results/baseline/ were written by these same commands.
set -euo pipefail
if [ $# -ne 2 ] || { [ "$1" != timing ] && [ "$1" != deterministic ]; }; then
  echo "usage: scripts/ci-gate.sh timing|deterministic OUT.json" >&2
  exit 2
fi
case "$1" in
  timing)
    ./suite --kernel=triad,add,latency --pattern=sequential,random --sizes=64KiB,4MiB,64MiB --threads=1 --quiet --out="$2"
    ;;
  deterministic)
    # valgrind 3.19 cannot decode AVX-512: the x86-64-v3 build (built beside ./suite when valgrind
    # is installed; SUITE_V3 names another one).
    "${SUITE_V3:-build/suite-x86-64-v3}" deterministic --kernel=triad,add,latency --pattern=sequential,random \
      --sizes=16KiB,1MiB,16MiB --out="$2"
    ;;
esac
