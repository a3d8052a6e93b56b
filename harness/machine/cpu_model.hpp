#pragma once
// The processor's name on an Arm CPU, which has no brand string: Linux prints the fields of its
// Main ID Register (MIDR_EL1) in /proc/cpuinfo ("CPU implementer", "CPU part", "CPU variant",
// "CPU revision"), and aarch64 kernels often print no "model name". A table of the common server
// and desktop cores names them; any other is named by its raw fields, never guessed.
#include <string>

namespace suite {

// "Arm Neoverse-N1 (MIDR implementer 0x41 part 0xd0c r3p1)" for a core in the table;
// "Arm core part 0xd99 (MIDR implementer 0x41 part 0xd99 r0p0; not in suite's table)" otherwise;
// "" where `cpuinfo` (the text of /proc/cpuinfo) has no implementer and part.
std::string arm_cpu_model(const std::string& cpuinfo);

}  // namespace suite
