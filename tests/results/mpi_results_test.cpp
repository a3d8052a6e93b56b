// Result files of MPI runs (suite-mpi) read back by `suite compare` and `suite check`, on
// hand-made documents (tests/results/mpi_fixtures.hpp: two ranks on one host, four on two):
// the ranks and the aggregate of a point are points of their own, two runs meet rank by rank,
// one run's hosts (or ranks) are lined up against each other, a slow rank fails the gate when
// the aggregate hides it, an MPI run against a plain one behaves as documented, a malformed
// `mpi` is one line naming the field, and the history keeps each rank and the aggregate as series
// of their own and gates a run rank by rank.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include "harness/results/check.hpp"
#include "harness/results/compare_figures.hpp"
#include "harness/results/history.hpp"
#include "harness/results/history_gate.hpp"
#include "harness/results/result_file.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"
#include "tests/results/mpi_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

void expect_one_line_error(const Outcome& r, const std::string& needle) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "'\n" << describe(r);
}

// The line of `text` that starts with `start` (after any spaces), or "".
std::string line_of(const std::string& text, const std::string& start) {
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        const std::string line = text.substr(at, end - at);
        const std::size_t first = line.find_first_not_of(' ');
        if (first != std::string::npos && line.compare(first, start.size(), start) == 0) return line;
        at = end + 1;
    }
    return "";
}

json plain_doc() { return load(fixture("vm-native.json")); }

json latency_template() {
    return template_record(load(fixture("vm-native-latency.json")), "latency", "random", 64ULL << 20, 1);
}

// The InputError that reading `doc` throws, or "" when it reads.
std::string read_error(const json& doc) {
    try {
        parse_result_text(doc.dump(), "mpi.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// Run i of a made-up history of two ranks on vm: rank r at `slow_r` times the template's times,
// with 1 % noise between runs (each rank's level) and between repetitions, stamped as run i.
json noisy_two_rank_run(std::size_t i, Gauss& g, double slow0, double slow1) {
    json doc =
        mpi_document(plain_doc(), bandwidth_templates(), two_ranks(slow0 * (1 + 0.01 * g()), slow1 * (1 + 0.01 * g())));
    stamp(doc, i);
    for (auto& r : doc["results"]) set_times(r, noisy_times(r, 1.0, 0.01, g));
    return doc;
}

}  // namespace

TEST(MpiResultFile, RanksAndTheAggregateAreSeparatePointsAndTheFixturesAreValid) {
    TempDir dir;
    const json two = mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 1));
    const json four = mpi_document(plain_doc(), {bandwidth_templates()[0], latency_template()},
                                   four_ranks_two_hosts({1, 1, 1.25, 1.25}));
    save(two, dir.file("two.json"));
    save(four, dir.file("four.json"));
    const Outcome v = validate_against_schema({dir.file("two.json"), dir.file("four.json")});
    EXPECT_EQ(v.status, 0) << describe(v);

    const ResultFile f = load_result_file(dir.file("two.json"));
    EXPECT_TRUE(f.notes.empty()) << f.notes.size() << " note(s)";  // nothing collided
    ASSERT_EQ(f.points.size(), 6u);
    ASSERT_TRUE(f.mpi);
    EXPECT_EQ(f.mpi->ranks, 2);
    EXPECT_EQ(f.processes_label(), "2 MPI ranks on 1 host");
    std::set<PointKey> keys;
    for (const auto& p : f.points) keys.insert(p.key);
    EXPECT_EQ(keys.size(), 6u);
    EXPECT_EQ(f.points[1].key.label(), "triad sequential 64MiB t=1 compact/local rank 1 of 2");
    EXPECT_EQ(f.points[1].mpi.scope, RankOrigin::Scope::rank);
    EXPECT_EQ(f.points[1].mpi.host, "vm");
    EXPECT_EQ(f.points[2].key.label(), "triad sequential 64MiB t=2 compact/local aggregate of 2 ranks");
    EXPECT_EQ(f.points[2].mpi.scope, RankOrigin::Scope::aggregate);
    EXPECT_EQ(f.points[2].mpi.slowest_host, "vm");
    // Twice the work in the slowest rank's time: twice one rank's bandwidth.
    EXPECT_NEAR(f.points[2].measures.front().best, 2 * f.points[0].measures.front().best,
                1e-9 * f.points[0].measures.front().best);

    const ResultFile g = load_result_file(dir.file("four.json"));
    ASSERT_EQ(g.points.size(), 10u);
    ASSERT_EQ(g.mpi->hosts.size(), 2u);
    EXPECT_EQ(g.mpi->host_of(3)->host, "node-b");
    EXPECT_EQ(g.points[3].key.rank_scope, "rank 3 of 4");
    EXPECT_EQ(g.points[3].mpi.host, "node-b");
    EXPECT_EQ(g.points[4].mpi.slowest_rank, 2);
    EXPECT_NEAR(g.points[4].mpi.spread, 1.25, 1e-12);
    // Only the aggregate of a run of one rank is a plain run's point.
    EXPECT_EQ(matching_key(g.points[4].key).rank_scope, "aggregate of 4 ranks");
    PointKey one = g.points[4].key;
    one.rank_scope = rank_scope_text(-1, 1);
    EXPECT_EQ(matching_key(one).rank_scope, "");
}

