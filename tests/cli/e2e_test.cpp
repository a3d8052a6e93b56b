// End-to-end tests of the real binary: non-temporal stores in the machine code, nothing lost
// on SIGINT/SIGTERM, random slower than sequential at DRAM size, what a result records.
#include <unistd.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

#ifdef __FMA__
#define FMA_INSTRUCTIONS_PER_UPDATE 1
#else
#define FMA_INSTRUCTIONS_PER_UPDATE 2  // a multiply and an add
#endif

namespace {

#if defined(__x86_64__)  // the aarch64 binary's instructions: tests/arm64/disasm_test.py
// objdump's disassembly of the suite binary, split into (demangled function name, body).
std::vector<std::pair<std::string, std::string>> disassembly() {
    Outcome r;
    {
        int o, e;
        pid_t pid = spawn({"/usr/bin/objdump", "-d", "-C", "--no-show-raw-insn", SUITE_BINARY}, o, e);
        r = finish(pid, o, e, 120);
    }
    EXPECT_EQ(r.status, 0) << r.err;
    std::vector<std::pair<std::string, std::string>> functions;
    std::istringstream in(r.out);
    std::string line;
    while (std::getline(in, line)) {
        auto lt = line.find(" <"), end = line.rfind(">:");
        if (lt != std::string::npos && end != std::string::npos && end > lt && line[0] != ' ')
            functions.push_back({line.substr(lt + 2, end - lt - 2), ""});
        else if (!functions.empty())
            functions.back().second += line + "\n";
    }
    return functions;
}

bool has_nt_store(const std::string& body) { return body.find("movntpd") != std::string::npos; }

#endif

json load_json(const std::string& path) { return json::parse(slurp(path)); }

}  // namespace

#if defined(__x86_64__)  // the aarch64 binary's instructions: tests/arm64/disasm_test.py
TEST(E2E, NonTemporalVariantsEmitStreamingStoresAndPlainOnesDoNot) {
    const auto functions = disassembly();
    ASSERT_FALSE(functions.empty());
    for (const std::string op : {"Copy", "Scale", "Add", "Triad"}) {
        bool nt_found = false, plain_has_nt = false, plain_seen = false;
        for (const auto& [name, body] : functions) {
            if (name.find("StreamKernel<suite::stream::(anonymous namespace)::" + op + ">::nt_store_loop") !=
                std::string::npos)
                nt_found = nt_found || has_nt_store(body);
            if (name.find("StreamKernel<suite::stream::(anonymous namespace)::" + op + ">::sequential_loop") !=
                std::string::npos) {
                plain_seen = true;
                plain_has_nt = plain_has_nt || has_nt_store(body);
            }
        }
        EXPECT_TRUE(nt_found) << op << ": no movntpd in StreamKernel<" << op << ">::nt_store_loop (or its OpenMP body)";
        EXPECT_TRUE(plain_seen) << op << ": sequential loop not found in the binary";
        EXPECT_FALSE(plain_has_nt) << op << ": the plain sequential loop should use ordinary stores";
    }
}

TEST(E2E, StoreNtEmitsStreamingStoresAndPlainStoreDoesNot) {
    // The store kernel is its own class (one array, no StreamKernel<Op>): the same check.
    bool nt_found = false, plain_seen = false, plain_has_nt = false;
    for (const auto& [name, body] : disassembly()) {
        if (name.find("suite::stream::(anonymous namespace)::Store::nt_store_loop") != std::string::npos)
            nt_found = nt_found || has_nt_store(body);
        if (name.find("suite::stream::(anonymous namespace)::Store::sequential_loop") != std::string::npos) {
            plain_seen = true;
            plain_has_nt = plain_has_nt || has_nt_store(body);
        }
    }
    EXPECT_TRUE(nt_found) << "no movntpd in Store::nt_store_loop (or its OpenMP body)";
    EXPECT_TRUE(plain_seen) << "Store::sequential_loop not found in the binary";
    EXPECT_FALSE(plain_has_nt) << "the plain store loop should use ordinary stores";
}

