# Cross build for 64-bit Arm (aarch64) from an x86-64 Debian host: Debian's cross compiler
# (g++-aarch64-linux-gnu) and the arm64 libraries installed beside the host's (multiarch:
# /usr/lib/aarch64-linux-gnu), as `scripts/install-deps.sh arm64` installs them.
# Used by `make build-arm64`; on an Arm host no toolchain file is needed.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Libraries and headers of the target only; programs (pkg-config, python) of the host.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
# The tests run under QEMU's user-mode emulation (qemu-user-static), with the arm64 loader and
# libraries where multiarch put them.
find_program(SUITE_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64)
if(SUITE_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${SUITE_QEMU_AARCH64})
endif()
# Debian's libmetis-dev is one architecture at a time (not Multi-Arch: same): the host's stays,
# and the cross build links the arm64 runtime library (libmetis5:arm64) with the host's metis.h.
if(EXISTS /usr/lib/aarch64-linux-gnu/libmetis.so.5 AND NOT EXISTS /usr/lib/aarch64-linux-gnu/libmetis.so)
  set(METIS_LIBRARY /usr/lib/aarch64-linux-gnu/libmetis.so.5 CACHE FILEPATH "the arm64 METIS runtime library")
endif()
# GCC notes, for Boost.Math's std::pair<long double, long double>, that GCC 10.1 changed how such
# an argument is passed: it matters only when code built by GCC 9 or older is linked in, which no
# part of this build is.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
