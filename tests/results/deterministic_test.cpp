// `suite deterministic`: the kernels under valgrind's callgrind, counted inside Kernel::run only.
// The counts must repeat exactly, look like the kernel's loop (instructions and misses per
// element in a sensible range, misses growing past the simulated caches), validate against the
// schema, and feed `suite check`. Needs valgrind and a build valgrind can decode (x86-64-v3).
#include <gtest/gtest.h>

#include <map>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include "harness/results/callgrind_dump.hpp"
#include "tests/process.hpp"

using namespace suite::test;
using nlohmann::json;

namespace {

// The binary valgrind can run: the x86-64-v3 twin, or the main build when it is itself generic.
std::string deterministic_binary() {
#ifdef SUITE_V3_BINARY
    return SUITE_V3_BINARY;
#else
    return SUITE_BINARY;
#endif
}

bool have_valgrind() { return access("/usr/bin/valgrind", X_OK) == 0; }

// Whether `binary` was built with AVX-512 (which valgrind 3.19 cannot run), from its own info.
bool uses_avx512(const std::string& binary) {
    Outcome info = run_program({binary, "info", "--json"}, 60);
    return info.status == 0 && json::parse(info.out)["instruction_set"]["avx512f"].get<bool>();
}

json per_call(const json& rec) { return rec["callgrind"]["per_call"]; }

}  // namespace

// Why the deterministic mode cannot run here, or "" when it can.
static std::string why_valgrind_cannot_run() {
    if (!have_valgrind()) return "valgrind is not installed (scripts/install-deps.sh test installs it)";
#if defined(__SANITIZE_ADDRESS__)
    return "an AddressSanitizer build (make test-sanitize) cannot run under valgrind; the plain build runs this test";
#endif
    if (uses_avx512(deterministic_binary()))
        return "no build valgrind can run: the main build uses AVX-512 and suite-x86-64-v3 was not built "
               "(SUITE_VALGRIND_TWIN=OFF?)";
    return "";
}

TEST(CallgrindDump, TotalsAreReadByEventName) {
    const std::string text =
        "# callgrind format\nversion: 1\ncreator: callgrind-3.19.0\ncmd: suite\npart: 2\ndesc: I1 cache: 32768 B, 64 "
        "B, 8-way associative\n"
        "desc: Trigger: Client Request: suite point add random 16KiB t=1\npositions: line\nevents: Ir Dr Dw I1mr D1mr "
        "D1mw ILmr DLmr DLmw\n"
        "fl=(1) x.cpp\nfn=(1) f\n3 10 4 2\nsummary: 300 120 60 1 30 7\ntotals: 300 120 60 1 30 7\n";
    const suite::CallgrindDump d = suite::parse_callgrind_dump(text);
    EXPECT_EQ(d.label, "Client Request: suite point add random 16KiB t=1");
    EXPECT_EQ(d.get("Ir"), 300);
    EXPECT_EQ(d.get("D1mw"), 7);
    EXPECT_EQ(d.get("DLmw"), 0) << "trailing zero counts are left out by callgrind";
    const json block = suite::callgrind_block(d, 3, "valgrind 3.19.0");
    EXPECT_EQ(block["per_call"]["Ir"], 100);
    EXPECT_EQ(block["calls"], 3);
    EXPECT_THROW(suite::parse_callgrind_dump("hello\n"), std::runtime_error);
}

