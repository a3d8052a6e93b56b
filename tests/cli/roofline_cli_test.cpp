// `suite roofline`: the ceilings measured and written (valid against results/schema/roofline-v1.json),
// a run placed on them with the arithmetic checked against ceilings set by hand, and every bad
// input refused with one line, exit 2 and nothing written. The measurement runs at a tiny size
// (--dram-size, --min-time; the probe finds the caches this process gets) so that the test stays a few seconds long.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "harness/results/history.hpp"
#include "harness/results/roofline_place.hpp"
#include "tests/cli/roofline_size.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

const std::string roofline_schema = std::string(SUITE_SOURCE_DIR) + "/results/schema/roofline-v1.json";

void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// One roofline and one small run, measured once for the whole file.
struct Measured {
    std::string dir, roof, run, peak;
    Measured() {
        dir = make_temp_dir();
        roof = dir + "/roof.json";
        run = dir + "/run.json";
        peak = dir + "/peak.json";
        Outcome r = run_suite(
            {"roofline", "--threads=1", "--min-time=0.02", roofline_test_dram_size(), "--no-png", "--out=" + roof});
        EXPECT_EQ(r.status, 0) << r.err;
        Outcome s = run_suite(
            {"--kernel=triad,latency", "--sizes=64KiB", "--threads=1", "--reps=3", "--quiet", "--out=" + run});
        EXPECT_EQ(s.status, 0) << s.err;
        Outcome p = run_suite({"--kernel=peak-flops", "--isa=scalar", "--size=4096", "--threads=1", "--reps=3",
                               "--quiet", "--out=" + peak});
        EXPECT_EQ(p.status, 0) << p.err;
    }
};

const Measured& measured() {
    static const Measured m;
    return m;
}

}  // namespace

TEST(Roofline, WritesEveryWidthAndLevelValidAgainstItsSchema) {
    const Measured& m = measured();
    const json doc = json::parse(slurp(m.roof));
    EXPECT_EQ(doc["kind"], "suite-roofline");
    EXPECT_EQ(doc["complete"], true);
    EXPECT_EQ(doc["fingerprint"], machine_fingerprint(doc["context"]));
    ASSERT_EQ(doc["ceilings"].size(), 1u);
    const json& c = doc["ceilings"][0];
    // Every width the build has, and the widest the fastest (the peak is the widest's).
    ASSERT_GE(c["peak"].size(), 2u);
    EXPECT_EQ(c["peak"][0]["isa"], "scalar");
    double widest = c["peak"].back()["gflops"];
    for (const auto& p : c["peak"]) EXPECT_GT(p["gflops"].get<double>(), 0) << p.dump();
    EXPECT_GT(widest, c["peak"][0]["gflops"].get<double>() * 1.5) << "the widest FMA should beat scalar by far";
    EXPECT_DOUBLE_EQ(c["peak_gflops"].get<double>(), widest);
    // A level per cache level plus DRAM, each with a ceiling that is the best kernel measured there.
    ASSERT_EQ(c["bandwidth"].size(), doc["levels"].size());
    EXPECT_EQ(doc["levels"].back()["name"], "DRAM");
    const json& dram = c["bandwidth"].back();
    EXPECT_EQ(dram["footprint_bytes"], roofline_test_dram_bytes());
    for (const auto& l : c["bandwidth"]) {
        if (l["gbps"].is_null()) continue;
        double best = 0;
        for (const auto& f : l["measured"]) best = std::max(best, f["gbps"].get<double>());
        EXPECT_DOUBLE_EQ(l["gbps"].get<double>(), best) << l.dump();
        EXPECT_EQ(l["read_only"]["kernel"], "load");
    }
    Outcome v = run_program({SUITE_PYTHON, validator_path, roofline_schema, m.roof});
    EXPECT_EQ(v.status, 0) << v.out << v.err;
}

TEST(Roofline, PlacesARunOnItsOwnMachinesCeilingsAndSaysWhatItCannotPlace) {
    const Measured& m = measured();
    const std::string out = m.dir + "/placed.json", peak_out = m.dir + "/placed-peak.json";
    Outcome r = run_suite({"roofline", "--place=" + m.run, "--ceilings=" + m.roof, "--no-png", "--out=" + out});
    ASSERT_EQ(r.status, 0) << r.err;
    Outcome rp = run_suite({"roofline", "--place=" + m.peak, "--ceilings=" + m.roof, "--no-png", "--out=" + peak_out});
    ASSERT_EQ(rp.status, 0) << rp.err;
    const json doc = json::parse(slurp(out)), peak_doc = json::parse(slurp(peak_out));
    EXPECT_EQ(doc["kind"], "suite-roofline-placement");
    ASSERT_EQ(doc["points"].size(), 1u) << doc.dump(1);
    const json& p = doc["points"][0];
    EXPECT_EQ(p["kernel"], "triad");
    EXPECT_GT(p["fraction"].get<double>(), 0);
    EXPECT_NEAR(p["intensity"]["stream"].get<double>(), 2.0 / 24.0, 1e-12);
    EXPECT_EQ(p["ceiling"]["bound"], "bandwidth");
    ASSERT_EQ(peak_doc["points"].size(), 1u) << peak_doc.dump(1);
    const json& q = peak_doc["points"][0];
    EXPECT_EQ(q["level"], "registers");
    EXPECT_EQ(q["ceiling"]["bound"], "compute");
    EXPECT_NEAR(q["fraction"].get<double>(), q["gflops"].get<double>() / q["ceiling"]["gflops"].get<double>(), 1e-12);
    ASSERT_EQ(doc["not_placed"].size(), 1u);
    EXPECT_NE(doc["not_placed"][0]["reason"].get<std::string>().find("latency"), std::string::npos);
    Outcome v = run_program({SUITE_PYTHON, validator_path, roofline_schema, out, peak_out});
    EXPECT_EQ(v.status, 0) << v.out << v.err;
}