TEST(E2E, RepVariantsAreOneStringInstructionAndThePlainLoopsAreNot) {
    // copy-rep is one rep movsb a call, store-rep one rep stosq (the instructions of glibc's memcpy
    // and memset); the plain loops are vector moves.
    bool copy_rep = false, store_rep = false, plain_seen = false, plain_has_rep = false;
    for (const auto& [name, body] : disassembly()) {
        if (name.find("StreamKernel<suite::stream::(anonymous namespace)::Copy>::rep_copy_loop") != std::string::npos)
            copy_rep = copy_rep || body.find("rep movsb") != std::string::npos;
        if (name.find("suite::stream::(anonymous namespace)::Store::rep_store_loop") != std::string::npos)
            store_rep = store_rep || body.find("rep stos %rax") != std::string::npos;
        if (name.find("StreamKernel<suite::stream::(anonymous namespace)::Copy>::sequential_loop") !=
                std::string::npos ||
            name.find("suite::stream::(anonymous namespace)::Store::sequential_loop") != std::string::npos) {
            plain_seen = true;
            plain_has_rep = plain_has_rep || body.find("rep ") != std::string::npos;
        }
    }
    EXPECT_TRUE(copy_rep) << "no rep movsb in StreamKernel<Copy>::rep_copy_loop (or its OpenMP body)";
    EXPECT_TRUE(store_rep) << "no rep stosq in Store::rep_store_loop (or its OpenMP body)";
    EXPECT_TRUE(plain_seen) << "the plain copy and store loops not found in the binary";
    EXPECT_FALSE(plain_has_rep) << "the plain copy and store loops should be vector moves, not string instructions";
}

// load's sequential loop keeps its eight accumulators in registers of the build's widest width:
// its adds take their loads from b and nothing vector is stored to the stack. With 64-byte GCC
// vectors on an AVX2 build every add went through the stack (17.6 GB/s at 32 KiB on a Zen 3,
// against likwid-bench's 107).
TEST(E2E, LoadLoopKeepsItsAccumulatorsInRegisters) {
#if defined(__AVX512F__)
    const std::string reg = "%zmm";
#elif defined(__AVX__)
    const std::string reg = "%ymm";
#else
    const std::string reg = "%xmm";
#endif
    // vaddpd SRC,ACC,ACC (AVX) or addpd SRC,ACC (SSE2): the accumulator is the last operand.
    const std::regex add_into("addpd\\s+\\S+,(" + reg + "[0-9]+)\\s*$");
    const std::regex vector_to_stack("mov\\w*\\s+%[xyz]mm[0-9]+,-?(0x[0-9a-f]+)?\\(%rsp\\)");
    bool seen = false;
    std::set<std::string> accumulators;
    std::vector<std::string> spills;
    for (const auto& [name, body] : disassembly()) {
        // The OpenMP body, where the loop is (the function around it passes its arguments on the stack).
        if (name.find("suite::stream::(anonymous namespace)::Load::sequential_loop") == std::string::npos ||
            name.find("_omp_fn") == std::string::npos)
            continue;
        seen = true;
        std::istringstream in(body);
        std::string line;
        std::smatch m;
        while (std::getline(in, line)) {
            if (std::regex_search(line, m, add_into)) accumulators.insert(m[1]);
            if (std::regex_search(line, vector_to_stack)) spills.push_back(line);
        }
    }
    ASSERT_TRUE(seen) << "Load::sequential_loop's OpenMP body not found in the binary";
    EXPECT_GE(accumulators.size(), 8u) << "the load loop's adds should go into 8 " << reg << " registers";
    EXPECT_TRUE(spills.empty()) << "a vector stored to the stack in the load loop: " << spills.front();
}

