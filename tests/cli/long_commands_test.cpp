// Every long command that writes a directory keeps the promise `suite run` keeps (app/suite/frame):
// interrupted by SIGINT or SIGTERM between two orderings, `suite matrix` and `suite traverse`
// write what they finished, marked "complete": false, say what was done, exit 128+N and leave
// no lock or temporary file behind. (`suite run` and `suite mpm` have their own tests of this:
// e2e_test.cpp, mpm_cli_test.cpp.)
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;

namespace {

// Starts `args`, waits until `first` exists in `dir` (the first ordering is done), sends `sig`.
Outcome interrupt_after(const std::vector<std::string>& args, const std::string& dir, const std::string& first,
                        int sig) {
    int out_fd = -1, err_fd = -1;
    std::vector<std::string> argv = {SUITE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    const pid_t pid = spawn(argv, out_fd, err_fd);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(dir + "/" + first) && std::chrono::steady_clock::now() < deadline) usleep(10000);
    kill(pid, sig);
    return finish(pid, out_fd, err_fd, 120);
}

// Nothing but the command's own files and their manifest: no lock, no temporary file, no
// staging directory, no plot script's stderr.
void expect_no_leftovers(const std::string& dir) {
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        EXPECT_TRUE(name[0] != '.' || name == ".suite-files") << name << " left in " << dir;
    }
}

// "after K of N ordering(s)": K.
int finished_orderings(const std::string& err, int of) {
    std::smatch m;
    const std::regex re("interrupted by signal [0-9]+ after ([0-9]+) of " + std::to_string(of) + " ordering\\(s\\)");
    return std::regex_search(err, m, re) ? std::stoi(m[1]) : -1;
}

class LongCommand : public ::testing::TestWithParam<int> {};

}  // namespace

TEST_P(LongCommand, AnInterruptedMatrixKeepsTheOrderingsItFinished) {
    const int sig = GetParam();
    TempDir tmp;
    const std::string dir = tmp.file("m");
    // About 1 s an ordering on the development VM (1000 SpMVs of 197 k rows; no factor computed).
    const Outcome r = interrupt_after({"matrix", "--mesh=disk:refine=8", "--reps=1000", "--max-factor=1KiB", "--no-png",
                                       "--ordering=natural,random,morton,hilbert", "--out=" + dir},
                                      dir, "matrix.json", sig);
    ASSERT_EQ(r.status, 128 + sig) << describe(r);
    const int done = finished_orderings(r.err, 4);
    ASSERT_GE(done, 1) << r.err;
    ASSERT_LT(done, 4) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir + "/matrix.json"));
    EXPECT_EQ(doc["complete"], false);
    ASSERT_EQ(doc["orderings"].size(), static_cast<std::size_t>(done));
    EXPECT_EQ(doc["orderings"][0]["ordering"], "natural");
    const std::string md = slurp(dir + "/matrix.md");
    EXPECT_NE(md.find("| natural |"), std::string::npos) << md;
    EXPECT_EQ(md.find("| hilbert |"), std::string::npos) << "an ordering not finished is not in the table";
    EXPECT_NE(r.out.find("incomplete: interrupted"), std::string::npos) << r.out;
    expect_no_leftovers(dir);
}

TEST_P(LongCommand, AnInterruptedTraverseKeepsTheOrderingsItFinished) {
    const int sig = GetParam();
    TempDir tmp;
    const std::string dir = tmp.file("t");
    // About 3 s an ordering on the development VM: eight .vtu files of 384 k tetrahedra each.
    const Outcome r = interrupt_after({"traverse", "--mesh=box:40,40,40", "--ordering=natural,random,morton",
                                       "--threads=1-8", "--no-png", "--out=" + dir},
                                      dir, "summary.json", sig);
    ASSERT_EQ(r.status, 128 + sig) << describe(r);
    const int done = finished_orderings(r.err, 3);
    ASSERT_GE(done, 1) << r.err;
    ASSERT_LT(done, 3) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir + "/summary.json"));
    EXPECT_EQ(doc["complete"], false);
    ASSERT_EQ(doc["orderings"].size(), static_cast<std::size_t>(done));
    for (const auto& o : doc["orderings"])
        for (const auto& t : o["threads"])
            EXPECT_TRUE(fs::is_regular_file(dir + "/" + t["vtu"].get<std::string>())) << t.dump();
    expect_no_leftovers(dir);
}

INSTANTIATE_TEST_SUITE_P(Signals, LongCommand, ::testing::Values(SIGINT, SIGTERM),
                         [](const ::testing::TestParamInfo<int>& i) {
                             return i.param == SIGINT ? std::string("SIGINT") : std::string("SIGTERM");
                         });
