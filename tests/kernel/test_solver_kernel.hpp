#pragma once
// "test-solve", a kernel registered in the test binary only (tests/kernel/test_solver_kernel.cpp)
// for the tests of what application kernels declare beyond the streaming ones: variants picked
// by --strategy, default and single-thread variants, parameters (--delta, --tol, --wrong), facts,
// and a solver that can fail to converge.
//
//   for each row i:  x = 0; repeat x = b[i] - delta * x  until |change| <= tol * |b[i]|
//
// converges to b[i] / (1 + delta) when |delta| < 1, and never when |delta| >= 1 (the solver then
// fails after max_iterations). --wrong=1 corrupts the answer, so that verification fails.
namespace suite::test {

inline constexpr const char* solver_kernel = "test-solve";
inline constexpr int solver_max_iterations = 200;

}  // namespace suite::test
