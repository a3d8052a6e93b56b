#!/usr/bin/env bash
# Installs the Debian packages the suite needs, if any is missing. As root it runs apt-get;
# otherwise it prints the one command to run and exits 2. Usage: scripts/install-deps.sh [build|run|test|bench|arm64]
set -euo pipefail
want=(build-essential cmake pkg-config git libhwloc-dev libnuma-dev libpfm4-dev libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev)
want+=(libboost-graph-dev libboost-dev)  # RCM ordering (kernels/sfc); Boost.Math headers for the history gate's band
want+=(libsuitesparse-dev libmetis-dev)  # suite matrix: AMD, CHOLMOD, nested dissection
want+=(libsqlite3-dev)  # suite history: the database of every run added
if [ "${1:-build}" = run ] || [ "${1:-build}" = test ]; then
  # make run draws the default sweep's figures (plots/plot.py); `suite history html` copies
  # Debian's Chart.js beside its page.
  want+=(python3 python3-matplotlib python3-numpy libjs-chart.js)
fi
if [ "${1:-build}" = test ]; then
  # binutils: objdump proves the non-temporal stores; python3-jsonschema validates results;
  # python3-yaml reads the CI workflow (tests/workflow_test.py); clang-format keeps the tree formatted;
  # clang + compiler-rt build the libFuzzer targets; valgrind: the deterministic mode (its header
  # also makes the build add suite-x86-64-v3); matplotlib: plots/plot.py and `suite traverse` PNGs.
  want+=(binutils python3 python3-jsonschema python3-yaml clang clang-format libclang-rt-dev valgrind python3-matplotlib python3-numpy python3-scipy)
  # make test-numa: an emulated two-node machine (the kernel itself is fetched by scripts/numa-vm/run.sh).
  want+=(qemu-system-x86 busybox-static cpio)
  # The history page drawn in a real browser (tests/dashboard_browser_test.py), with its Chart.js.
  want+=(chromium libjs-chart.js)
  # suite mpm's particle snapshots read back by meshio (tests/check_mpm_vtu.py).
  want+=(python3-meshio)
  # suite-mpi, the MPI mode (optional in the build; tests/mpi_test.py runs it with mpirun -np 2).
  want+=(libopenmpi-dev openmpi-bin)
  # tests/install_test.py: what the installed programs open, traced (nothing in the source tree).
  want+=(strace)
  # Eigen's headers: suite-spmv-eigen (make bench-spmv) is built, and CTest's spmv_eigen checks every
  # fem-spmv product, SELL-C-σ's included, against Eigen's.
  want+=(libeigen3-dev)
fi
if [ "${1:-build}" = arm64 ] || [ "${1:-build}" = test ]; then
  # make build-arm64 / make test-arm64: the aarch64 cross build (Debian's cross compiler and the
  # arm64 libraries beside the host's, multiarch), its unit tests under qemu-user, and the
  # emulated Arm machine with a PMU (qemu-system-aarch64). The arm64 architecture is added below.
  want+=(g++-aarch64-linux-gnu binutils-aarch64-linux-gnu qemu-user-static qemu-system-arm cpio)
  want+=(libhwloc-dev:arm64 libnuma-dev:arm64 libpfm4-dev:arm64 libgtest-dev:arm64 libboost-dev:arm64)
  # Not every -dev package is multiarch: libmetis-dev and busybox-static are one architecture at a
  # time, so the host's stay (the cross build links libmetis5:arm64 with the host's metis.h, and
  # test-arm64 unpacks the arm64 busybox into its own folder).
  want+=(libboost-graph-dev:arm64 libsqlite3-dev:arm64 libsuitesparse-dev:arm64 libmetis5:arm64 libcli11-dev nlohmann-json3-dev)
fi
if [ "${1:-build}" = bench ]; then
  # likwid: likwid-bench, the hand-written assembly `make bench-vs` compares with (not needed by
  # the build or the tests).
  want+=(likwid python3)
  # Eigen: the sparse product `make bench-spmv` compares the fem SpMV with (headers, bench/ only).
  want+=(libeigen3-dev)
fi
if ! command -v dpkg-query > /dev/null; then
  echo "suite: not a Debian system, so the packages cannot be checked; CMake will name anything missing" >&2
  exit 0
fi
missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "suite: missing Debian packages; install them with:" >&2
  arch_step=""
  if printf '%s\n' "${missing[@]}" | grep -q ':arm64$' && ! dpkg --print-foreign-architectures | grep -qx arm64; then
    arch_step="sudo dpkg --add-architecture arm64 && "
  fi
  echo "  ${arch_step}sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 2
fi
echo "installing: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# The arm64 packages (name:arm64) need dpkg to know the architecture before apt's index has them.
if printf '%s\n' "${missing[@]}" | grep -q ':arm64$' && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  dpkg --add-architecture arm64
fi
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