// peak-flops: each width's timed loop is exactly its 12 independent FMAs (or, in a build without
// FMA, multiplies and adds) on registers of that width, plus the loop's counter: no load, no
// store, no spill, nothing else the compiler added.
TEST(E2E, PeakFlopsLoopsAreTwelveRegisterFmasOfTheirWidth) {
    struct Width {
        std::string isa, fma, reg;
    };
    std::vector<Width> widths = {{"Scalar", "sd", "%xmm"}, {"Sse", "pd", "%xmm"}};
#ifdef __AVX__
    widths.push_back({"Avx", "pd", "%ymm"});
#endif
#ifdef __AVX512F__
    widths.push_back({"Avx512", "pd", "%zmm"});
#endif
    const auto functions = disassembly();
    for (const auto& w : widths) {
        std::string body;
        for (const auto& [name, b] : functions)
            if (name.find("peak_loop<suite::stream::(anonymous namespace)::" + w.isa + ">") != std::string::npos)
                body = b;
        ASSERT_FALSE(body.empty()) << "peak_loop<" << w.isa << "> not found in the binary";
        // The loop: from the target of the last backward jump to that jump.
        std::vector<std::string> lines;
        std::istringstream in(body);
        for (std::string l; std::getline(in, l);)
            if (!l.empty()) lines.push_back(l);
        // A conditional jump back: "  1df48e:\tjne    1df440 <...>"; the loop starts at "  1df440:".
        const std::regex jcc(R"(^\s*([0-9a-f]+):\s+j(?!mp)[a-z]+\s+([0-9a-f]+) <)");
        std::size_t jump = lines.size(), target = lines.size();
        std::string address;
        for (std::size_t i = 0; i < lines.size(); ++i)
            if (std::smatch mt; std::regex_search(lines[i], mt, jcc) &&
                                std::stoull(mt[2], nullptr, 16) < std::stoull(mt[1], nullptr, 16))
                jump = i, address = mt[2];
        ASSERT_LT(jump, lines.size()) << w.isa << ": no backward jump in\n" << body;
        for (std::size_t i = 0; i < jump; ++i)
            if (lines[i].find(" " + address + ":") != std::string::npos) target = i;
        ASSERT_LT(target, jump) << w.isa << ": the loop's start " << address << " not found in\n" << body;
        int fmas = 0, others = 0;
        std::set<std::string> destinations;
        std::string loop;
        for (std::size_t i = target; i <= jump; ++i) {
            const std::string& l = lines[i];
            loop += l + "\n";
            EXPECT_EQ(l.substr(0, l.find('<')).find('('), std::string::npos)
                << w.isa << ": a memory operand in the loop: " << l;
#ifdef __FMA__
            if (l.find("vfmadd") != std::string::npos && l.find(w.fma + " ") != std::string::npos &&
                l.find(w.reg) != std::string::npos) {
                ++fmas;
                destinations.insert(l.substr(l.rfind('%')));
                continue;
            }
#else
            if ((l.find("mul" + w.fma) != std::string::npos || l.find("add" + w.fma) != std::string::npos) &&
                l.find(w.reg) != std::string::npos) {
                ++fmas;
                continue;
            }
#endif
            ++others;
        }
        EXPECT_EQ(fmas, 12 * (FMA_INSTRUCTIONS_PER_UPDATE)) << w.isa << ":\n" << loop;
        EXPECT_LE(others, 4) << w.isa << ": more than the loop counter in the loop:\n" << loop;
#ifdef __FMA__
        EXPECT_EQ(destinations.size(), 12u) << w.isa << ": the 12 accumulators are not 12 registers:\n" << loop;
#endif
    }
}

#endif  // x86-64

// SIGINT (Ctrl-C) and SIGTERM mid-sweep: the finished points are kept, the file is valid JSON
// saying "complete": false, and the exit status is 128 + the signal.
class Interrupt : public testing::TestWithParam<int> {};

