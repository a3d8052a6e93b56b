// The step detection of ./suite info --probe on synthetic latency curves: clean ones, noisy ones,
// a VM whose last-level cache is much smaller than reported (or missing), and curves that end
// before memory. Pure functions: no timing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "harness/measure/cache_steps.hpp"

using namespace suite;

namespace {

constexpr std::uint64_t KiB = 1024, MiB = 1024 * KiB;

struct Level {
    double capacity;  // bytes
    double latency;   // ns when every load hits this level
};

// Latency of a random chase over footprint F through `levels` and then memory: a level keeps
// the fraction (C/F)^2 of a footprint larger than it, so each rise is gradual (most of it over
// the octave after C), like a real one. sharp = true: all or nothing at the capacity (LRU on a
// cyclic walk).
double model_latency(double f, const std::vector<Level>& levels, double memory, bool sharp = false) {
    double lat = levels.front().latency;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const double next = i + 1 < levels.size() ? levels[i + 1].latency : memory;
        const double kept = levels[i].capacity / f;
        const double miss = f <= levels[i].capacity ? 0.0 : sharp ? 1.0 : 1.0 - kept * kept;
        lat += miss * (next - levels[i].latency);
    }
    return lat;
}

// Sizes from 4 KiB to `top`, four a factor of two, as the probe sweeps them.
std::vector<double> sweep_sizes(double top) {
    std::vector<double> s;
    for (double f = 4 * KiB; f <= top * 1.0001; f *= std::pow(2.0, 0.25)) s.push_back(std::floor(f / 64) * 64);
    return s;
}

std::vector<CurvePoint> curve(const std::vector<Level>& levels, double memory, double top, bool sharp = false) {
    std::vector<CurvePoint> c;
    for (double f : sweep_sizes(top))
        c.push_back({static_cast<std::uint64_t>(f), model_latency(f, levels, memory, sharp)});
    return c;
}

// Multiplicative noise, log-normal with the given spread (`memory_spread` for points at 60 ns
// and more: on a shared machine the memory latency varies far more than a cache's), from a
// fixed seed; plus `spikes` single points made 3x slower (another process took the CPU).
std::vector<CurvePoint> noisy(std::vector<CurvePoint> c, double spread, int spikes, unsigned seed,
                              double memory_spread = -1) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    for (auto& p : c) p.value *= std::exp(n(rng) * (p.value >= 60 && memory_spread >= 0 ? memory_spread : spread));
    std::uniform_int_distribution<std::size_t> pick(1, c.size() - 2);
    for (int k = 0; k < spikes; ++k) c[pick(rng)].value *= 3;
    return c;
}

// `got` within [lo, hi] times `want`.
void expect_near_capacity(std::optional<std::uint64_t> got, double want, double lo = 0.85, double hi = 1.35) {
    ASSERT_TRUE(got.has_value());
    EXPECT_GE(static_cast<double>(*got), lo * want) << *got << " vs " << want;
    EXPECT_LE(static_cast<double>(*got), hi * want) << *got << " vs " << want;
}

// The curve and what was found in it, for failure messages.
std::string describe(const Steps& s) {
    std::string out;
    for (std::size_t i = 0; i < s.curve.size(); ++i)
        out += std::to_string(i) + " " + std::to_string(s.curve[i].size_bytes) + " " +
               std::to_string(s.curve[i].value) + "\n";
    for (const auto& p : s.plateaus)
        out += "plateau " + std::to_string(p.first) + "-" + std::to_string(p.last) + " at " + std::to_string(p.value) +
               "\n";
    for (auto c : s.capacities) out += "capacity " + std::to_string(c) + "\n";
    return out;
}

const std::vector<Level> three_levels = {{48.0 * KiB, 1.0}, {2.0 * MiB, 4.0}, {32.0 * MiB, 14.0}};

}  // namespace

TEST(CacheSteps, CleanThreeLevelCurveGivesEachCapacityAndMemory) {
    for (bool sharp : {false, true}) {
        const Hierarchy h =
            read_hierarchy(find_steps(curve(three_levels, 110, 256 * MiB, sharp), latency_step_options()));
        ASSERT_EQ(h.levels.size(), 3u) << (sharp ? "sharp" : "gradual");
        for (std::size_t i = 0; i < 3; ++i) {
            expect_near_capacity(h.levels[i].capacity_bytes, three_levels[i].capacity);
            EXPECT_NEAR(h.levels[i].latency_ns, three_levels[i].latency, 0.1 * three_levels[i].latency);
            EXPECT_EQ(h.levels[i].level, static_cast<int>(i) + 1);
        }
        ASSERT_TRUE(h.memory_latency_ns);
        EXPECT_NEAR(*h.memory_latency_ns, 110, 15);
    }
}