TEST(MpiResultFile, AMalformedMpiFieldIsAnInputErrorNamingTheField) {
    const json good = mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 1));
    ASSERT_EQ(read_error(good), "");
    auto broken = [&](const std::function<void(json&)>& edit, const std::string& needle) {
        json doc = good;
        edit(doc);
        const std::string error = read_error(doc);
        EXPECT_NE(error.find(needle), std::string::npos) << "expected '" << needle << "' in: '" << error << "'";
        EXPECT_EQ(error.rfind("mpi.json: ", 0), 0u) << error;
    };
    broken([](json& d) { d["results"][1]["mpi"]["scope"] = "everyone"; },
           "results[1].mpi.scope: expected 'rank' or 'aggregate'");
    broken([](json& d) { d["results"][1]["mpi"]["rank"] = "1"; },
           "results[1].mpi.rank: expected a non-negative integer");
    broken([](json& d) { d["results"][1]["mpi"]["rank"] = 2; }, "results[1].mpi.rank: rank 2 of a run of 2");
    broken([](json& d) { d["results"][1]["mpi"].erase("host"); }, "results[1].mpi.host: missing");
    broken([](json& d) { d["results"][1]["mpi"]["host"] = "elsewhere"; },
           "results[1].mpi.host: 'elsewhere', but context.mpi.hosts puts rank 1 on 'vm'");
    broken([](json& d) { d["results"][1]["mpi"]["ranks"] = 3; }, "results[1].mpi.ranks: 3, but context.mpi.ranks is 2");
    broken([](json& d) { d["results"][1]["mpi"] = 1; }, "results[1].mpi: expected an object");
    broken([](json& d) { d["results"][2]["mpi"]["spread"] = 0.5; }, "results[2].mpi.spread: expected at least 1");
    broken([](json& d) { d["results"][2]["mpi"]["slowest_rank"] = -1; },
           "results[2].mpi.slowest_rank: expected a non-negative integer");
    broken([](json& d) { d["results"][2]["mpi"]["hosts"] = 2; }, "results[2].mpi.hosts: 2, but context.mpi lists 1");
    broken([](json& d) { d["results"][0].erase("mpi"); }, "results[0].mpi: missing, in a run of 2 MPI ranks");
    broken([](json& d) { d["context"].erase("mpi"); },
           "results[0].mpi: a record of an MPI run, but the context has no mpi");
    broken([](json& d) { d["context"]["mpi"]["ranks"] = "2"; }, "context.mpi.ranks: expected a non-negative integer");
    broken(
        [](json& d) {
            d["context"]["mpi"]["hosts"][0]["ranks"] = {0, 0};
        },
        "context.mpi.hosts[0].ranks[1]: rank 0 is on two hosts");
    broken([](json& d) { d["context"]["mpi"]["hosts"][0]["ranks"] = {0}; },
           "context.mpi.hosts: rank 1 of 2 is on no host");
    broken([](json& d) { d["context"]["mpi"]["hosts"] = json::array(); },
           "context.mpi.hosts: expected a non-empty array");
    // The same through the command line: one line, exit status 2.
    TempDir dir;
    json doc = good;
    doc["results"][1]["mpi"]["scope"] = 7;
    save(doc, dir.file("bad.json"));
    expect_one_line_error(run_suite({"compare", dir.file("bad.json"), dir.file("bad.json")}),
                          "results[1].mpi.scope: expected a string");
    expect_one_line_error(run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("bad.json")}),
                          "results[1].mpi.scope");
}

