// The aggregate of an MPI run's point (results/ranks.hpp), from rank records as each rank
// renders them: the work adds up, each repetition takes the slowest rank's time, a failure on
// any rank fails it, and the slowest rank is named. No MPI needed.
#include <gtest/gtest.h>

#include "harness/measure/runner.hpp"
#include "harness/results/ranks.hpp"
#include "harness/results/report.hpp"

using namespace suite;

namespace {

Record rank_record(int rank, const std::string& host, std::vector<double> samples, double bytes, int threads = 2) {
    Record r;
    r.kernel = r.name = "triad";
    r.access = "sequential";
    r.metric = Metric::bandwidth;
    r.threads = threads;
    r.work.units = bytes / 24;
    r.work.stream_bytes = bytes;
    r.work.hardware_bytes = bytes * 4 / 3;
    r.work.flops = bytes / 12;
    r.work.footprint_bytes = static_cast<std::uint64_t>(bytes);
    r.samples_s = std::move(samples);
    r.repetitions = static_cast<int>(r.samples_s.size());
    r.time = summarise(r.samples_s);
    r.rates = derive_rates(r.work, r.time, r.metric, r.threads);
    r.binding_held = true;
    for (int t = 0; t < threads; ++t) r.bindings.push_back({t, 10 * rank + t, {10 * rank + t}, 10 * rank + t, rank});
    r.verification.passed = true;
    r.verification.detail = "ok";
    r.mpi.kind = RankScope::Kind::rank;
    r.mpi.rank = rank;
    r.mpi.ranks = 3;
    r.mpi.host = host;
    return r;
}

}  // namespace

TEST(Ranks, AggregateAddsTheWorkOverTheSlowestRankOfEachRepetition) {
    const std::vector<Record> ranks = {rank_record(0, "a", {1.0, 2.0, 1.5}, 24e9),
                                       rank_record(1, "a", {1.2, 1.1, 3.0}, 24e9),
                                       rank_record(2, "b", {0.9, 2.5, 1.0}, 48e9, 4)};
    std::vector<RankRun> runs;
    for (const Record& r : ranks) runs.push_back(rank_run_from_json(to_json(r)));
    const Record all = aggregate_record(ranks[0], runs, 2);
    EXPECT_EQ(all.threads, 8);
    EXPECT_DOUBLE_EQ(all.work.stream_bytes, 96e9);
    EXPECT_DOUBLE_EQ(all.work.units, 4e9);
    EXPECT_EQ(all.work.footprint_bytes, 96000000000u);
    EXPECT_EQ(all.samples_s, (std::vector<double>{1.2, 2.5, 3.0}));
    EXPECT_DOUBLE_EQ(all.time.min, 1.2);
    EXPECT_DOUBLE_EQ(*all.rates.stream_gbps_best, 96e9 / 1.2 / 1e9);  // the sum moved over the slowest time
    EXPECT_TRUE(all.verification.passed);
    EXPECT_EQ(all.mpi.kind, RankScope::Kind::aggregate);
    EXPECT_EQ(all.mpi.ranks, 3);
    EXPECT_EQ(all.mpi.hosts, 2);
    // best times 1.0, 1.1, 0.9: rank 1 is the slowest, 1.1 / 0.9 the spread
    EXPECT_EQ(all.mpi.slowest_rank, 1);
    EXPECT_EQ(all.mpi.slowest_host, "a");
    EXPECT_NEAR(all.mpi.spread, 1.1 / 0.9, 1e-12);
    ASSERT_EQ(all.bindings.size(), 8u);  // every rank's threads, in rank order, numbered on
    EXPECT_EQ(all.bindings[2].thread, 2);
    EXPECT_EQ(all.bindings[2].cpu, 10);
    EXPECT_EQ(all.bindings[7].allowed, (std::vector<int>{23}));
    EXPECT_EQ(all.bindings[7].numa_node, 2);
    EXPECT_FALSE(all.energy.available);
    EXPECT_NE(all.energy.reason.find("each rank's record"), std::string::npos);
    const nlohmann::json j = to_json(all);
    EXPECT_EQ(j["mpi"]["scope"], "aggregate");
    EXPECT_EQ(j["mpi"]["slowest_rank"], 1);
    EXPECT_FALSE(j["mpi"].contains("rank"));
    EXPECT_EQ(to_json(ranks[2])["mpi"], (nlohmann::json{{"scope", "rank"}, {"rank", 2}, {"ranks", 3}, {"host", "b"}}));
}

TEST(Ranks, OneRankFailingFailsTheAggregateAndIsNamed) {
    std::vector<Record> ranks = {rank_record(0, "a", {1.0, 1.0}, 1e9), rank_record(1, "b", {1.0, 1.0}, 1e9)};
    ranks[1].verification.passed = false;
    ranks[1].verification.detail = "a[7] = 3, expected 4";
    ranks[1].verification.max_error = 1;
    std::vector<RankRun> runs;
    for (const Record& r : ranks) runs.push_back(rank_run_from_json(to_json(r)));
    const Record all = aggregate_record(ranks[0], runs, 2);
    EXPECT_FALSE(all.verification.passed);
    EXPECT_EQ(all.verification.detail, "rank 1 (b): a[7] = 3, expected 4");
    EXPECT_EQ(all.verification.max_error, 1);
    ranks[1].verification.solver_failed = true;
    runs[1] = rank_run_from_json(to_json(ranks[1]));
    EXPECT_TRUE(aggregate_record(ranks[0], runs, 2).verification.solver_failed);
}

TEST(Ranks, RanksThatTimedDifferentRepetitionsOrLackAFieldAreRefused) {
    const Record a = rank_record(0, "a", {1.0, 1.0}, 1e9), b = rank_record(1, "a", {1.0}, 1e9);
    EXPECT_THROW(aggregate_record(a, {rank_run_from_json(to_json(a)), rank_run_from_json(to_json(b))}, 1),
                 std::logic_error);
    nlohmann::json j = to_json(a);
    j["work_per_repetition"].erase("stream_bytes");
    try {
        rank_run_from_json(j);
        FAIL() << "a record without its work was read";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "a rank's record lacks work_per_repetition.stream_bytes");
    }
    nlohmann::json plain = to_json(a);
    plain.erase("mpi");
    EXPECT_THROW(rank_run_from_json(plain), std::runtime_error);
}
