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
    // A variant this CPU cannot run (peak-flops sve without SVE) is refused as the program
    // refuses it, naming the variant; running it would be an illegal instruction.
    try {
        c.kernel->validate({c.access, c.variant, c.kernel->test_size, 1, 1, "", default_params(c.kernel->info)});
    } catch (const UsageError& e) {
        ASSERT_NE(std::string(e.what()).find(c.variant), std::string::npos)
            << "a refusal names the variant: " << e.what();
        GTEST_SKIP() << e.what();
    }
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

namespace {

// Every name of every named parameter (ParamInfo::choices) but the default, which the walk above
// runs: at the kernel's first access and variant, it must verify, or be refused by the kernel's
// validate as a usage error (the implicit MPM kernels take the elastic cases only).
struct ChoiceCase {
    const KernelEntry* kernel;
    std::string param, choice, label;
};

std::vector<ChoiceCase> all_choices() {
    std::vector<ChoiceCase> out;
    for (const auto& k : kernels())
        for (const auto& p : k.info.params)
            for (std::size_t i = 1; i < p.choices.size(); ++i) {
                std::string label = k.info.name + "_" + p.name + "_" + p.choices[i];
                for (auto& c : label)
                    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                out.push_back({&k, p.name, p.choices[i], label});
            }
    return out;
}

void PrintTo(const ChoiceCase& c, std::ostream* os) { *os << c.label; }

class RegistryChoice : public testing::TestWithParam<ChoiceCase> {};

}  // namespace

TEST_P(RegistryChoice, VerifiesAtTinySizeOrIsRefused) {
    const ChoiceCase& c = GetParam();
    const Topology topo = Topology::load();
    const std::string& a = c.kernel->info.accesses.front();
    Point p{c.kernel, {a, a == "strided" ? 4u : 0u}, c.kernel->info.variants.front(), c.kernel->test_size, 1};
    p.params[c.param] = c.choice;
    KernelConfig cfg{p.access, p.variant, p.size, 1, 1, "", default_params(c.kernel->info)};
    cfg.params[c.param] = c.choice;
    try {
        c.kernel->validate(cfg);
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find(c.choice), std::string::npos)
            << "a refusal names the choice: " << e.what();
        return;
    }
    Record r = run_point(p, tiny_settings(topo), topo);
    EXPECT_TRUE(r.verification.passed) << r.verification.detail;
    EXPECT_EQ(r.params.at(c.param), ParamValue(c.choice));
    EXPECT_NE(r.verification.detail.find(c.choice), std::string::npos) << "the detail names the choice";
}

INSTANTIATE_TEST_SUITE_P(AllChoices, RegistryChoice, testing::ValuesIn(all_choices()),
                         [](const testing::TestParamInfo<ChoiceCase>& info) { return info.param.label; });