TEST(MpiCompare, TwoMpiRunsMeetRankWithRankAndAggregateWithAggregate) {
    TempDir dir;
    save(mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 1)), dir.file("before.json"));
    save(mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 2)), dir.file("after.json"));
    const Outcome r = run_suite({"compare", dir.file("before.json"), dir.file("after.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("6 point(s) of [1] found in another file."), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("vm (AMD EPYC), 2 MPI ranks on 1 host"), std::string::npos) << r.out;
    const std::string rank0 = line_of(r.out, "triad sequential 64MiB t=1 compact/local rank 0 of 2 on vm");
    const std::string rank1 = line_of(r.out, "triad sequential 64MiB t=1 compact/local rank 1 of 2 on vm");
    const std::string all = line_of(r.out, "triad sequential 64MiB t=2 compact/local aggregate of 2 ranks");
    EXPECT_NE(rank0.find("1.000x"), std::string::npos) << r.out;
    EXPECT_NE(rank1.find("0.500x"), std::string::npos) << "rank 1 took twice as long\n" << r.out;
    EXPECT_NE(all.find("0.500x"), std::string::npos) << "the aggregate waits for the slowest rank\n" << r.out;

    // Runs of different rank counts have no point in common, and the error says why.
    save(mpi_document(plain_doc(), bandwidth_templates(), four_ranks_two_hosts({1, 1, 1, 1})), dir.file("four.json"));
    const Outcome mixed = run_suite({"compare", dir.file("before.json"), dir.file("four.json")});
    expect_one_line_error(mixed, "no point of");
    EXPECT_NE(mixed.err.find("[1] is a run of 2 MPI ranks on 1 host and [2] of 4 MPI ranks on 2 hosts"),
              std::string::npos)
        << mixed.err;
}

TEST(MpiCompare, OneMpiFileLinesUpItsHostsAndNamesTheSlowerOne) {
    TempDir dir;
    const std::vector<json> templates{bandwidth_templates()[0], bandwidth_templates()[1], latency_template()};
    save(mpi_document(plain_doc(), templates, four_ranks_two_hosts({1, 1, 1.25, 1.25})), dir.file("cluster.json"));
    const Outcome r = run_suite({"compare", dir.file("cluster.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("the hosts of one MPI run"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("node-a (2 ranks)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("node-b (2 ranks)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("The hosts are alike as machines"), std::string::npos) << r.out;
    // A host's bandwidth is the sum of its ranks' best: node-a has two ranks at the template's.
    const double best = templates[0]["bandwidth_gbps"]["stream"]["best"].get<double>();
    const std::string triad = line_of(r.out, "triad sequential 64MiB t=1/rank compact/local");
    ASSERT_FALSE(triad.empty()) << r.out;
    EXPECT_NE(triad.find(compare_value_text(2 * best) + "  "), std::string::npos) << triad;
    EXPECT_NE(triad.find("1.000x"), std::string::npos) << triad;
    EXPECT_NE(triad.find("0.800x"), std::string::npos) << "node-b's ranks took 1.25 times as long\n" << triad;
    EXPECT_NE(triad.find("node-b"), std::string::npos) << triad;
    EXPECT_NE(triad.find("1.250"), std::string::npos) << "the aggregate's rank spread\n" << triad;
    // Latency: the worst rank's, lower is better, and the ratio is still performance.
    const std::string latency = line_of(r.out, "latency random 64MiB t=1/rank compact/local");
    EXPECT_NE(latency.find("0.800x"), std::string::npos) << latency;
    EXPECT_NE(latency.find("node-b"), std::string::npos) << latency;
    EXPECT_NE(line_of(r.out, "all kernels").find("0.800x"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Slowest most often: node-b, at 3 of 3 point(s)."), std::string::npos) << r.out;
    const Outcome md = run_suite({"compare", dir.file("cluster.json"), "--format=markdown"});
    ASSERT_EQ(md.status, 0) << describe(md);
    EXPECT_NE(md.out.find("### Hosts"), std::string::npos) << md.out;
    EXPECT_NE(md.out.find("| node-b (2 ranks) | vs fastest |"), std::string::npos) << md.out;
}

TEST(MpiCompare, OneMpiFileOnOneHostLinesUpItsRanks) {
    TempDir dir;
    save(mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 1.1)), dir.file("two.json"));
    const Outcome r = run_suite({"compare", dir.file("two.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("the ranks of one MPI run"), std::string::npos) << r.out;
    const std::string add = line_of(r.out, "add random 64MiB t=1/rank compact/local");
    EXPECT_NE(add.find("0.909x"), std::string::npos) << add;
    EXPECT_NE(add.find("rank 1"), std::string::npos) << add;
    EXPECT_NE(r.out.find("Slowest most often: rank 1, at 2 of 2 point(s)."), std::string::npos) << r.out;
    // A run of one rank has nothing to line up; a plain file alone still asks for two files.
    save(mpi_document(plain_doc(), bandwidth_templates(), {{{"vm", {0}}}, {1}}), dir.file("one.json"));
    expect_one_line_error(run_suite({"compare", dir.file("one.json")}), "an MPI run of one rank on one host");
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json")}), "at least two");
}

TEST(MpiCompare, APlainRunMeetsOnlyTheAggregateOfARunOfOneRank) {
    TempDir dir;
    save(mpi_document(plain_doc(), bandwidth_templates(), {{{"vm", {0}}}, {1}}), dir.file("one.json"));
    save(mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1, 1)), dir.file("two.json"));
    const Outcome one = run_suite({"compare", fixture("vm-native.json"), dir.file("one.json")});
    ASSERT_EQ(one.status, 0) << describe(one);
    EXPECT_NE(one.out.find("2 point(s) of [1] found in another file; 124 of [1] in no other file (not shown). 2 "
                           "point(s) of [2] are not in [1]."),
              std::string::npos)
        << one.out;
    EXPECT_NE(line_of(one.out, "triad sequential 64MiB t=1 compact/local").find("1.000x"), std::string::npos)
        << one.out;
    EXPECT_NE(one.out.find("1 MPI rank on 1 host (split): vm [0]"), std::string::npos)
        << "the processes are a context difference\n"
        << one.out;
    const Outcome two = run_suite({"compare", fixture("vm-native.json"), dir.file("two.json")});
    expect_one_line_error(two, "no point of");
    EXPECT_NE(two.err.find("[1] is a run of one process and [2] of 2 MPI ranks on 1 host"), std::string::npos)
        << two.err;
    // The gate likewise: a plain baseline gates the aggregate of one rank, and nothing of two.
    const Outcome gate = run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("one.json")});
    EXPECT_EQ(gate.status, 0) << describe(gate);
    EXPECT_NE(gate.out.find("2 point(s) compared, 2 figure(s): 0 regressed"), std::string::npos) << gate.out;
    EXPECT_NE(gate.out.find("2 point(s) of the run are not in the baseline"), std::string::npos) << gate.out;
    const Outcome refused = run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("two.json")});
    expect_one_line_error(refused, "none of the 6 point(s)");
    EXPECT_NE(refused.err.find("the baseline is a run of one process and the run of 2 MPI ranks on 1 host"),
              std::string::npos)
        << refused.err;
}

TEST(MpiCheck, ASlowRankFailsTheGateThoughTheAggregateBarelyMoved) {
    TempDir dir;
    // In the baseline rank 0 was the slow one; in the run rank 1 is 30 % slower than it was,
    // which moves the aggregate (the slowest rank's time) by 4 % only.
    const json base = mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1.25, 1.0));
    const json run = mpi_document(plain_doc(), bandwidth_templates(), two_ranks(1.25, 1.3));
    save(base, dir.file("base.json"));
    save(run, dir.file("run.json"));
    const Outcome r = run_suite({"check", "--baseline", dir.file("base.json"), dir.file("run.json")});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.out.find("REGRESSED  triad sequential 64MiB t=1 compact/local rank 1 of 2 on vm"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("REGRESSED  add random 64MiB t=1 compact/local rank 1 of 2 on vm"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("6 point(s) compared, 6 figure(s): 2 regressed, 0 improved, 4 within the threshold"),
              std::string::npos)
        << r.out;
    const CheckReport rep =
        check_run(load_result_file(dir.file("base.json")), load_result_file(dir.file("run.json")), GateRule{});
    bool saw_aggregate = false;
    for (const auto& f : rep.findings) {
        if (f.key.rank_scope != "aggregate of 2 ranks") continue;
        saw_aggregate = true;
        EXPECT_EQ(f.verdict, Verdict::unchanged) << f.key.label();
        EXPECT_NEAR(f.run / f.baseline - 1, 1.25 / 1.3 - 1, 1e-9) << f.key.label();
    }
    EXPECT_TRUE(saw_aggregate);
    // A run against itself passes; on two hosts, the slow host's ranks are named with it.
    EXPECT_EQ(run_suite({"check", "--baseline", dir.file("run.json"), dir.file("run.json")}).status, 0);
    save(mpi_document(plain_doc(), bandwidth_templates(), four_ranks_two_hosts({1, 1, 1, 1})), dir.file("base4.json"));
    save(mpi_document(plain_doc(), bandwidth_templates(), four_ranks_two_hosts({1, 1, 1.3, 1.3})),
         dir.file("run4.json"));
    const Outcome four = run_suite({"check", "--baseline", dir.file("base4.json"), dir.file("run4.json")});
    EXPECT_EQ(four.status, 1) << describe(four);
    EXPECT_NE(four.out.find("REGRESSED  triad sequential 64MiB t=1 compact/local rank 3 of 4 on node-b"),
              std::string::npos)
        << four.out;
    EXPECT_EQ(four.out.find("rank 0 of 4 on node-a"), std::string::npos) << "node-a did not change\n" << four.out;
}

TEST(MpiHistory, EachRankAndTheAggregateAreSeriesOfTheirOwn) {
    TempDir dir;
    Gauss g{7};
    std::vector<std::string> args{"history", "add"};
    std::vector<ResultFile> runs;
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string path = dir.file("run" + std::to_string(i) + ".json");
        save(noisy_two_rank_run(i, g, 1, 1.5), path);
        args.push_back(path);
        runs.push_back(load_result_file(path));
    }
    const std::string db = dir.file("history.sqlite");
    args.insert(args.end(), {"--db", db});
    const Outcome added = run_suite(args);
    ASSERT_EQ(added.status, 0) << describe(added);

    const History h = History::open_for_reading(db);
    EXPECT_EQ(h.schema_version(), history_schema_version);
    const std::vector<Series> series = h.series();
    std::size_t figures = 0;
    for (const auto& p : runs[0].points) figures += p.measures.size();
    ASSERT_EQ(series.size(), figures) << "one series a figure of each rank's point and of each aggregate";
    ASSERT_EQ(h.summary().at(0).series, figures);
    std::map<std::string, std::size_t> per_scope;
    for (const Series& s : series) {
        ++per_scope[s.key.rank_scope];
        ASSERT_EQ(s.entries.size(), runs.size()) << s.key.label();
        // Entry i is run i's own median of this rank (or the aggregate): nothing of another mixed in.
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const Measure* m = nullptr;
            for (const auto& p : runs[i].points)
                for (const auto& x : p.measures)
                    if (p.key == s.key && x.name == s.figure && x.unit == s.unit) m = &x;
            ASSERT_NE(m, nullptr) << s.key.label() << " " << s.figure;
            EXPECT_DOUBLE_EQ(s.entries[i].median, m->median) << s.key.label() << " " << s.figure << ", run " << i;
        }
    }
    EXPECT_EQ(per_scope,
              (std::map<std::string, std::size_t>{
                  {"aggregate of 2 ranks", figures / 3}, {"rank 0 of 2", figures / 3}, {"rank 1 of 2", figures / 3}}));
    // The slow rank's bandwidth series sits at its own level, two thirds of rank 0's.
    auto bandwidth_of = [&](const std::string& scope) {
        for (const Series& s : series)
            if (s.key.kernel == "triad" && s.key.rank_scope == scope && s.figure == "bandwidth")
                return s.entries.at(0).median;
        ADD_FAILURE() << "no triad bandwidth series of " << scope;
        return 0.0;
    };
    EXPECT_NEAR(bandwidth_of("rank 1 of 2") / bandwidth_of("rank 0 of 2"), 1 / 1.5, 0.05);
    // Each rank's record keeps the host it ran on; an aggregate has none.
    SqlDatabase raw = SqlDatabase::open(db, {false, false, 1000});
    SqlStatement hosts = raw.prepare("SELECT DISTINCT rank_scope, rank_host FROM records ORDER BY 1");
    std::vector<std::pair<std::string, std::string>> seen;
    while (hosts.step()) seen.emplace_back(hosts.text(0), hosts.text(1));
    EXPECT_EQ(seen, (std::vector<std::pair<std::string, std::string>>{
                        {"aggregate of 2 ranks", ""}, {"rank 0 of 2", "vm"}, {"rank 1 of 2", "vm"}}));
}

