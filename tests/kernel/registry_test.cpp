// One parametrised test walks the kernel registry: every kernel, pattern and variant is run
// through the real runner at a tiny size with 1 and 2 threads and must verify.
#include <gtest/gtest.h>

#include <omp.h>

#include "harness/common/units.hpp"
#include "harness/measure/runner.hpp"

using namespace suite;

namespace {

struct Case {
    const KernelEntry* kernel;
    Access access;
    std::string variant;
    std::string label;
};

std::vector<Case> all_cases() {
    std::vector<Case> cases;
    for (const auto& k : kernels())
        for (const auto& a : k.info.accesses)
            for (const auto& v : k.info.variants) {
                if (is_store_variant(v) && a != "sequential") continue;  // nt and rep are sequential stores only
                Access access{a, a == "strided" ? 4u : 0u};
                std::string label = display_name(k.info.name, v) + "_" + (a == "strided" ? "strided4" : a);
                for (auto& c : label)
                    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                cases.push_back({&k, access, v, label});
            }
    return cases;
}

// gtest prints a parameter on failure and in ctest's names; the label says which case it is.
void PrintTo(const Case& c, std::ostream* os) { *os << c.label; }

class Registry : public testing::TestWithParam<Case> {};

RunSettings tiny_settings(const Topology& topo) {
    RunSettings s;
    s.pin = parse_pin("compact", topo);
    s.placement = parse_placement("local", topo);
    s.reps = 2;
    return s;
}

}  // namespace

TEST(RegistryContents, HoldsTheStreamKernels) {
    for (const char* name : {"copy", "scale", "add", "triad", "sin-add", "load", "store", "latency"})
        EXPECT_NE(find_kernel(name), nullptr) << name;
    EXPECT_EQ(find_kernel("nonesuch"), nullptr);
}

TEST_P(Registry, VerifiesAtTinySize) {
    const Case& c = GetParam();
    const Topology topo = Topology::load();
    for (int threads : {1, std::min(2, topo.pu_count())}) {
        if (threads > 1 && single_thread_only(c.kernel->info, c.variant)) continue;
        Point p{c.kernel, c.access, c.variant, c.kernel->test_size, threads};  // the kernel's default parameters
        Record r = run_point(p, tiny_settings(topo), topo);
        EXPECT_TRUE(r.verification.passed) << r.verification.detail;
        EXPECT_EQ(r.repetitions, 2);
        EXPECT_GT(r.work.units, 0);
        EXPECT_GT(r.time.min, 0);
        EXPECT_EQ(r.bindings.size(), static_cast<std::size_t>(threads));
        EXPECT_TRUE(r.binding_held) << "a thread lost its binding during the repetitions";
    }
}

TEST_P(Registry, VerificationFailsWhenTheKernelNeverRan) {
    // The check is real: right after setup, before any run(), the answer must not be there.
    const Case& c = GetParam();
    KernelConfig cfg{c.access, c.variant, c.kernel->test_size, 1, 1, "", default_params(c.kernel->info)};
    omp_set_num_threads(1);
    Arena arena(MemoryPolicy{});
    auto k = c.kernel->make(cfg);
    k->setup(arena);
    EXPECT_FALSE(k->verify().passed);
}

INSTANTIATE_TEST_SUITE_P(AllKernels, Registry, testing::ValuesIn(all_cases()),
                         [](const testing::TestParamInfo<Case>& info) { return info.param.label; });