TEST_P(Interrupt, KeepsFinishedRecordsInAValidIncompleteFile) {
    const int sig = GetParam();
    const std::string dir = make_temp_dir();
    const std::string out = dir + "/r.json";
    int o, e;
    pid_t pid =
        spawn({SUITE_BINARY, "--kernel=latency", "--sizes=64KiB,128KiB,256KiB,512KiB,1MiB,2MiB,4MiB,8MiB,16MiB,32MiB",
               "--threads=1", "--min-time=0.5", "--out=" + out},
              o, e);
    // Wait for the first record on disk, then interrupt.
    std::size_t seen = 0;
    for (int i = 0; i < 600 && seen == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (access(out.c_str(), R_OK) == 0) seen = load_json(out)["results"].size();
    }
    ASSERT_GE(seen, 1u) << "no record was written within 30 s";
    kill(pid, sig);
    Outcome r = finish(pid, o, e, 120);
    EXPECT_EQ(r.status, 128 + sig) << r.err;
    EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
    json doc = load_json(out);
    EXPECT_EQ(doc["complete"], false);
    EXPECT_GE(doc["results"].size(), seen);
    EXPECT_LT(doc["results"].size(), 10u);
    Outcome v = validate_against_schema(out);
    EXPECT_EQ(v.status, 0) << v.out << v.err;
    // No temporary file is left behind: the directory holds the result and nothing else.
    std::vector<std::string> entries;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) entries.push_back(entry.path().filename());
    EXPECT_EQ(entries, std::vector<std::string>{"r.json"});
    std::system(("rm -rf " + dir).c_str());
}

INSTANTIATE_TEST_SUITE_P(Signals, Interrupt, testing::Values(SIGINT, SIGTERM),
                         [](const testing::TestParamInfo<int>& i) {
                             return i.param == SIGINT ? std::string("SIGINT") : std::string("SIGTERM");
                         });

TEST(E2E, RandomAddIsSlowerThanSequentialAtDramSize) {
    // DRAM-sized: every one of add's arrays at least 4x the last-level cache hwloc reports.
    const std::uint64_t size = default_sizes(Topology::load(), 1).back();
    const std::string dir = make_temp_dir();
    const std::string out = dir + "/dram.json";
    Outcome r = run_suite({"--kernel=add", "--pattern=sequential,random", "--size=" + std::to_string(size),
                           "--threads=all", "--reps=3", "--quiet", "--out=" + out});
    ASSERT_EQ(r.status, 0) << r.err;
    json doc = load_json(out);
    ASSERT_EQ(doc["results"].size(), 2u);
    double seq = 0, rnd = 0;
    for (const auto& rec : doc["results"]) {
        EXPECT_TRUE(rec["verification"]["passed"].get<bool>());
        double gbps = rec["bandwidth_gbps"]["stream"]["best"];
        (rec["pattern"] == "random" ? rnd : seq) = gbps;
    }
    std::printf("add at %s: sequential %.2f GB/s, random %.2f GB/s (ratio %.2f)\n", std::to_string(size).c_str(), seq,
                rnd, seq / rnd);
    EXPECT_GT(seq, 0);
    EXPECT_LT(rnd, seq);
    std::system(("rm -rf " + dir).c_str());
}

