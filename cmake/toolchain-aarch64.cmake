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
