#include "harness/results/context.hpp"

#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>
#if defined(__x86_64__)
#include <cpuid.h>
#elif defined(__aarch64__)
#include <sys/auxv.h>
#include <sys/prctl.h>
#endif

#include <chrono>
#include <fstream>

#include <nlohmann/json.hpp>

#include "harness/common/sysfs_file.hpp"
#include "harness/results/build_info.hpp"

namespace suite {

namespace {

// The first line of a sysfs file; "" when it cannot be read as one (read_attribute).
std::string read_first_line(const std::string& path) { return read_attribute(path).text; }

// "always [madvise] never" -> "madvise".
std::string bracketed_choice(const std::string& line) {
    auto open = line.find('['), close = line.find(']');
    if (open == std::string::npos || close == std::string::npos || close < open) return line;
    return line.substr(open + 1, close - open - 1);
}

// A setting that may be unreadable: {"value": ...} or {"value": null, "reason": ...}.
nlohmann::json readable(const std::string& path, bool bracketed, const std::string& why_missing) {
    std::string line = read_first_line(path);
    if (line.empty()) return {{"value", nullptr}, {"reason", why_missing + "; " + path + " is not readable"}};
    return {{"value", bracketed ? bracketed_choice(line) : line}, {"source", path}};
}

double timer_resolution_ns() {
    timespec res{};
    clock_getres(CLOCK_MONOTONIC, &res);
    return static_cast<double>(res.tv_sec) * 1e9 + static_cast<double>(res.tv_nsec);
}

std::string utc_now() {
    std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

std::string cpu_model_fallback() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            auto colon = line.find(':');
            return colon == std::string::npos ? "" : line.substr(colon + 2);
        }
    return "";
}

// The CPU's fast-string features, which decide how fast the rep variants (rep movsb, rep stosq)
// run: ERMS (enhanced rep movsb/stosb) and FSRM (fast short rep mov), from CPUID leaf 7.
#if defined(__x86_64__)
nlohmann::json string_ops_context() {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (!__get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx))
        return {{"erms", nullptr}, {"fsrm", nullptr}, {"reason", "this CPU has no CPUID leaf 7"}};
    return {{"erms", ((ebx >> 9) & 1u) != 0},
            {"fsrm", ((edx >> 4) & 1u) != 0},
            {"source", "CPUID leaf 7: EBX bit 9, EDX bit 4"}};
}
#endif

// What the kernels' vector code is. x86-64: what -march resolved to, as the compiler saw it when
// it built the kernels. aarch64: NEON is the baseline of every build; SVE is the CPU's (HWCAP),
// and where it has SVE the stream kernels and peak-flops run their SVE twins at its vector length.
nlohmann::json instruction_set_context() {
#if defined(__x86_64__) || defined(__i386__)
    nlohmann::json is = {{"arch", "x86_64"}};
#ifdef __AVX512F__
    is["avx512f"] = true;
#else
    is["avx512f"] = false;
#endif
#ifdef __AVX2__
    is["avx2"] = true;
#else
    is["avx2"] = false;
#endif
#ifdef __FMA__
    is["fma"] = true;
#else
    is["fma"] = false;
#endif
#if defined(__AVX512F__)
    is["nt_store_bits"] = 512;
#elif defined(__AVX__)
    is["nt_store_bits"] = 256;
#else
    is["nt_store_bits"] = 128;
#endif
    return is;
#elif defined(__aarch64__)
    const bool sve = (getauxval(AT_HWCAP) & HWCAP_SVE) != 0;
    const int vl_bits = sve ? (prctl(PR_SVE_GET_VL) & PR_SVE_VL_LEN_MASK) * 8 : 0;
    nlohmann::json is = {{"arch", "aarch64"}, {"neon", true}, {"sve", sve}};
    is["sve_vector_bits"] = sve ? nlohmann::json(vl_bits) : nlohmann::json(nullptr);
    is["nt_store_bits"] = sve ? vl_bits : 128;
    is["source"] = "SVE and its vector length from the CPU (HWCAP, prctl PR_SVE_GET_VL)";
    return is;
#else
#error "the instruction set is recorded for x86-64 and aarch64"
#endif
}

}  // namespace

nlohmann::json build_context(const Topology& topo, const std::vector<std::string>& argv, const Instruments& instruments,
                             const std::string& bandwidth_convention) {
    nlohmann::json c;
    c["suite_version"] = build::version;
    c["git_revision"] = build::git_revision;
    c["compiler"] = build::compiler;
    c["compiler_flags"] = build::flags;
    c["build_type"] = build::build_type;
    c["instruction_set"] = instruction_set_context();
#if defined(__x86_64__)
    c["string_ops"] = string_ops_context();  // the rep variants' speed; they are x86-64 only
#endif
    c["date"] = utc_now();
    char host[256] = {0};
    gethostname(host, sizeof host - 1);
    c["host"] = host;
    c["command_line"] = argv;
    c["cpu_model"] = topo.cpu_model.empty() ? cpu_model_fallback() : topo.cpu_model;
    c["sockets"] = topo.packages;
    c["cores"] = topo.cores;
    c["pus"] = topo.pu_count();
    c["numa_node_count"] = topo.nodes.size();
    c["topology"] = to_json(topo);
    utsname u{};
    uname(&u);
    c["os_kernel"] = std::string(u.sysname) + " " + u.release;
    c["memory_bytes"] =
        static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) * static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
    c["page_size_bytes"] = sysconf(_SC_PAGESIZE);
    c["transparent_hugepages"] = readable("/sys/kernel/mm/transparent_hugepage/enabled", true, "THP setting unknown");
    c["frequency_governor"] = readable("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor", false,
                                       "no cpufreq driver exposes a governor here (common in VMs)");
    c["instruments"] = instruments_context(instruments, timer_resolution_ns());
    c["conventions"] = {
        {"bandwidth", bandwidth_convention},
        {"gigabyte", "1 GB/s = 1e9 B/s"},
        {"hardware_bytes",
         "estimate of memory-system traffic: +1 read per store (write-allocate) unless non-temporal or a string "
         "instruction (rep), "
         "4 B per index for random, whole 64 B lines for random and wide-strided accesses"},
        {"headline",
         "best = minimum time over the counted repetitions; the first repetition is a warm-up, not counted"},
        {"timing", "monotonic clock around the whole parallel region, barriers included"},
    };
    return c;
}

}  // namespace suite
