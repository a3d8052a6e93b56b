// The test-only kernel "test-solve" (see test_solver_kernel.hpp): registered here, used by the
// plan, runner, output and exit-status tests, and walked by the registry test like any kernel.
#include "tests/kernel/test_solver_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"

namespace suite::test {

namespace {

class TestSolve final : public Kernel {
public:
    explicit TestSolve(const KernelConfig& cfg)
        : cfg_(cfg), delta_(cfg.param("delta")), tol_(cfg.param("tol")), wrong_(cfg.param("wrong") != 0) {}

    void setup(Arena& arena) override {
        n_ = cfg_.size;
        b_ = arena.allocate<double>("b", n_);
        x_ = arena.allocate<double>("x", n_);
        for (std::uint64_t i = 0; i < n_; ++i) {
            b_[i] = static_cast<double>(i + 1);
            x_[i] = 0;
        }
    }

    void run(int calls) override {
        for (int c = 0; c < calls; ++c) {
            int most = 0;
            const auto n = static_cast<std::int64_t>(n_);
            if (cfg_.variant == "serial") {
                for (std::int64_t i = 0; i < n; ++i) most = std::max(most, solve_row(i));
            } else {
#pragma omp parallel for schedule(static) reduction(max : most)
                for (std::int64_t i = 0; i < n; ++i) most = std::max(most, solve_row(i));
            }
            iterations_ = most;
            ran_ = true;
        }
        if (wrong_ && n_ > 0) x_[0] += 1;
    }

    Verification verify() override {
        Verification v{false, "x[i] == b[i] / (1 + delta)", 0};
        if (!ran_) {
            v.detail = "the solver never ran";
            return v;
        }
        if (iterations_ >= solver_max_iterations) {
            v.solver_failed = true;
            v.detail = "no convergence after " + std::to_string(solver_max_iterations) +
                       " iterations (delta=" + format_number(delta_) + ", which must be between -1 and 1)";
            return v;
        }
        v.passed = true;
        for (std::uint64_t i = 0; i < n_; ++i) {
            const double expected = b_[i] / (1 + delta_);
            const double err = std::fabs(x_[i] - expected);
            v.max_error = std::max(v.max_error, err);
            if (err > 10 * tol_ * std::fabs(b_[i]) && v.passed) {
                v.passed = false;
                v.detail += "; x[" + std::to_string(i) + "] = " + std::to_string(x_[i]) + ", expected " +
                            std::to_string(expected);
            }
        }
        return v;
    }

    Work work() const override { return {static_cast<double>(n_), 16.0 * n_, 16.0 * n_, 2.0 * n_, n_ * 16}; }

    std::vector<Fact> facts() const override {
        return {{"x0", n_ ? x_[0] : 0.0, ""},
                {"iterations", static_cast<double>(iterations_), ""},
                {"rows", static_cast<double>(n_), "rows"}};
    }

private:
    int solve_row(std::int64_t i) {
        double x = 0;
        const double b = b_[i];
        int k = 0;
        while (k < solver_max_iterations) {
            ++k;
            const double next = b - delta_ * x;
            const double change = std::fabs(next - x);
            x = next;
            if (!std::isfinite(x) || change <= tol_ * std::fabs(b)) break;
        }
        x_[i] = x;
        return std::isfinite(x) && k < solver_max_iterations ? k : solver_max_iterations;
    }

    KernelConfig cfg_;
    double delta_, tol_;
    bool wrong_;
    std::uint64_t n_ = 0;
    double *b_ = nullptr, *x_ = nullptr;
    int iterations_ = 0;
    bool ran_ = false;
};

void validate(const KernelConfig& cfg) {
    const double delta = cfg.param("delta"), tol = cfg.param("tol");
    if (!(delta > -1)) throw UsageError("--delta=" + format_number(delta) + ": test-solve needs delta above -1");
    if (!(tol > 0 && tol < 1))
        throw UsageError("--tol=" + format_number(tol) + ": test-solve needs a tolerance between 0 and 1");
}

const bool registered = [] {
    KernelEntry e;
    e.info.name = solver_kernel;
    e.info.group = "test";
    e.info.formula = "x = b - delta * x until converged";
    e.info.unit = "row";
    e.info.axis = AccessAxis::ordering;
    e.info.accesses = {"natural"};
    e.info.variants = {"jacobi", "serial", "atomic"};
    e.info.variant_option = "strategy";
    e.info.default_variants = {"jacobi", "serial"};
    e.info.single_thread_variants = {"serial"};
    e.info.params = {{"delta", 0.5, "test-solve: the fixed-point factor; |delta| >= 1 does not converge"},
                     {"tol", 1e-8, "test-solve: relative tolerance of the fixed-point iteration"},
                     {"wrong", 0, "test-solve: 1 corrupts the answer, so that verification fails"}};
    e.info.size_kind = SizeKind::count;
    e.make = [](const KernelConfig& c) { return std::make_unique<TestSolve>(c); };
    e.validate = validate;
    e.test_size = 1024;
    return register_kernel(std::move(e));
}();

}  // namespace

}  // namespace suite::test
