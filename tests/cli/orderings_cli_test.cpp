// The mesh orderings are one table (kernels/sfc/orderings.hpp) and `suite matrix`'s one table that
// extends it (kernels/fem/ordering_study.hpp): every --help, every kernel's list and every refusal
// shows exactly their names, so a list copied by hand anywhere fails here as soon as it and the
// table differ.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/kernel/kernel.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/ordering_study.hpp"
#include "kernels/sfc/orderings.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;

namespace {

std::string help_of(const std::vector<std::string>& args) {
    const Outcome r = run_suite(args, 60);
    EXPECT_EQ(r.status, 0) << describe(r);
    return r.out;
}

// A refusal is one line on stderr, exit status 2, nothing on stdout.
void expect_refused(const std::vector<std::string>& args, const std::string& line) {
    const Outcome r = run_suite(args, 60);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.err, "suite: error: " + line + "\n") << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
}

std::set<std::string> as_set(const std::vector<std::string>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST(CliOrderings, TheTablesNestAsTheirUsersNeed) {
    const auto all = as_set(sfc::mesh_orderings().names());
    EXPECT_TRUE(all.count(sfc::as_given_name()));
    for (const auto* sub : {&sfc::sorting_orderings(), &sfc::distinct_orderings()})
        for (const auto& name : sub->names()) EXPECT_TRUE(all.count(name)) << name;
    // The matrix's table starts with the finite element kernels' orderings, in their order.
    const std::vector<std::string> fem = fem::fem_orderings().names(), matrix = fem::matrix_orderings().names();
    ASSERT_GT(matrix.size(), fem.size());
    EXPECT_TRUE(std::equal(fem.begin(), fem.end(), matrix.begin()));
    for (std::size_t i = fem.size(); i < matrix.size(); ++i) EXPECT_FALSE(all.count(matrix[i])) << matrix[i];
}

TEST(CliOrderings, KernelsTakeTheTablesNames) {
    const auto all = as_set(sfc::mesh_orderings().names());
    int fem_kernels = 0;
    for (const auto& e : kernels()) {
        if (e.info.axis != AccessAxis::ordering) continue;
        // No kernel takes an ordering the table lacks (the MPM grid's table included).
        for (const auto& a : e.info.accesses) EXPECT_TRUE(all.count(a)) << e.info.name << ": " << a;
        if (e.info.group == "fem") {
            ++fem_kernels;
            EXPECT_EQ(e.info.accesses, fem::fem_orderings().names()) << e.info.name;
        }
    }
    EXPECT_GT(fem_kernels, 0);
    ASSERT_NE(find_kernel("sfc-build"), nullptr);
    EXPECT_EQ(find_kernel("sfc-build")->info.accesses, sfc::sorting_orderings().names());
}

TEST(CliOrderings, HelpListsExactlyTheTablesNames) {
    const std::string traverse = help_of({"traverse", "--help"});
    EXPECT_NE(traverse.find("one or more of " + sfc::mesh_orderings().accepted() + " (default"), std::string::npos)
        << traverse;
    EXPECT_NE(traverse.find("Orderings:\n" + sfc::mesh_orderings().listed()), std::string::npos) << traverse;

    const std::string matrix = help_of({"matrix", "--help"});
    EXPECT_NE(matrix.find("one or more of " + fem::matrix_orderings().accepted() + " (default"), std::string::npos)
        << matrix;
    EXPECT_NE(matrix.find("Orderings:\n" + fem::matrix_orderings().listed()), std::string::npos) << matrix;

    const std::string run = help_of({"run", "--help"});
    EXPECT_NE(run.find("data orderings of application kernels: " + sfc::mesh_orderings().accepted() + " ("),
              std::string::npos)
        << run;

    // `suite list` shows each kernel's orderings: the fem kernels' are the table's.
    const std::string list = help_of({"list"});
    std::string fem_list;
    for (const auto& name : fem::fem_orderings().names()) fem_list += (fem_list.empty() ? "" : ",") + name;
    EXPECT_NE(list.find(fem_list), std::string::npos) << list;
}

TEST(CliOrderings, AnUnknownOrderingIsRefusedWithTheTablesNames) {
    TempDir dir;
    expect_refused(
        {"traverse", "--ordering=natural,hilbrt", "--no-png", "--out=" + dir.file("t")},
        "unknown ordering 'hilbrt' (did you mean 'hilbert'?); accepted: " + sfc::mesh_orderings().accepted());
    expect_refused({"matrix", "--mesh=disk:refine=2", "--ordering=amdd", "--no-png", "--out=" + dir.file("m")},
                   "unknown ordering 'amdd' (did you mean 'amd'?); accepted: " + fem::matrix_orderings().accepted());
    expect_refused({"run", "--kernel=fem-spmv", "--ordering=mortn", "--dry-run"},
                   "kernel 'fem-spmv' has no ordering 'mortn' (did you mean 'morton'?); it accepts: " +
                       fem::fem_orderings().accepted());
    // morton-recursive orders as morton does: the kernels that walk ordered data leave it to sfc-build.
    expect_refused(
        {"run", "--kernel=fem-spmv", "--ordering=morton-recursive", "--dry-run"},
        "kernel 'fem-spmv' has no ordering 'morton-recursive'; it accepts: " + fem::fem_orderings().accepted());
    expect_refused({"run", "--kernel=sfc-build", "--ordering=natural", "--dry-run"},
                   "kernel 'sfc-build' has no ordering 'natural'; it accepts: " + sfc::sorting_orderings().accepted());
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliOrderings, ParsingReadsTheTable) {
    EXPECT_EQ(sfc::parse_method("hilbert"), sfc::Method::hilbert);
    EXPECT_EQ(sfc::method_name(sfc::Method::rcm), "rcm");
    EXPECT_THROW(sfc::parse_method(sfc::as_given_name()), UsageError);
    for (const auto& c : sfc::sorting_orderings().all()) EXPECT_EQ(sfc::method_name(c.what.method), c.name);
}