TEST(CacheSteps, NoiseAndSpikesDoNotAddOrMoveLevels) {
    // 8 % noise on every point and three 3x spikes, over twenty seeds.
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const auto c = noisy(curve(three_levels, 110, 256 * MiB), 0.08, 3, seed);
        const Hierarchy h = read_hierarchy(find_steps(c, latency_step_options()));
        ASSERT_EQ(h.levels.size(), 3u) << "seed " << seed;
        for (std::size_t i = 0; i < 3; ++i)
            expect_near_capacity(h.levels[i].capacity_bytes, three_levels[i].capacity, 0.7, 1.6);
        ASSERT_TRUE(h.memory_latency_ns) << "seed " << seed;
    }
}

TEST(CacheSteps, VmWhoseLastLevelIsFarSmallerThanReported) {
    // hwloc says 32 MiB of L3; the chase sees 6 MiB of it, then memory at 250 ns with 30 %
    // noise (neighbours sharing the host's cache and memory), 3 % in the caches.
    const std::vector<Level> vm = {{48.0 * KiB, 1.1}, {2.0 * MiB, 3.7}, {6.0 * MiB, 17.0}};
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const Steps steps =
            find_steps(noisy(curve(vm, 250, 64 * MiB, true), 0.03, 2, seed, 0.3), latency_step_options());
        const Hierarchy h = read_hierarchy(steps);
        ASSERT_EQ(h.levels.size(), 3u) << "seed " << seed << "\n" << describe(steps);
        expect_near_capacity(h.levels[2].capacity_bytes, 6.0 * MiB, 0.7, 1.6);
        ASSERT_TRUE(h.memory_from);
        EXPECT_LT(*h.memory_from, 16 * MiB);
    }
}

TEST(CacheSteps, VmWithoutAnyThirdLevel) {
    const std::vector<Level> vm = {{48.0 * KiB, 1.1}, {2.0 * MiB, 3.7}};
    const Steps steps = find_steps(noisy(curve(vm, 250, 32 * MiB), 0.05, 1, 7, 0.3), latency_step_options());
    const Hierarchy h = read_hierarchy(steps);
    ASSERT_EQ(h.levels.size(), 2u) << describe(steps);
    expect_near_capacity(h.levels[1].capacity_bytes, 2.0 * MiB, 0.7, 1.6);
    ASSERT_TRUE(h.memory_latency_ns);
    EXPECT_NEAR(*h.memory_latency_ns, 250, 60);
}

TEST(CacheSteps, ARiseInsideALevelIsNotALevel) {
    // TLB misses lift the latency 30 % in the middle of L2: not a step of its own.
    auto c = curve({{32.0 * KiB, 1.0}, {1.0 * MiB, 4.0}}, 100, 16 * MiB);
    for (auto& p : c)
        if (p.size_bytes > 256 * KiB && p.size_bytes <= 1 * MiB) p.value *= 1.3;
    const Hierarchy h = read_hierarchy(find_steps(c, latency_step_options()));
    ASSERT_EQ(h.levels.size(), 2u);
    expect_near_capacity(h.levels[1].capacity_bytes, 1.0 * MiB, 0.7, 1.6);
}

TEST(CacheSteps, ASweepThatEndsBeforeMemoryLeavesTheLastCapacityOpen) {
    const Hierarchy h = read_hierarchy(find_steps(curve(three_levels, 110, 16 * MiB), latency_step_options()));
    ASSERT_EQ(h.levels.size(), 3u);
    expect_near_capacity(h.levels[1].capacity_bytes, 2.0 * MiB);
    EXPECT_FALSE(h.levels[2].capacity_bytes) << "the sweep never left L3, so its end is unknown";
    EXPECT_FALSE(h.memory_latency_ns);
}

TEST(CacheSteps, DegenerateInputs) {
    EXPECT_TRUE(find_steps({}).plateaus.empty());
    EXPECT_TRUE(find_steps({{4096, 1.0}, {8192, 1.0}}).plateaus.empty());
    // Zeros, negatives and NaN are dropped, not divided by.
    const Steps s =
        find_steps({{4096, 0.0}, {8192, -1.0}, {16384, std::nan("")}, {32768, 2.0}, {65536, 2.0}, {131072, 2.0}});
    ASSERT_EQ(s.plateaus.size(), 1u);
    EXPECT_DOUBLE_EQ(s.plateaus[0].value, 2.0);
    EXPECT_TRUE(s.capacities.empty());
    // A flat curve is one level and no memory; unsorted input is sorted first.
    const Hierarchy h =
        read_hierarchy(find_steps({{65536, 1.0}, {4096, 1.0}, {16384, 1.02}, {8192, 0.99}}, latency_step_options()));
    ASSERT_EQ(h.levels.size(), 1u);
    EXPECT_FALSE(h.levels[0].capacity_bytes);
    EXPECT_FALSE(h.memory_latency_ns);
}