TEST(E2E, ResultRecordsPinningAndPagesAsObserved) {
    const std::string dir = make_temp_dir();
    const std::string out = dir + "/r.json";
    const Topology topo = Topology::load();
    Outcome r =
        run_suite({"--kernel=triad", "--size=8MiB", "--threads=1", "--pin=0", "--reps=2", "--quiet", "--out=" + out});
    ASSERT_EQ(r.status, 0) << r.err;
    json rec = load_json(out)["results"][0];
    EXPECT_EQ(rec["pin"]["requested"], "0");
    ASSERT_EQ(rec["pin"]["threads"].size(), 1u);
    EXPECT_EQ(rec["pin"]["threads"][0]["requested_cpu"], 0);
    EXPECT_EQ(rec["pin"]["threads"][0]["allowed_cpus"], json::array({0}));
    EXPECT_EQ(rec["pin"]["threads"][0]["cpu"], 0);
    EXPECT_EQ(rec["pin"]["held_during_run"], true);
    // What else the machine did around the repetitions: measured, and the flag agrees with its reasons.
    const json& st = rec["stability"];
    ASSERT_TRUE(st.is_object()) << rec.dump(1);
    EXPECT_GT(st["window_s"].get<double>(), 0.0);
    EXPECT_GE(st["spread"].get<double>(), 0.0);
    EXPECT_EQ(st["unstable"].get<bool>(), !st["reasons"].empty()) << st.dump();
    EXPECT_FALSE(st["load_average_1m"].is_null()) << "Linux has /proc/loadavg";
    // a, b, c; every page present and counted on an existing node (node 0 on a one-node machine).
    ASSERT_EQ(rec["placement"]["arrays"].size(), 3u);
    for (const auto& a : rec["placement"]["arrays"]) {
        EXPECT_EQ(a["pages_not_present"], 0);
        std::uint64_t sum = 0;
        for (auto& [node, count] : a["pages_per_node"].items()) {
            EXPECT_NE(topo.find_node(std::stoi(node)), nullptr);
            sum += count.get<std::uint64_t>();
        }
        EXPECT_EQ(sum, a["pages"].get<std::uint64_t>());
        if (topo.nodes.size() == 1) {
            EXPECT_EQ(a["pages_per_node"][std::to_string(topo.nodes[0].os_index)], a["pages"]);
        }
    }
    std::system(("rm -rf " + dir).c_str());
}

