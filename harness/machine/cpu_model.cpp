#include "harness/machine/cpu_model.hpp"

#include <cstdio>
#include <sstream>

namespace suite {
namespace {

struct Implementer {
    unsigned id;
    const char* name;
};
// JEP106-style implementer codes of the Arm architecture reference manual (MIDR_EL1.Implementer).
constexpr Implementer implementers[] = {{0x41, "Arm"},       {0x42, "Broadcom"}, {0x43, "Cavium"}, {0x46, "Fujitsu"},
                                        {0x48, "HiSilicon"}, {0x4e, "NVIDIA"},   {0x50, "APM"},    {0x51, "Qualcomm"},
                                        {0x61, "Apple"},     {0xc0, "Ampere"}};

struct Core {
    unsigned implementer, part;
    const char* name;
};
// The cores HPC and cloud servers are built on, and the common Cortex cores. Servers by core:
// AWS Graviton2 N1, Graviton3 V1, Graviton4 V2; NVIDIA Grace V2; Ampere Altra N1; Fujitsu A64FX.
constexpr Core cores[] = {
    {0x41, 0xd03, "Cortex-A53"},  {0x41, 0xd07, "Cortex-A57"},  {0x41, 0xd08, "Cortex-A72"},
    {0x41, 0xd09, "Cortex-A73"},  {0x41, 0xd0a, "Cortex-A75"},  {0x41, 0xd0b, "Cortex-A76"},
    {0x41, 0xd0c, "Neoverse-N1"}, {0x41, 0xd0d, "Cortex-A77"},  {0x41, 0xd40, "Neoverse-V1"},
    {0x41, 0xd41, "Cortex-A78"},  {0x41, 0xd44, "Cortex-X1"},   {0x41, 0xd46, "Cortex-A510"},
    {0x41, 0xd47, "Cortex-A710"}, {0x41, 0xd48, "Cortex-X2"},   {0x41, 0xd49, "Neoverse-N2"},
    {0x41, 0xd4a, "Neoverse-E1"}, {0x41, 0xd4f, "Neoverse-V2"}, {0x41, 0xd80, "Cortex-A520"},
    {0x41, 0xd81, "Cortex-A720"}, {0x41, 0xd82, "Cortex-X4"},   {0x41, 0xd84, "Neoverse-V3"},
    {0x41, 0xd8e, "Neoverse-N3"}, {0x43, 0x0a1, "ThunderX"},    {0x43, 0x0af, "ThunderX2"},
    {0x46, 0x001, "A64FX"},       {0x48, 0xd01, "Kunpeng-920"}, {0xc0, 0xac3, "Ampere-1"},
    {0xc0, 0xac4, "Ampere-1A"},   {0x4e, 0x004, "Carmel"},
};

// The value of the first line "key<spaces/tabs>: value", parsed as a number (0x.. or decimal).
bool field(const std::string& text, const std::string& key, unsigned& out) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind(key, 0) != 0) continue;
        const auto colon = line.find(':');
        if (colon == std::string::npos || line.find_first_not_of(" \t", key.size()) != colon) continue;
        try {
            out = static_cast<unsigned>(std::stoul(line.substr(colon + 1), nullptr, 0));
            return true;
        } catch (const std::exception&) {
            return false;
        }
    }
    return false;
}

std::string hex(unsigned v, int digits) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%0*x", digits, v);
    return buf;
}

}  // namespace

std::string arm_cpu_model(const std::string& cpuinfo) {
    unsigned impl = 0, part = 0, variant = 0, revision = 0;
    if (!field(cpuinfo, "CPU implementer", impl) || !field(cpuinfo, "CPU part", part)) return "";
    field(cpuinfo, "CPU variant", variant);
    field(cpuinfo, "CPU revision", revision);
    const std::string midr = "MIDR implementer " + hex(impl, 2) + " part " + hex(part, 3) + " r" +
                             std::to_string(variant) + "p" + std::to_string(revision);
    std::string vendor = "implementer " + hex(impl, 2);
    for (const auto& i : implementers)
        if (i.id == impl) vendor = i.name;
    for (const auto& c : cores)
        if (c.implementer == impl && c.part == part) return vendor + " " + c.name + " (" + midr + ")";
    return vendor + " core part " + hex(part, 3) + " (" + midr + "; not in suite's table)";
}

}  // namespace suite
