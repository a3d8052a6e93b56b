// The named choices of the machine, the output and energy options (--pin, --placement, --format,
// --energy): every name of a table parses to its behaviour, and an unknown name is refused with
// a "did you mean" and the list read from the same table.
#include <gtest/gtest.h>

#include <string>

#include "harness/common/units.hpp"
#include "harness/instruments/energy.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"
#include "harness/measure/plan.hpp"
#include "rapl/energy.hpp"
#include "tests/synthetic_topology.hpp"

using namespace suite;
using suite::testing::two_socket;

namespace {

// The UsageError `f` throws; "" when it throws none.
template <class F>
std::string refusal(F f) {
    try {
        f();
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Pinning, EveryNamedModeParsesAndAnUnknownOneListsTheTable) {
    const Topology t = two_socket();
    ASSERT_EQ(pin_modes().accepted(), "compact, scatter, none");
    for (const auto& c : pin_modes().all()) {
        const PinSpec spec = parse_pin(c.name, t);
        EXPECT_EQ(spec.mode, c.what) << c.name;
        EXPECT_EQ(spec.text, c.name);
        EXPECT_EQ(pin_name(c.what), c.name);
    }
    EXPECT_EQ(parse_pin("0,2", t).mode, PinMode::list);
    EXPECT_EQ(refusal([&] { parse_pin("scater", t); }),
              "unknown --pin value 'scater' (did you mean 'scatter'?); accepted: compact, scatter, none, or a CPU "
              "list such as 0,2,4-7");
}

TEST(Placement, EveryKindParsesAndAnUnknownOneListsTheTable) {
    const Topology t = two_socket();
    ASSERT_EQ(placement_forms(), "local, node:N, remote, interleave");
    for (const auto& c : placement_kinds().all()) {
        const std::string text = c.what.takes_node ? c.name + ":1" : c.name;
        const PlacementSpec spec = parse_placement(text, t);
        EXPECT_EQ(spec.kind, c.what.kind) << text;
        EXPECT_EQ(spec.text, text);
        EXPECT_EQ(placement_name(c.what.kind), c.name);
        // A kind that takes a node is refused without one, and one that takes none with one.
        EXPECT_NE(refusal([&] { parse_placement(c.what.takes_node ? c.name : c.name + ":1", t); }), "") << c.name;
    }
    EXPECT_EQ(parse_placement("node:1", t).node, 1);
    EXPECT_EQ(refusal([&] { parse_placement("interleaved", t); }),
              "unknown --placement 'interleaved' (did you mean 'interleave'?); accepted: local, node:N, remote, "
              "interleave");
    EXPECT_EQ(refusal([&] { parse_placement("node", t); }),
              "unknown --placement 'node' (did you mean 'node:0'?); accepted: local, node:N, remote, interleave");
    Topology one = t;
    one.nodes.resize(1);
    EXPECT_EQ(refusal([&] { parse_placement("remote", one); }),
              "--placement=remote needs at least 2 NUMA nodes, and this machine has 1; use local, node:N or "
              "interleave");
}

TEST(OutputFormats, EveryFormatParsesAndAnUnknownOneListsTheTable) {
    const Topology t = two_socket();
    RunOptions o;
    o.kernels = "triad";
    o.size = "1MiB";
    o.threads = "1";
    ASSERT_EQ(output_formats().accepted(), "table, json, csv, gbench");
    for (const auto& c : output_formats().all()) {
        o.format = c.name;
        o.out.clear();
        EXPECT_EQ(make_plan(o, t).format, c.what.format) << c.name;
        EXPECT_EQ(format_name(c.what.format), c.name);
        o.out = "r.out";
        if (c.what.to_file)
            EXPECT_EQ(make_plan(o, t).format, c.what.format) << c.name;
        else
            EXPECT_EQ(refusal([&] { make_plan(o, t); }),
                      "--format=" + c.name + " cannot be written to a file; use json, csv or gbench with --out");
    }
    o.format.clear();
    o.out.clear();
    EXPECT_EQ(make_plan(o, t).format, OutputFormat::table);
    o.out = "r.csv";
    EXPECT_EQ(make_plan(o, t).format, OutputFormat::csv);
    o.out = "r.json";
    EXPECT_EQ(make_plan(o, t).format, OutputFormat::json);
    o.format = "jsn";
    EXPECT_EQ(refusal([&] { make_plan(o, t); }),
              "unknown --format 'jsn' (did you mean 'json'?); accepted: table, json, csv, gbench");
}

TEST(EnergyBackends, EveryNameParsesAndAnUnknownOneListsTheTable) {
    ASSERT_EQ(energy_backends().accepted(), "auto, sysfs, perf, none");
    for (const auto& c : energy_backends().all()) {
        EXPECT_EQ(parse_energy_backend(c.name), c.what.backend) << c.name;
        EXPECT_EQ(energy_backend_name(c.what.backend), c.name);
    }
    EXPECT_EQ(refusal([] { parse_energy_backend("sysf"); }),
              "--energy=sysf is not a backend; accepted: auto, sysfs, perf, none (did you mean 'sysfs'?)");
    // Without an opener (a program that reads no energy) only auto and none mean anything.
    EXPECT_EQ(refusal([] { make_instruments("none", "perf", {}); }),
              "--energy=perf: this program reads no energy; accepted: auto, none");
}
