// The result file against its published schema (results/schema/v2.json): the real binary
// writes files for every registered kernel and for the non-temporal variants, and each must
// pass tests/validate_result.py (Debian's python3 with jsonschema). A few facts the schema
// cannot express are checked here directly, and broken copies of a valid file must fail, so
// a schema that accepts everything cannot pass.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace suite::test;

constexpr double kTimeoutS = 60;  // per run of the binary or the validator
// A hang guard for a kernel's whole sweep, not a speed check: mpm-implicit-step's 16 points take
// 28 s alone on the 2-core VM, and more than 60 when ctest runs another test beside it.
constexpr double kKernelTimeoutS = 300;

json load(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
}

void save(const std::string& path, const json& doc) { std::ofstream(path) << doc.dump(1) << "\n"; }

json kernel_list() {
    Outcome r = run_suite({"list", "--json"}, kTimeoutS);
    EXPECT_EQ(r.status, 0) << describe(r);
    return json::parse(r.combined());
}

// "1,2" where the machine has two PUs, else "1".
std::string small_thread_list() {
    Outcome r = run_suite({"info", "--json"}, kTimeoutS);
    EXPECT_EQ(r.status, 0) << describe(r);
    return json::parse(r.combined()).at("pus").get<int>() >= 2 ? "1,2" : "1";
}

// The checks the schema cannot express. `where` names the file in failure messages.
void check_content(const json& doc, const std::string& where, int reps) {
    SCOPED_TRACE(where);
    EXPECT_EQ(doc.at("schema_version"), 2);
    EXPECT_EQ(doc.at("complete"), true);
    ASSERT_TRUE(doc.at("results").is_array());
    EXPECT_FALSE(doc.at("results").empty());
    const json& ctx = doc.at("context");
    EXPECT_EQ(ctx.at("pus"), ctx.at("topology").at("pus"));
    EXPECT_EQ(ctx.at("numa_node_count").get<std::size_t>(), ctx.at("topology").at("numa_nodes").size());
    for (const auto& r : doc.at("results")) {
        SCOPED_TRACE(r.value("name", "?") + " " + r.value(r.value("axis", "pattern"), "?") +
                     " threads=" + std::to_string(r.value("threads", 0)));
        EXPECT_EQ(r.at("verification").at("passed"), true) << r.at("verification").dump();
        EXPECT_EQ(r.at("pin").at("threads").size(), r.at("threads").get<std::size_t>());
        EXPECT_EQ(r.at("repetitions").at("counted"), reps);
        EXPECT_EQ(r.at("time_s").at("samples").size(), static_cast<std::size_t>(reps));
        EXPECT_EQ(r.at("size").at("units"), r.at("work_per_repetition").at("units"));
        EXPECT_GT(r.at("time_s").at("min").get<double>(), 0.0);
        EXPECT_GT(r.at("units_per_second_best").get<double>(), 0.0);
        if (r.at("metric") == "bandwidth") {
            ASSERT_TRUE(r.at("bandwidth_gbps").is_object());
            const json& best = r.at("bandwidth_gbps").at("stream").at("best");
            // A kernel that moves no bytes (peak-flops) has a rate of flops instead, and no
            // bandwidth: null with the reason, never 0.
            if (r.at("work_per_repetition").at("stream_bytes").get<double>() == 0) {
                EXPECT_GT(r.at("gflops_best").get<double>(), 0.0);
                EXPECT_TRUE(best.is_null()) << best.dump();
                EXPECT_TRUE(r.at("bandwidth_gbps").at("reason").is_string());
            } else {
                ASSERT_TRUE(best.is_number()) << best.dump();
                EXPECT_GT(best.get<double>(), 0.0);
            }
            EXPECT_TRUE(r.at("latency_ns").is_null());
        } else {
            ASSERT_TRUE(r.at("latency_ns").is_object());
            const json& best = r.at("latency_ns").at("best");
            ASSERT_TRUE(best.is_number()) << best.dump();
            EXPECT_GT(best.get<double>(), 0.0);
            EXPECT_TRUE(r.at("bandwidth_gbps").is_null());
        }
    }
}

TEST(ResultSchema, SchemaAndValidatorArePresent) {
    EXPECT_TRUE(fs::exists(schema_path)) << schema_path;
    EXPECT_TRUE(fs::exists(validator_path)) << validator_path;
    // The schema file is JSON and says what it is.
    const json schema = load(schema_path);
    EXPECT_EQ(schema.at("$schema"), "https://json-schema.org/draft/2020-12/schema");
    EXPECT_EQ(schema.at("properties").at("schema_version").at("const"), 2);
    // The version before it stays, for the files the suite still reads.
    EXPECT_EQ(load(schema_dir + "/v1.json").at("properties").at("schema_version").at("const"), 1);
    // Usage errors are 2, not 0 or 1.
    Outcome usage = run_program({SUITE_PYTHON, validator_path}, kTimeoutS);
    EXPECT_EQ(usage.status, 2) << describe(usage);
}

