// The CPU's name on aarch64 from the MIDR fields of /proc/cpuinfo (harness/machine/cpu_model.cpp),
// read from the texts real Arm kernels print; runs on any host.
#include "harness/machine/cpu_model.hpp"

#include <gtest/gtest.h>

namespace {

// What Debian's arm64 kernel prints for one CPU of QEMU's neoverse-n1 (trimmed to the fields).
const char* const neoverse_n1 =
    "processor\t: 0\nBogoMIPS\t: 125.00\nFeatures\t: fp asimd evtstrm aes pmull sha1 sha2 crc32 atomics\n"
    "CPU implementer\t: 0x41\nCPU architecture: 8\nCPU variant\t: 0x3\nCPU part\t: 0xd0c\nCPU revision\t: 1\n\n"
    "processor\t: 1\nCPU implementer\t: 0x41\nCPU architecture: 8\nCPU variant\t: 0x3\nCPU part\t: 0xd0c\n";

TEST(CpuModel, NamesACoreInTheTableWithItsMidrFields) {
    EXPECT_EQ(suite::arm_cpu_model(neoverse_n1), "Arm Neoverse-N1 (MIDR implementer 0x41 part 0xd0c r3p1)");
    EXPECT_EQ(
        suite::arm_cpu_model("CPU implementer\t: 0x46\nCPU variant\t: 0x1\nCPU part\t: 0x001\nCPU revision\t: 0\n"),
        "Fujitsu A64FX (MIDR implementer 0x46 part 0x001 r1p0)");
    EXPECT_EQ(
        suite::arm_cpu_model("CPU implementer\t: 0x41\nCPU variant\t: 0x0\nCPU part\t: 0xd4f\nCPU revision\t: 0\n"),
        "Arm Neoverse-V2 (MIDR implementer 0x41 part 0xd4f r0p0)");
}

TEST(CpuModel, AnUnknownCoreIsNamedByItsRawFieldsNotGuessed) {
    EXPECT_EQ(
        suite::arm_cpu_model("CPU implementer\t: 0x41\nCPU variant\t: 0x0\nCPU part\t: 0xd99\nCPU revision\t: 2\n"),
        "Arm core part 0xd99 (MIDR implementer 0x41 part 0xd99 r0p2; not in suite's table)");
    EXPECT_EQ(suite::arm_cpu_model("CPU implementer\t: 0x7f\nCPU part\t: 0x123\n"),
              "implementer 0x7f core part 0x123 (MIDR implementer 0x7f part 0x123 r0p0; not in suite's table)");
}

TEST(CpuModel, AnX86CpuinfoHasNoMidr) {
    EXPECT_EQ(suite::arm_cpu_model("processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC\n"), "");
    EXPECT_EQ(suite::arm_cpu_model("CPU implementer\t: 0x41\n"), "");                   // no part
    EXPECT_EQ(suite::arm_cpu_model("CPU implementer\t: zz\nCPU part\t: 0xd0c\n"), "");  // not a number
}

}  // namespace
