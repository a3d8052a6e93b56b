// Fuzz-style robustness of the result-file readers: truncated, byte-mutated and structurally
// mutated copies of real result files (tests/fixtures/results) go to the loader in process (a
// few thousand cases) and to `suite compare` and `suite check` as programs (a few hundred). The
// loader may accept a file or refuse it with InputError, nothing else; the programs may end
// with 0, 1 or 2, never a signal, and a refusal is one line. Seeded, and bounded in time.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <random>

#include "harness/results/check.hpp"
#include "harness/results/compare.hpp"
#include "harness/results/result_file.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

std::string fixture(const std::string& name) {
    return slurp(std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/" + name);
}

// One mutation of `text`, chosen by `rng`: a truncation, a few bytes changed, or a JSON value
// replaced or removed (which gets past the parser into the field checks).
std::string mutate(const std::string& text, const json& doc, const std::vector<std::string>& leaves,
                   std::mt19937_64& rng) {
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
    switch (pick(3)) {
        case 0:
            return text.substr(0, pick(text.size()));
        case 1: {
            static const char bytes[] = {'{', '}', '[', ']',  '"',  ',',    ':', '0', '-',
                                         'e', 'n', 'x', '\\', '\0', '\xff', ' ', '9'};
            std::string t = text;
            for (std::size_t k = 0, n = 1 + pick(4); k < n; ++k) t[pick(t.size())] = bytes[pick(sizeof bytes)];
            return t;
        }
        default: {
            static const json replacements[] = {nullptr,
                                                -1,
                                                0,
                                                1e308,
                                                -0.0,
                                                "",
                                                "x",
                                                json::array(),
                                                json::object(),
                                                true,
                                                18446744073709551615ULL,
                                                -9223372036854775807LL,
                                                json::array({1, "a"})};
            json d = doc;
            // A leaf, or one of its ancestors, so that whole objects and arrays change too.
            json::json_pointer p(leaves[pick(leaves.size())]);
            for (std::size_t up = pick(4); up > 0 && !p.empty(); --up) p = p.parent_pointer();
            if (p.empty()) return d.dump();
            if (pick(3) == 0) {
                json& parent = d[p.parent_pointer()];
                if (parent.is_object())
                    parent.erase(p.back());
                else if (parent.is_array() && !parent.empty())
                    parent.erase(parent.begin());
            } else {
                d[p] = replacements[pick(std::size(replacements))];
            }
            return d.dump();
        }
    }
}

std::vector<std::string> leaves_of(const json& doc) {
    std::vector<std::string> out;
    const json flat = doc.flatten();  // kept alive: items() is a view of it
    for (const auto& [pointer, value] : flat.items()) out.push_back(pointer);
    return out;
}

}  // namespace

TEST(FuzzResults, TheLoaderAcceptsOrRefusesCleanly) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(6);
    std::mt19937_64 rng(20261122);
    std::size_t cases = 0, accepted = 0;
    for (const char* name : {"vm-native-latency.json", "vm-native-HANDMADE-counters-energy.json"}) {
        const std::string text = fixture(name);
        const json doc = json::parse(text);
        const std::vector<std::string> leaves = leaves_of(doc);
        const ResultFile good = parse_result_text(text, name);
        for (int i = 0; i < 1500 && std::chrono::steady_clock::now() < deadline; ++i, ++cases) {
            const std::string bad = mutate(text, doc, leaves, rng);
            try {
                const ResultFile f = parse_result_text(bad, "mutated.json");
                ++accepted;
                // What was accepted can be compared and gated without surprises.
                try {
                    (void)render_comparison({good, f}, i % 2 == 0);
                    (void)render_check_text(check_run(good, f, GateRule{0.1}));
                } catch (const InputError&) {
                }
            } catch (const InputError& e) {
                EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            } catch (const std::exception& e) {
                ADD_FAILURE() << "case " << i << " of " << name << ": not an InputError: " << e.what();
            }
        }
    }
    std::printf("fuzz: %zu mutated files, %zu accepted\n", cases, accepted);
    EXPECT_GT(cases, 500u);
    EXPECT_GT(accepted, 0u) << "some mutations (a changed number, say) must still be readable";
}

TEST(FuzzResults, CompareAndCheckNeverCrash) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(12);
    TempDir dir;
    const std::string base_path = std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/vm-native-latency.json";
    const std::string text = fixture("vm-native-latency.json");
    const json doc = json::parse(text);
    const std::vector<std::string> leaves = leaves_of(doc);
    std::mt19937_64 rng(4);
    int runs = 0;
    for (int i = 0; i < 150 && std::chrono::steady_clock::now() < deadline; ++i) {
        const std::string path = dir.file("m" + std::to_string(i) + ".json");
        { std::ofstream(path, std::ios::binary) << mutate(text, doc, leaves, rng); }
        const std::vector<std::string> args = i % 2 ? std::vector<std::string>{"compare", base_path, path}
                                                    : std::vector<std::string>{"check", "--baseline", base_path, path};
        const Outcome r = run_suite(args, 30);
        ++runs;
        SCOPED_TRACE("suite " + join(args) + "\n" + describe(r));
        EXPECT_FALSE(r.timed_out);
        EXPECT_EQ(r.term_signal, 0);
        EXPECT_TRUE(r.status == 0 || r.status == 1 || r.status == 2);
        if (r.status == 1) {
            EXPECT_EQ(args[0], "check") << "compare has no exit status 1";
        }
        if (r.status == 2) {
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
        }
    }
    std::printf("fuzz: %d runs of compare/check\n", runs);
    EXPECT_GT(runs, 40);
}