TEST(E2E, CsvOutputHasAHeaderAndOneRowPerPoint) {
    const std::string dir = make_temp_dir();
    Outcome r = run_suite(
        {"--kernel=copy,latency", "--size=256KiB", "--threads=1", "--reps=2", "--quiet", "--out=" + dir + "/r.csv"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream in(slurp(dir + "/r.csv"));
    std::string header, line;
    std::getline(in, header);
    EXPECT_EQ(header.rfind("kernel,variant,name,", 0), 0u);
    // Each row says which run it came from, so that concatenated CSVs can be told apart.
    EXPECT_NE(header.find(",unstable,hugepages,host,cpu_model,date,git_revision"), std::string::npos) << header;
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    int rows = 0;
    while (std::getline(in, line)) {
        ++rows;
        EXPECT_NE(line.find(",true"), std::string::npos) << line;
        EXPECT_NE(line.find(std::string(",\"") + host + "\","), std::string::npos) << line;
        EXPECT_NE(line.find(",\"20"), std::string::npos) << "the run's date\n" << line;
    }
    EXPECT_EQ(rows, 2);
    std::system(("rm -rf " + dir).c_str());
}

TEST(E2E, OutputThatIsNotARegularFileIsRefusedAndLeftAlone) {
    TempDir dir;
    const std::string target = dir.file("real.json"), link = dir.file("link.json");
    { std::ofstream(target) << "keep me\n"; }
    ASSERT_EQ(symlink(target.c_str(), link.c_str()), 0);
    Outcome r = run_suite({"--kernel=copy", "--size=64KiB", "--reps=1", "--out=" + link});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    struct stat st {};
    ASSERT_EQ(lstat(link.c_str(), &st), 0);
    EXPECT_TRUE(S_ISLNK(st.st_mode));
    EXPECT_EQ(slurp(target), "keep me\n");
}

TEST(E2E, InfoSaysWhatCanBeMeasuredAndWhyNot) {
    Outcome r = run_suite({"info", "--json"});
    ASSERT_EQ(r.status, 0) << describe(r);
    json info = json::parse(r.out);
    EXPECT_GE(info["pus"].get<int>(), 1);
    EXPECT_EQ(info["instruments"]["timer"]["available"], true);
    for (const char* name : {"perf_counters", "energy"}) {
        const auto& inst = info["instruments"][name];
        ASSERT_TRUE(inst.is_object()) << name;
        // Not measured is never 0: either available, or unavailable with a reason.
        if (!inst["available"].get<bool>()) {
            EXPECT_FALSE(inst["reason"].get<std::string>().empty()) << name;
        }
    }
#if defined(__aarch64__)
    // No string instructions on Arm: no fast-string flags; the vector code is NEON, or SVE.
    EXPECT_FALSE(info.contains("string_ops")) << info.dump();
    EXPECT_EQ(info["instruction_set"]["arch"], "aarch64");
    EXPECT_EQ(info["instruction_set"]["neon"], true);
    const std::string built_for = info["instruction_set"]["sve"].get<bool>() ? "built for: SVE " : "built for: NEON";
    Outcome table = run_suite({"info"});
    ASSERT_EQ(table.status, 0);
    EXPECT_NE(table.out.find(built_for), std::string::npos) << table.out;
#else
    // The fast-string flags from CPUID, against the kernel's own reading of them.
    const std::string cpuinfo = slurp("/proc/cpuinfo");
    const auto flags_at = cpuinfo.find("\nflags");
    if (flags_at != std::string::npos) {
        const std::string flags = cpuinfo.substr(flags_at, cpuinfo.find('\n', flags_at + 1) - flags_at) + " ";
        for (const char* flag : {"erms", "fsrm"})
            EXPECT_EQ(info["string_ops"][flag], flags.find(" " + std::string(flag) + " ") != std::string::npos)
                << flag << ": " << info["string_ops"].dump();
    }
    Outcome table = run_suite({"info"});
    ASSERT_EQ(table.status, 0);
    EXPECT_NE(table.out.find("fast strings (the rep variants): ERMS "), std::string::npos) << table.out;
#endif
    EXPECT_NE(table.out.find("What can be measured here"), std::string::npos);
    EXPECT_NE(table.out.find("Caches (as reported by hwloc)"), std::string::npos);
}

TEST(E2E, JsonAndCsvOnStdoutWithoutAFile) {
    Outcome j = run_suite({"--kernel=scale,latency", "--size=128KiB", "--threads=1", "--reps=2", "--format=json"});
    ASSERT_EQ(j.status, 0) << describe(j);
    json doc = json::parse(j.out);  // stdout is the document and nothing else
    EXPECT_EQ(doc["complete"], true);
    EXPECT_EQ(doc["results"].size(), 2u);
    TempDir dir;
    { std::ofstream(dir.file("stdout.json")) << j.out; }
    Outcome v = validate_against_schema(dir.file("stdout.json"));
    EXPECT_EQ(v.status, 0) << describe(v);
    Outcome c = run_suite({"--kernel=scale", "--size=128KiB", "--threads=1", "--reps=2", "--format=csv"});
    ASSERT_EQ(c.status, 0) << describe(c);
    EXPECT_EQ(c.out.rfind("kernel,variant,name,", 0), 0u) << c.out;
}

TEST(E2E, InfoReadsAnotherMachineThroughHwloc) {
    // hwloc's own variable: a two-package, two-node machine described instead of detected.
    setenv("HWLOC_SYNTHETIC", "pack:2 numa:1 l3:1 core:4 pu:2", 1);
    Outcome r = run_suite({"info", "--json"});
    Outcome table = run_suite({"info"});
    Outcome run = run_suite({"--kernel=copy", "--size=64KiB", "--reps=1"});
    unsetenv("HWLOC_SYNTHETIC");
    ASSERT_EQ(r.status, 0) << describe(r);
    json info = json::parse(r.out);
    EXPECT_EQ(info["packages"], 2);
    EXPECT_EQ(info["numa_nodes"].size(), 2u);
    EXPECT_EQ(info["pus"], 16);
    EXPECT_EQ(info["this_system"], false);
    EXPECT_NE(table.out.find("2 NUMA node(s)"), std::string::npos) << table.out;
    EXPECT_NE(table.out.find("not this machine's"), std::string::npos) << table.out;
    // Pinning to CPUs of a machine that is not this one is refused, not faked.
    EXPECT_EQ(run.status, 2) << describe(run);
    EXPECT_NE(run.err.find("--pin=none"), std::string::npos) << run.err;
}