// Every kernel `suite list --json` reports, with all its patterns (orderings), at a tiny size.
TEST(ResultSchema, EveryKernelWritesAValidFile) {
    TempDir dir;
    ASSERT_TRUE(dir.ok());
    const json kernels = kernel_list();
    ASSERT_TRUE(kernels.is_array());
    ASSERT_FALSE(kernels.empty());
    const std::string threads = small_thread_list();
    const std::size_t thread_count = threads == "1" ? 1 : 2;
    const int reps = 2;

    std::vector<std::string> files;
    for (const auto& k : kernels) {
        const std::string name = k.at("name");
        const std::string axis = k.at("axis");
        std::vector<std::string> accesses;
        for (const auto& a : k.at("accesses")) accesses.push_back(a == "strided" ? "strided:4" : a.get<std::string>());
        std::string access_list;
        for (const auto& a : accesses) access_list += (access_list.empty() ? "" : ",") + a;
        // Byte-sized kernels get 64 KiB; count-sized (application) kernels a small count.
        const std::string size = k.at("size") == "bytes" ? "64KiB" : "4096";
        const std::string out = dir.file(name + ".json");
        const std::vector<std::string> args{"--kernel=" + name,     "--" + axis + "=" + access_list,  "--size=" + size,
                                            "--threads=" + threads, "--reps=" + std::to_string(reps), "-q",
                                            "--out=" + out};
        Outcome r = run_suite(args, kKernelTimeoutS);
        ASSERT_EQ(r.status, 0) << "suite " << join(args) << "\n" << describe(r);
        files.push_back(out);

        const json doc = load(out);
        check_content(doc, name, reps);
        // One record per access, default variant ("" when the kernel names none) and thread
        // count (one thread only for a single-thread variant), each of this kernel, on its axis.
        std::vector<std::string> variants = k.at("default_variants").get<std::vector<std::string>>();
        if (variants.empty()) variants = {""};
        const auto single = k.at("single_thread_variants").get<std::vector<std::string>>();
        auto teams = [&](const std::string& v) {
            return std::find(single.begin(), single.end(), v) != single.end() ? std::size_t{1} : thread_count;
        };
        std::size_t expected = 0;
        for (const auto& v : variants) expected += accesses.size() * teams(v);
        ASSERT_EQ(doc.at("results").size(), expected) << doc.at("results").dump(1);
        std::set<std::tuple<std::string, std::string, int>> seen;
        for (const auto& rec : doc.at("results")) {
            EXPECT_EQ(rec.at("kernel"), name);
            EXPECT_EQ(rec.at("axis"), axis);
            EXPECT_EQ(rec.at("metric"), k.at("metric"));
            EXPECT_EQ(rec.at("size").at("kind"), k.at("size"));
            seen.insert(
                {rec.at(axis).get<std::string>(), rec.at("variant").get<std::string>(), rec.at("threads").get<int>()});
            // Every declared parameter is recorded, at its default here.
            for (const auto& p : k.at("params"))
                EXPECT_EQ(rec.at("parameters").at(p.at("name").get<std::string>()), p.at("default"));
        }
        for (const auto& a : accesses)
            for (const auto& v : variants)
                for (int t = 1; t <= static_cast<int>(teams(v)); ++t)
                    EXPECT_TRUE(seen.count({a, v, t}))
                        << name << " has no record for " << a << " '" << v << "' with " << t << " thread(s)";
    }
    Outcome v = validate_against_schema(files);
    EXPECT_EQ(v.status, 0) << describe(v);
}

TEST(ResultSchema, NonTemporalStoresWriteAValidFile) {
    TempDir dir;
    ASSERT_TRUE(dir.ok());
    const std::string out = dir.file("nt.json");
    const std::vector<std::string> args{"--kernel=copy,triad", "--stores=nt", "--size=1MiB", "--reps=2", "-q",
                                        "--out=" + out};
    Outcome r = run_suite(args, kTimeoutS);
    ASSERT_EQ(r.status, 0) << "suite " << join(args) << "\n" << describe(r);
    Outcome v = validate_against_schema({out});
    EXPECT_EQ(v.status, 0) << describe(v);

    const json doc = load(out);
    check_content(doc, "copy,triad --stores=nt", 2);
    std::set<std::string> kernels;
    for (const auto& rec : doc.at("results")) {
        kernels.insert(rec.at("kernel").get<std::string>());
        EXPECT_EQ(rec.at("variant"), "nt");
        EXPECT_EQ(rec.at("name"), rec.at("kernel").get<std::string>() + "-nt");
        EXPECT_EQ(rec.at("pattern"), "sequential");
    }
    EXPECT_EQ(kernels, (std::set<std::string>{"copy", "triad"}));
}