// The arithmetic on ceilings set by hand: the level by footprint, min(peak, I x B), the fraction.
TEST(Roofline, PlacementArithmeticOnHandSetCeilings) {
    const Measured& m = measured();
    json roof = json::parse(slurp(m.roof));
    roof["levels"] = json::array(
        {{{"name", "L1"}, {"capacity_bytes", 16384}, {"instances", 1}, {"pus_per_instance", 1}, {"source", "reported"}},
         {{"name", "L2"},
          {"capacity_bytes", 1 << 20},
          {"instances", 1},
          {"pus_per_instance", 1},
          {"source", "reported"}},
         {{"name", "DRAM"},
          {"capacity_bytes", nullptr},
          {"instances", 1},
          {"pus_per_instance", 1},
          {"source", "memory"}}});
    auto level = [](const char* name, double gbps) {
        json f = {{"kernel", "load"}, {"gbps", gbps}, {"hardware_gbps", gbps}};
        return json{
            {"level", name},    {"footprint_bytes", 4096}, {"gbps", gbps},          {"hardware_gbps", gbps},
            {"kernel", "load"}, {"read_only", f},          {"read_write", nullptr}, {"measured", json::array({f})}};
    };
    // A triad at 64 KiB is past L1 (16 KiB, reach 32 KiB) and inside L2: held against L2's 1 GB/s.
    roof["ceilings"][0]["bandwidth"] = json::array({level("L1", 1000), level("L2", 1), level("DRAM", 0.5)});
    roof["ceilings"][0]["peak"] = json::array({{{"isa", "scalar"}, {"kernel", "peak-flops-scalar"}, {"gflops", 1e6}}});
    const RooflineFile file = parse_roofline_text(roof.dump(), "hand.json");
    const json run = json::parse(slurp(m.run));
    const ResultFile result = parse_result_text(slurp(m.run), m.run);
    const Placement pl = place_points(file, result, run);
    const PlacedPoint* triad = nullptr;
    for (const auto& p : pl.points)
        if (p.kernel == "triad") triad = &p;
    ASSERT_NE(triad, nullptr);
    EXPECT_EQ(triad->level, "L2");
    EXPECT_DOUBLE_EQ(triad->ceiling_gbps, 1.0);
    EXPECT_NEAR(*triad->ceiling_gflops, 2.0 / 24.0 * 1.0, 1e-15);
    EXPECT_NEAR(triad->fraction, *triad->gflops / (2.0 / 24.0), 1e-12);
    EXPECT_NEAR(triad->fraction, triad->gbps / 1.0, 1e-12);
    // With a peak below I x B the compute ceiling bounds it.
    roof["ceilings"][0]["peak"][0]["gflops"] = 0.01;
    const Placement low = place_points(parse_roofline_text(roof.dump(), "hand.json"), result, run);
    for (const auto& p : low.points)
        if (p.kernel == "triad") {
            EXPECT_EQ(p.bound, "compute");
            EXPECT_NEAR(p.fraction, *p.gflops / 0.01, 1e-9);
        }
}

// Bad input: one line on stderr, exit 2, the output file untouched.
TEST(Roofline, RefusesBadInputWithOneLineAndWritesNothing) {
    const Measured& m = measured();
    const std::string out = m.dir + "/keep.json";
    write_file(out, "earlier\n");
    json run = json::parse(slurp(m.run));
    json other = run;
    other["context"]["host"] = "another-host";
    write_file(m.dir + "/other.json", other.dump());
    json empty = run;
    empty["results"] = json::array();
    write_file(m.dir + "/empty.json", empty.dump());
    json v2 = json::parse(slurp(m.roof));
    v2["schema_version"] = 2;
    write_file(m.dir + "/v2.json", v2.dump());
    const struct {
        std::vector<std::string> args;
        std::string says;
    } cases[] = {
        {{"--place=" + m.dir + "/other.json", "--ceilings=" + m.roof}, "another-host"},
        {{"--place=" + m.dir + "/empty.json", "--ceilings=" + m.roof}, "no records"},
        {{"--threads=100000"}, "100000"},
        {{"--place=" + m.run, "--ceilings=" + m.dir + "/v2.json"}, "schema_version 2"},
        {{"--place=" + m.run, "--ceilings=" + m.run}, "not a roofline file"},
        {{"--place=" + m.dir + "/missing.json", "--ceilings=" + m.roof}, "missing.json: cannot read it"},
        {{"--ceilings=" + m.roof}, "--place"},
        {{"--dram-size=12"}, "--dram-size"},
    };
    for (const auto& c : cases) {
        std::vector<std::string> args{"roofline", "--no-png", "--out=" + out};
        args.insert(args.end(), c.args.begin(), c.args.end());
        Outcome r = run_suite(args);
        const std::string what = join(c.args);
        EXPECT_EQ(r.status, 2) << what << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << what << ": " << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << what << ": " << r.err;
        EXPECT_EQ(slurp(out), "earlier\n") << what;
    }
}