TEST(MpiHistory, HistoryCheckGatesRankWithRankAndNamesTheSlowOne) {
    TempDir dir;
    Gauss g{11};
    const std::string db = dir.file("history.sqlite");
    {
        History h = History::open_for_adding(db);
        for (std::size_t i = 0; i < 6; ++i)
            h.add({parse_result_text(noisy_two_rank_run(i, g, 1, 1).dump(), "run.json")}, "", "main");
    }
    save(noisy_two_rank_run(10, g, 1, 1), dir.file("same.json"));
    save(noisy_two_rank_run(11, g, 1, 1.4), dir.file("slow.json"));
    const Outcome same = run_suite({"history", "check", dir.file("same.json"), "--db", db});
    EXPECT_EQ(same.status, 0) << describe(same);
    EXPECT_NE(same.out.find("6 run(s) of the history pooled"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("6 point(s) compared"), std::string::npos) << same.out;
    EXPECT_EQ(same.out.find("REGRESSED"), std::string::npos) << same.out;
    // The window is of the run's own processes, rank by rank: no context difference to note.
    EXPECT_EQ(same.out.find("the context differs"), std::string::npos) << same.out;
    // Rank 1 takes 40 % longer; the aggregate, which waits for it, too; rank 0 is as it was.
    const Outcome slow = run_suite({"history", "check", dir.file("slow.json"), "--db", db});
    EXPECT_EQ(slow.status, 1) << describe(slow);
    EXPECT_NE(slow.out.find("REGRESSED  triad sequential 64MiB t=1 compact/local rank 1 of 2 on vm"), std::string::npos)
        << slow.out;
    EXPECT_NE(slow.out.find("REGRESSED  add random 64MiB t=1 compact/local rank 1 of 2 on vm"), std::string::npos)
        << slow.out;
    EXPECT_NE(slow.out.find("REGRESSED  triad sequential 64MiB t=2 compact/local aggregate of 2 ranks"),
              std::string::npos)
        << slow.out;
    EXPECT_EQ(slow.out.find("rank 0 of 2"), std::string::npos) << "rank 0 did not change\n" << slow.out;

    // The window's baseline holds each rank's own history: the run's rank against its own level.
    const ResultFile run = load_result_file(dir.file("slow.json"));
    const History h = History::open_for_reading(db);
    const RunIdentity id = identify_run(run);
    SeriesFilter f;
    f.fingerprints = {id.fingerprint};
    f.context_class = id.context_class;
    const WindowBaseline base = window_baseline(h.series(f), run, id, 0, 10, db);
    EXPECT_EQ(base.runs_pooled, 6u);
    ASSERT_EQ(base.file.points.size(), run.points.size());
    const CheckReport rep = check_run(base.file, run, GateRule{}, true);
    std::set<std::string> scopes;
    for (const Finding& x : rep.findings) {
        if (x.figure != "bandwidth GB/s") continue;
        scopes.insert(x.key.rank_scope);
        const bool slowed = x.key.rank_scope != "rank 0 of 2";
        EXPECT_EQ(x.verdict, slowed ? Verdict::regressed : Verdict::unchanged) << x.key.label();
        EXPECT_NEAR(x.run / x.baseline, slowed ? 1 / 1.4 : 1.0, 0.04) << x.key.label();
    }
    EXPECT_EQ(scopes, (std::set<std::string>{"aggregate of 2 ranks", "rank 0 of 2", "rank 1 of 2"}));
}
