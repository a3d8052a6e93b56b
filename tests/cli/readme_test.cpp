// The README's examples work as written: every `./suite ...` line of its "Examples" block is
// checked with --dry-run (the full validation, without the minutes of measuring), and the
// informational commands are run for real.
#include <gtest/gtest.h>

#include <sstream>

#include "harness/machine/topology.hpp"
#include "tests/process.hpp"

using namespace suite::test;

namespace {

// Splits a shell-like line on spaces, stopping at a comment or a redirection.
std::vector<std::string> words(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    std::string w;
    while (in >> w) {
        if (w[0] == '#' || w[0] == '>') break;
        out.push_back(w);
    }
    return out;
}

// The `./suite ...` lines of the code blocks of `file`, in the section `section` ("" for every section).
std::vector<std::string> examples_in(const std::string& file, const std::string& section) {
    std::istringstream in(slurp(std::string(SUITE_SOURCE_DIR) + "/" + file));
    std::string line;
    bool in_section = section.empty(), in_code = false;
    std::vector<std::string> lines;
    while (std::getline(in, line)) {
        if (!section.empty() && line.rfind("## ", 0) == 0) in_section = line == section;
        if (!in_section) continue;
        if (line.rfind("```", 0) == 0) {
            in_code = !in_code;
            continue;
        }
        if (in_code && line.rfind("./suite", 0) == 0) lines.push_back(line);
    }
    return lines;
}

void expect_accepted(const std::vector<std::string>& examples);

}  // namespace

TEST(Readme, ExamplesAreAcceptedAsWritten) {
    const auto examples = examples_in("README.md", "## Examples");
    ASSERT_GE(examples.size(), 10u) << "the README's Examples block was not found";
    expect_accepted(examples);
}

TEST(Readme, TheFullListOfExamplesInDocsIsAcceptedAsWritten) {
    const auto examples = examples_in("docs/examples.md", "");
    ASSERT_GE(examples.size(), 20u) << "docs/examples.md has lost its examples";
    expect_accepted(examples);
}

namespace {

void expect_accepted(const std::vector<std::string>& examples) {
    const bool one_node = suite::Topology::load().nodes.size() < 2;
    for (const auto& line : examples) {
        auto args = words(line);
        args.erase(args.begin());  // ./suite
        const bool info = !args.empty() && (args[0] == "list" || args[0] == "info" || args[0] == "--help");
        // compare and check read committed files and are run for real; check may say "regressed".
        const bool results_tool = !args.empty() && (args[0] == "compare" || args[0] == "check");
        if (!info && !results_tool) args.push_back("--dry-run");
        Outcome r = run_suite(args, 60, SUITE_SOURCE_DIR);  // the README's commands start at the top of the tree
        if (results_tool && args[0] == "check") {
            EXPECT_TRUE(r.status == 0 || r.status == 1) << line << "\n" << r.err;
            EXPECT_NE(r.out.find("point(s) compared"), std::string::npos) << line << "\n" << r.out;
            continue;
        }
        const bool needs_nodes = line.find("node:1") != std::string::npos || line.find("remote") != std::string::npos;
        if (needs_nodes && one_node) {
            // On a one-node machine these are refused, clearly, as usage errors.
            EXPECT_EQ(r.status, 2) << line << "\n" << r.err;
            EXPECT_NE(r.err.find("node"), std::string::npos) << line << "\n" << r.err;
            continue;
        }
        EXPECT_EQ(r.status, 0) << line << "\n" << r.err;
        EXPECT_FALSE(r.out.empty()) << line;
    }
}

}  // namespace
