// The one writer (harness/common/output_file.hpp) in-process: what it refuses, what it keeps,
// and that it leaves nothing behind. The end-to-end cases are in tests/cli/output_test.cpp.
#include "harness/common/output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>

#include "harness/common/units.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite;
using suite::test::slurp;
using suite::test::TempDir;

namespace {

std::vector<std::string> names(const TempDir& d) { return suite::test::names_in(d.path()); }

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(OutputFile, WritesReplaceAtomicallyAndKeepTheFileMode) {
    TempDir d;
    const std::string p = d.file("r.json");
    {
        OutputFile f = OutputFile::claim(p, "--out");
        EXPECT_EQ(names(d), (std::vector<std::string>{"r.json.lock"}));
        f.write("one\n");
        ASSERT_EQ(chmod(p.c_str(), 0600), 0);
        f.write("two\n");
    }
    EXPECT_EQ(slurp(p), "two\n");
    struct stat st {};
    ASSERT_EQ(stat(p.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u) << "a replaced file keeps its permissions";
    EXPECT_EQ(names(d), (std::vector<std::string>{"r.json"})) << "the lock file goes with the claim";
}

TEST(OutputFile, TheSameFileClaimedTwiceInOneRunIsRefused) {
    TempDir d;
    const OutputFile first = OutputFile::claim(d.file("r.json"), "--out");
    fs::create_directory(d.file("sub"));
    const std::string msg = message_of([&] { OutputFile::claim(d.file("sub/../r.json"), "--markdown"); });
    EXPECT_NE(msg.find("named twice"), std::string::npos) << msg;
    // The refused claim did not drop the first one's lock.
    EXPECT_TRUE(fs::exists(d.file("r.json.lock")));
    first.write("still mine\n");
    EXPECT_EQ(slurp(d.file("r.json")), "still mine\n");
}

TEST(OutputFile, ATargetThatTurnsIntoAFifoAfterTheClaimIsNotWritten) {
    TempDir d;
    const std::string p = d.file("r.json");
    const OutputFile f = OutputFile::claim(p, "--out");
    ASSERT_EQ(mkfifo(p.c_str(), 0644), 0);
    const std::string msg = message_of([&] { f.write("x"); });
    EXPECT_NE(msg.find("a named pipe (FIFO)"), std::string::npos) << msg;
    struct stat st {};
    EXPECT_TRUE(lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode));
    EXPECT_EQ(names(d), (std::vector<std::string>{"r.json", "r.json.lock"})) << "no temporary file";
}

TEST(OutputFile, InputsAreRecognisedByInodeNotBySpelling) {
    TempDir d;
    const std::string in = d.file("mesh.txt");
    { std::ofstream(in) << "data\n"; }
    ASSERT_EQ(symlink(in.c_str(), d.file("via-link").c_str()), 0);
    const auto inputs = identify_inputs({d.file("via-link"), d.file("missing.json")});
    ASSERT_EQ(inputs.size(), 1u) << "a missing input is its reader's error";
    fs::create_directory(d.file("sub"));
    EXPECT_THROW(OutputFile::claim(d.file("sub/../mesh.txt"), "--out", inputs), UsageError);
    EXPECT_EQ(slurp(in), "data\n");
    EXPECT_EQ(names(d), (std::vector<std::string>{"mesh.txt", "sub", "via-link"}));
}

TEST(OutputDir, CreatesLocksAndWritesPlainNamesOnly) {
    TempDir d;
    const std::string dir = d.file("out");
    {
        OutputDir o = OutputDir::claim(dir, "--out");
        EXPECT_TRUE(fs::is_directory(dir));
        EXPECT_TRUE(fs::exists(dir + "/.suite.lock"));
        o.write("summary.json", "{}\n");
        EXPECT_THROW(o.write("../escape.json", "x"), std::logic_error);
        EXPECT_THROW(OutputDir::claim(dir, "--out"), UsageError) << "one claim of a directory at a time";
        ASSERT_EQ(mkfifo((dir + "/a.vtu").c_str(), 0644), 0);
        EXPECT_THROW(o.write("a.vtu", "x"), std::runtime_error);
    }
    EXPECT_EQ(slurp(dir + "/summary.json"), "{}\n");
    EXPECT_FALSE(fs::exists(dir + "/.suite.lock"));
    EXPECT_FALSE(fs::exists(d.file("escape.json")));
    // A regular file where the directory should be, and a missing parent, are usage errors.
    { std::ofstream(d.file("file")) << "x"; }
    EXPECT_THROW(OutputDir::claim(d.file("file"), "--out"), UsageError);
    EXPECT_THROW(OutputDir::claim(d.file("no/such/dir"), "--out"), UsageError);
    EXPECT_FALSE(fs::exists(d.file("no")));
}

TEST(OutputDir, AReplacementIsAllOrNothing) {
    TempDir d;
    const std::string dir = d.file("out");
    const DirPolicy first{.option = "--out", .command = "suite test"};
    {
        OutputDir o = OutputDir::claim(dir, first);
        o.write("a.txt", "a\n");
        o.write("b.txt", "b\n");
        o.commit();
    }
    EXPECT_EQ(suite::test::names_in(dir), (std::vector<std::string>{".suite-files", "a.txt", "b.txt"}));
    EXPECT_THROW(OutputDir::claim(dir, first), UsageError) << "an earlier run's files, without replace";
    const DirPolicy replace{.option = "--out", .command = "suite test", .replace_earlier = true};
    {
        // Abandoned (an exception, no commit): the earlier set stays, the staging goes.
        OutputDir o = OutputDir::claim(dir, replace);
        EXPECT_NE(o.writing_path(), dir);
        o.write("c.txt", "c\n");
        EXPECT_FALSE(fs::exists(dir + "/c.txt"));
    }
    EXPECT_EQ(suite::test::names_in(dir), (std::vector<std::string>{".suite-files", "a.txt", "b.txt"}));
    {
        OutputDir o = OutputDir::claim(dir, replace);
        o.write("c.txt", "c\n");
        o.commit();
    }
    EXPECT_EQ(suite::test::names_in(dir), (std::vector<std::string>{".suite-files", "c.txt"}));
    EXPECT_EQ(slurp(dir + "/.suite-files"), "suite test\nc.txt\n");
    // A run killed while it wrote straight into a new directory leaves its files listed, so
    // that a later --replace may take them: the manifest grows with every new file.
    const std::string fresh = d.file("fresh");
    {
        OutputDir o = OutputDir::claim(fresh, first);
        o.write("x.vtu", "x\n");
        EXPECT_EQ(slurp(fresh + "/.suite-files"), "suite test\nx.vtu\n");
    }
}