// Broken copies of a valid file must fail, with the path of the break in the message.
TEST(ResultSchema, BrokenFilesFailValidation) {
    TempDir dir;
    ASSERT_TRUE(dir.ok());
    const std::string good = dir.file("good.json");
    Outcome r = run_suite({"--kernel=copy,latency", "--size=64KiB", "--threads=1", "--reps=2", "-q", "--out=" + good},
                          kTimeoutS);
    ASSERT_EQ(r.status, 0) << describe(r);
    Outcome ok = validate_against_schema({good});
    ASSERT_EQ(ok.status, 0) << "the unmodified file must be valid\n" << describe(ok);

    const json doc = load(good);
    ASSERT_GE(doc.at("results").size(), 2u);
    ASSERT_EQ(doc["results"][0]["metric"], "bandwidth");
    ASSERT_EQ(doc["results"][1]["metric"], "latency");

    struct Break {
        std::string name;
        std::function<void(json&)> apply;
        std::string expect_in_output;  // the JSON path the validator must name
    };
    const std::vector<Break> breaks = {
        {"no_kernel", [](json& d) { d["results"][0].erase("kernel"); },
         "$.results[0]: 'kernel' is a required property"},
        {"bandwidth_empty", [](json& d) { d["results"][0]["bandwidth_gbps"] = json::object(); },
         "$.results[0].bandwidth_gbps"},
        {"bandwidth_garbage", [](json& d) { d["results"][0]["bandwidth_gbps"] = "fast"; },
         "$.results[0].bandwidth_gbps"},
        {"bandwidth_on_latency", [](json& d) { d["results"][1]["bandwidth_gbps"] = d["results"][0]["bandwidth_gbps"]; },
         "$.results[1].bandwidth_gbps"},
        {"latency_null", [](json& d) { d["results"][1]["latency_ns"] = nullptr; }, "$.results[1].latency_ns"},
        {"bad_axis", [](json& d) { d["results"][0]["axis"] = "diagonal"; }, "$.results[0].axis"},
        {"ordering_on_pattern", [](json& d) { d["results"][0]["ordering"] = "morton"; }, "$.results[0].ordering"},
        {"node_string", [](json& d) { d["results"][0]["placement"]["node"] = "0"; }, "$.results[0].placement.node"},
        {"extra_key", [](json& d) { d["results"][0]["speedup"] = 2; }, "$.results[0]"},
        {"version_3", [](json& d) { d["schema_version"] = 3; }, "$.schema_version"},
        {"choice_index",
         [](json& d) {
             d["results"][0]["parameters"] = {{"case", "Dam Break"}};
         },
         "$.results[0].parameters.case"},
        {"energy_no_reason",
         [](json& d) {
             d["context"]["instruments"]["energy"] = {{"available", false}};
         },
         "$.context.instruments.energy"},
        {"governor_no_reason",
         [](json& d) {
             d["context"]["frequency_governor"] = {{"value", nullptr}};
         },
         "$.context.frequency_governor"},
    };
    for (const auto& b : breaks) {
        SCOPED_TRACE(b.name);
        json broken = doc;
        b.apply(broken);
        const std::string path = dir.file(b.name + ".json");
        save(path, broken);
        Outcome v = validate_against_schema({path});
        EXPECT_EQ(v.status, 1) << describe(v);
        EXPECT_NE(v.combined().find(b.expect_in_output), std::string::npos) << describe(v);
    }
    // Several files at once: one bad one makes the whole run fail, and the good one is still reported.
    Outcome mixed = validate_against_schema({good, dir.file("no_kernel.json")});
    EXPECT_EQ(mixed.status, 1) << describe(mixed);
    EXPECT_NE(mixed.combined().find(good + ": valid"), std::string::npos) << describe(mixed);
    // Not JSON at all.
    std::ofstream(dir.file("truncated.json")) << "{\"schema_version\": 1, \"results\": [";
    Outcome truncated = validate_against_schema({dir.file("truncated.json")});
    EXPECT_EQ(truncated.status, 1) << describe(truncated);
}

}  // namespace