TEST(CacheSteps, EverythingAtMemoryLatencyHasNoCacheLevel) {
    const Hierarchy h =
        read_hierarchy(find_steps(noisy(curve({{1.0 * KiB, 200}}, 200, 8 * MiB), 0.1, 0, 3), latency_step_options()));
    EXPECT_TRUE(h.levels.empty());
    ASSERT_TRUE(h.memory_latency_ns);
    EXPECT_EQ(*h.memory_from, 4 * KiB);
}

// Two sweeps recorded on the 2-core KVM development guest (hwloc: 48 KiB L1d and 1 MiB L2 per
// core, 32 MiB L3), ns per load, best of the repetitions, while other jobs ran. The L2 plateau
// ends near 1 MiB (4 KiB pages: TLB misses lift it from 0.4 MiB on), a few points of L3 latency
// follow, and memory (150-430 ns) from 2-3 MB on: the L3 the guest really gets is no plateau,
// a partial level of about 2 MB.
void expect_development_vm(const std::vector<CurvePoint>& c) {
    const Steps steps = find_steps(c, latency_step_options());
    const Hierarchy h = read_hierarchy(steps);
    ASSERT_EQ(h.levels.size(), 3u) << describe(steps);
    expect_near_capacity(h.levels[0].capacity_bytes, 48.0 * KiB, 0.9, 1.3);
    expect_near_capacity(h.levels[1].capacity_bytes, 1.0 * MiB, 0.7, 1.5);
    EXPECT_FALSE(h.levels[1].partial);
    EXPECT_TRUE(h.levels[2].partial);
    expect_near_capacity(h.levels[2].capacity_bytes, 2.0 * MiB, 0.75, 1.5);
    EXPECT_GT(h.levels[2].latency_ns, 5);
    EXPECT_LT(h.levels[2].latency_ns, memory_latency_floor_ns);
    ASSERT_TRUE(h.memory_from);
    EXPECT_LE(*h.memory_from, 3 * MiB);
    ASSERT_TRUE(h.memory_latency_ns);
    EXPECT_GT(*h.memory_latency_ns, 150);
}

TEST(CacheSteps, ASweepRecordedOnTheDevelopmentVmAtHalfOctaves) {
    // ./suite --kernel=latency --sizes=4KiB:256MiB:x1.41 --threads=1
    const std::vector<std::pair<double, double>> kib_ns = {
        {4, 1.07},        {5.64, 1.08},     {7.95, 1.08},    {11.2, 1.07},    {15.8, 1.07},    {22.3, 1.06},
        {31.4, 1.07},     {44.3, 1.07},     {62.5, 3.75},    {88.1, 3.75},    {124, 3.74},     {175, 3.72},
        {247, 3.74},      {348, 3.72},      {491, 4.08},     {692, 4.65},     {976, 6.67},     {1372, 9.32},
        {1946, 11.31},    {2734, 168.55},   {3860, 219.92},  {5437, 289.08},  {7670, 273.42},  {10854, 303.32},
        {15258, 308.49},  {21504, 296.70},  {30310, 306.66}, {42803, 390.61}, {60314, 384.16}, {84992, 365.06},
        {119808, 214.92}, {168960, 184.22}, {238592, 434.86}};
    std::vector<CurvePoint> c;
    for (auto [kib, ns] : kib_ns) c.push_back({static_cast<std::uint64_t>(kib * KiB), ns});
    expect_development_vm(c);
}

TEST(CacheSteps, ASweepRecordedOnTheDevelopmentVmByTheProbe) {
    // ./suite info --probe --json: caches_measured.latency_sweep (with a 113 ns spike at 1.7 MB)
    expect_development_vm(
        {{4096, 1.12},      {4864, 1.11},      {5760, 1.10},      {6848, 1.10},      {8192, 1.10},
         {9728, 1.10},      {11584, 1.11},     {13760, 1.10},     {16384, 1.10},     {19456, 1.10},
         {23168, 1.11},     {27520, 1.10},     {32768, 1.11},     {38912, 1.10},     {46336, 1.11},
         {55104, 3.91},     {65536, 3.87},     {77888, 3.79},     {92672, 3.83},     {110208, 3.95},
         {131072, 3.82},    {155840, 3.81},    {185344, 3.81},    {220416, 3.80},    {262144, 3.84},
         {311680, 3.81},    {370688, 3.84},    {440832, 4.05},    {524288, 4.37},    {623424, 4.71},
         {741440, 5.08},    {881728, 6.57},    {1048576, 9.06},   {1246912, 13.14},  {1482880, 15.57},
         {1763456, 112.74}, {2097152, 15.92},  {2493888, 24.19},  {2965760, 141.18}, {3526912, 288.57},
         {4194304, 271.60}, {4987840, 276.98}, {5931584, 279.72}, {7053888, 295.40}});
}
