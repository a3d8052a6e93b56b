// --strategy=sell end to end: fem-spmv, fem-cg and fem-eigen run and verify it on a small disk and
// record its facts (SELL bytes, padding, C, σ); a kernel without it and a --sell-sigma that is not
// a positive multiple of this build's C are refused in one line naming what is accepted, exit 2.
#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "kernels/fem/sell_arch.hpp"
#include "tests/process.hpp"

using namespace suite::test;

namespace {

const std::string C = std::to_string(suite::fem::sell_c);

void expect_refused(const std::vector<std::string>& args, const std::vector<std::string>& expected) {
    TempDir tmp;
    std::vector<std::string> full = args;
    full.push_back("--out=" + tmp.file("r.json"));
    const Outcome r = run_suite(full, 120);
    EXPECT_EQ(r.status, 2) << join(args) << "\n" << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line\n" << describe(r);
    for (const auto& s : expected) EXPECT_NE(r.err.find(s), std::string::npos) << "lacks " << s << "\n" << describe(r);
    EXPECT_TRUE(names_in(tmp.path().string()).empty()) << "nothing written";
}

}  // namespace

TEST(FemSellCli, SolversRunAndVerifySellAndRecordItsFacts) {
    TempDir tmp;
    const std::string out = tmp.file("r.json");
    const Outcome r =
        run_suite({"--kernel=fem-spmv,fem-cg,fem-eigen", "--strategy=sell", "--ordering=hilbert,rcm",
                   "--mesh=disk:refine=2", "--threads=1,2", "--reps=2", "--sell-sigma=" + C, "--quiet", "--out=" + out},
                  300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const nlohmann::json doc = nlohmann::json::parse(std::ifstream(out));
    ASSERT_EQ(doc["results"].size(), 12u);
    for (const auto& rec : doc["results"]) {
        SCOPED_TRACE(rec["name"].dump());
        EXPECT_EQ(rec["variant"], "sell");
        EXPECT_TRUE(rec["verification"]["passed"].get<bool>()) << rec["verification"];
        const nlohmann::json& f = rec["facts"];
        EXPECT_EQ(f["sell-c"]["value"].get<double>(), suite::fem::sell_c);
        EXPECT_EQ(f["sell-sigma"]["value"].get<double>(), suite::fem::sell_c);
        EXPECT_GE(f["padding"]["value"].get<double>(), 0.0);
        // Padding is a cost: SELL's bytes a nonzero are CSR's less the row pointers, plus padding's.
        EXPECT_GT(f["sell-bytes-per-nnz"]["value"].get<double>(), 12.0);
    }
    const std::string spmv = doc["results"][0]["verification"]["detail"];
    EXPECT_NE(spmv.find("equals a serial replay exactly"), std::string::npos) << spmv;
}

TEST(FemSellCli, SellOnAKernelWithoutItIsRefused) {
    expect_refused({"--kernel=fem-spmv-dist", "--strategy=sell"}, {"'fem-spmv-dist'", "'sell'", "curve, metis"});
    expect_refused({"--kernel=fem-assembly", "--strategy=sell"}, {"'fem-assembly'", "'sell'", "serial"});
    expect_refused({"--kernel=triad", "--sell-sigma=" + C},
                   {"--sell-sigma does not apply", "fem-cg, fem-eigen, fem-spmv"});
}

TEST(FemSellCli, ASigmaThatIsNotAPositiveMultipleOfCIsRefused) {
    const std::string accepted = "a positive multiple of " + C + ", this build's SIMD width in doubles";
    for (const std::string& bad : std::vector<std::string>{"0", "-" + C, std::to_string(suite::fem::sell_c + 1), "2.5"})
        for (const char* kernel : {"fem-spmv", "fem-cg"})
            expect_refused({std::string("--kernel=") + kernel, "--strategy=sell", "--sell-sigma=" + bad},
                           {"--sell-sigma=", std::string("for ") + kernel, accepted});
}