TEST(Deterministic, CountsRepeatExactlyAndFeedTheGate) {
    if (const std::string why = why_valgrind_cannot_run(); !why.empty()) GTEST_SKIP() << why;
    TempDir dir;
    const std::vector<std::string> args = {"deterministic", "--kernel=add,latency", "--pattern=sequential,random",
                                           "--sizes=16KiB,256KiB,16MiB"};
    std::vector<std::string> a1{deterministic_binary()}, a2{deterministic_binary()};
    a1.insert(a1.end(), args.begin(), args.end());
    a2.insert(a2.end(), args.begin(), args.end());
    a1.push_back("--out=" + dir.file("a.json"));
    a2.push_back("--out=" + dir.file("a-second-run-with-a-longer-name.json"));
    Outcome r1 = run_program(a1, 300), r2 = run_program(a2, 300);
    ASSERT_EQ(r1.status, 0) << describe(r1);
    ASSERT_EQ(r2.status, 0) << describe(r2);
    Outcome v = validate_against_schema({dir.file("a.json")});
    EXPECT_EQ(v.status, 0) << describe(v);
    const json d1 = json::parse(slurp(dir.file("a.json"))),
               d2 = json::parse(slurp(dir.file("a-second-run-with-a-longer-name.json")));
    ASSERT_EQ(d1["results"].size(), 12u);
    for (std::size_t i = 0; i < d1["results"].size(); ++i) {
        const json& r = d1["results"][i];
        SCOPED_TRACE(r["name"].get<std::string>() + " " + r["pattern"].get<std::string>() + " " +
                     std::to_string(r["size"]["requested"].get<long>()));
        EXPECT_EQ(per_call(r), per_call(d2["results"][i])) << "callgrind counts must repeat exactly";
        EXPECT_EQ(r["repetitions"]["batch"], 1);
        EXPECT_EQ(r["callgrind"]["calls"], r["repetitions"]["counted"]);
        const double units = r["size"]["units"], ir = per_call(r)["Ir"];
        // A loop of a few instructions per element or load: the kernel was counted, and only it
        // (setup alone would be tens of instructions per element more).
        EXPECT_GT(ir / units, 0.5);
        EXPECT_LT(ir / units, 30);
    }
    // Misses per element grow once the footprint leaves the simulated 32 KiB D1 and 8 MiB LL.
    auto find = [&](const std::string& k, const std::string& p, long size) {
        for (const auto& r : d1["results"])
            if (r["kernel"] == k && r["pattern"] == p && r["size"]["requested"] == size) return r;
        throw std::runtime_error("missing record");
    };
    for (const char* k : {"add", "latency"}) {
        const json small = find(k, "random", 16 << 10), mid = find(k, "random", 256 << 10),
                   big = find(k, "random", 16 << 20);
        auto d1_per = [](const json& r) {
            return (per_call(r)["D1mr"].get<double>() + per_call(r)["D1mw"].get<double>()) /
                   r["size"]["units"].get<double>();
        };
        auto ll_per = [](const json& r) {
            return (per_call(r)["DLmr"].get<double>() + per_call(r)["DLmw"].get<double>()) /
                   r["size"]["units"].get<double>();
        };
        EXPECT_LT(d1_per(small), 0.1) << k;
        EXPECT_GT(d1_per(mid), 0.3) << k;
        EXPECT_LT(ll_per(mid), 0.01) << k;
        EXPECT_GT(ll_per(big), 0.3) << k;
    }
    // The gate: identical counts pass at 0 % tolerance; one more instruction per element fails at 1 %.
    Outcome same = run_suite(
        {"check", "--baseline", dir.file("a.json"), dir.file("a-second-run-with-a-longer-name.json"), "--tolerance=0"});
    EXPECT_EQ(same.status, 0) << describe(same);
    json worse = d1;
    json& rec = worse["results"][0];
    rec["callgrind"]["per_call"]["Ir"] =
        rec["callgrind"]["per_call"]["Ir"].get<double>() + rec["size"]["units"].get<double>();
    std::ofstream(dir.file("worse.json")) << worse.dump();
    Outcome gate = run_suite({"check", "--baseline", dir.file("a.json"), dir.file("worse.json"), "--tolerance=1%"});
    EXPECT_EQ(gate.status, 1) << describe(gate);
    EXPECT_NE(gate.out.find("callgrind instructions"), std::string::npos) << gate.out;
}

TEST(Deterministic, MeshKernelsTakeTheirSizeFromTheMeshAndOrderingsShowInTheMisses) {
    if (const std::string why = why_valgrind_cannot_run(); !why.empty()) GTEST_SKIP() << why;
    TempDir dir;
    // x is 96 KiB here, three times the simulated D1: a random numbering misses on most of its
    // reads, a Hilbert one on few. (The default sizes are not added beside --mesh.)
    Outcome r = run_program({deterministic_binary(), "deterministic", "--kernel=fem-spmv", "--mesh=disk:refine=6",
                             "--ordering=random,hilbert", "--reps=1", "--out=" + dir.file("m.json")},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json d = json::parse(slurp(dir.file("m.json")));
    ASSERT_EQ(d["results"].size(), 2u);
    std::map<std::string, double> d1_per_nnz;
    for (const auto& rec : d["results"]) {
        EXPECT_EQ(rec["verification"]["passed"], true);
        d1_per_nnz[rec["ordering"]] =
            per_call(rec)["D1mr"].get<double>() / rec["work_per_repetition"]["units"].get<double>();
    }
    EXPECT_GT(d1_per_nnz["random"], 2 * d1_per_nnz["hilbert"])
        << "random " << d1_per_nnz["random"] << " hilbert " << d1_per_nnz["hilbert"];
}

TEST(Deterministic, UsageErrorsAreRefusedBeforeValgrindRuns) {
    TempDir dir;
    Outcome threads = run_program(
        {deterministic_binary(), "deterministic", "--kernel=add", "--threads=2", "--out=" + dir.file("d.json")}, 60);
    EXPECT_EQ(threads.status, 2) << describe(threads);
    EXPECT_NE(threads.err.find("--threads=1"), std::string::npos) << describe(threads);
    Outcome format = run_program({deterministic_binary(), "deterministic", "--kernel=add", "--format=csv"}, 60);
    EXPECT_EQ(format.status, 2) << describe(format);
    Outcome vg =
        run_program({deterministic_binary(), "deterministic", "--kernel=add", "--valgrind=/nonexistent/valgrind"}, 60);
    EXPECT_EQ(vg.status, 2) << describe(vg);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Deterministic, AnAvx512BuildSaysToUseX8664V3) {
    Outcome info = run_suite({"info", "--json"});
    ASSERT_EQ(info.status, 0);
    if (!json::parse(info.out)["instruction_set"]["avx512f"].get<bool>())
        GTEST_SKIP() << "the main build does not use AVX-512 here";
    Outcome r = run_suite({"deterministic", "--kernel=add", "--sizes=16KiB"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_NE(r.err.find("x86-64-v3"), std::string::npos) << describe(r);
    EXPECT_NE(r.err.find("AVX-512"), std::string::npos) << describe(r);
}
