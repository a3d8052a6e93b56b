// The frame every long command runs in (app/suite/frame): the output claimed and its lock gone
// when the frame ends; SIGINT and SIGTERM turned into a stop asked for, not a death; 128+N and
// one line from finish(); the handlers the frame found put back; one frame at a time.
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "app/suite/frame.hpp"
#include "harness/common/units.hpp"
#include "tests/process.hpp"

using namespace suite;
namespace fs = std::filesystem;

namespace {

std::atomic<int> custom_seen{0};
extern "C" void custom_handler(int sig) { custom_seen.store(sig); }

void (*handler_of(int sig))(int) {
    struct sigaction now {};
    sigaction(sig, nullptr, &now);
    return now.sa_handler;
}

}  // namespace

TEST(CommandFrame, ASignalAsksForAStopAndFinishSaysSo) {
    for (const int sig : {SIGINT, SIGTERM}) {
        CommandFrame frame("suite");
        EXPECT_FALSE(frame.stop_requested());
        ::testing::internal::CaptureStderr();
        EXPECT_EQ(frame.finish(3, "nothing", false), 3) << "no signal: the command's own status";
        raise(sig);  // the process survives it
        EXPECT_TRUE(frame.stop_requested());
        EXPECT_EQ(frame.stop_signal(), sig);
        EXPECT_EQ(frame.stop_flag()->load(), sig);
        EXPECT_EQ(frame.finish(1, "2 of 5 point(s)", false), 128 + sig);
        const std::string err = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(err, "suite: interrupted by signal " + std::to_string(sig) + " after 2 of 5 point(s)\n");
    }
}

TEST(CommandFrame, ASecondSignalEndsTheProcessUnlessTheFrameWaits) {
    {
        CommandFrame frame("suite");
        raise(SIGINT);
        EXPECT_EQ(handler_of(SIGINT), SIG_DFL) << "the next Ctrl-C ends the program at once";
        EXPECT_EQ(handler_of(SIGTERM), SIG_DFL) << "and so does a SIGTERM after a Ctrl-C";
        EXPECT_EQ(frame.stop_signal(), SIGINT) << "the first signal is the one reported";
    }
    {
        CommandFrame frame("suite-mpi", CommandFrame::SecondSignal::waits_for_ranks);
        raise(SIGINT);
        EXPECT_NE(handler_of(SIGINT), SIG_DFL) << "a rank keeps waiting for the others";
        raise(SIGINT);
        EXPECT_EQ(frame.stop_signal(), SIGINT);
    }
}

TEST(CommandFrame, TheHandlersItFoundArePutBackAndANewFrameStartsClear) {
    struct sigaction sa {};
    sa.sa_handler = custom_handler;
    sigemptyset(&sa.sa_mask);
    struct sigaction old_int {
    }, old_term{};
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    {
        CommandFrame frame("suite");
        EXPECT_NE(handler_of(SIGINT), custom_handler);
        raise(SIGTERM);
        EXPECT_EQ(custom_seen.load(), 0);
    }
    EXPECT_EQ(handler_of(SIGINT), custom_handler);
    EXPECT_EQ(handler_of(SIGTERM), custom_handler);
    {
        CommandFrame next("suite");
        EXPECT_FALSE(next.stop_requested()) << "a stop asked of the last command is not this one's";
    }
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
}

TEST(CommandFrame, ASignalStartedIgnoredStaysIgnored) {
    struct sigaction ignore {
    }, old{};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGINT, &ignore, &old);
    {
        CommandFrame frame("suite");
        EXPECT_EQ(handler_of(SIGINT), SIG_IGN) << "a background job's Ctrl-C is the foreground's";
        EXPECT_NE(handler_of(SIGTERM), SIG_DFL);
        raise(SIGINT);
        EXPECT_FALSE(frame.stop_requested());
    }
    sigaction(SIGINT, &old, nullptr);
}

TEST(CommandFrame, ARankRemovesItsLockFileAtTheFirstSignalOnlyWhileItIsItsOwn) {
    suite::test::TempDir tmp;
    const std::string file = tmp.file("r.json");
    CommandFrame frame("suite-mpi", CommandFrame::SecondSignal::waits_for_ranks);
    frame.claim_file(file, "--out");
    ASSERT_TRUE(fs::exists(file + ".lock"));
    raise(SIGTERM);
    EXPECT_FALSE(fs::exists(file + ".lock")) << "mpirun's SIGKILL may follow: no lock file outlives the rank";
    // Another run takes the name meanwhile: a second signal does not remove its lock file.
    { std::ofstream(file + ".lock") << "12345\n"; }
    raise(SIGTERM);
    EXPECT_TRUE(fs::exists(file + ".lock"));
    fs::remove(file + ".lock");
}

TEST(CommandFrame, OneFrameAtATime) {
    CommandFrame frame("suite");
    EXPECT_THROW(CommandFrame("suite"), std::logic_error);
}

TEST(CommandFrame, TheOutputIsLockedWhileItLivesAndTheLockGoesWithIt) {
    suite::test::TempDir tmp;
    const std::string dir = tmp.file("out"), file = tmp.file("r.json");
    {
        CommandFrame frame("suite");
        OutputDir& out = frame.claim_dir(dir, DirPolicy{.option = "--out", .command = "suite test"});
        EXPECT_TRUE(fs::exists(dir + "/.suite.lock"));
        EXPECT_THROW(OutputDir::claim(dir, "--out"), UsageError) << "a second run on the same directory refuses";
        EXPECT_THROW(frame.claim_file(file, "--out"), std::logic_error) << "a frame holds one output";
        out.write("a.txt", "a\n");
        EXPECT_EQ(frame.file(), nullptr);
    }
    EXPECT_FALSE(fs::exists(dir + "/.suite.lock"));
    EXPECT_TRUE(fs::exists(dir + "/a.txt"));
    {
        CommandFrame frame("suite");
        frame.claim_file(file, "--out");
        ASSERT_NE(frame.file(), nullptr);
        EXPECT_EQ(frame.file()->path(), file);
        EXPECT_TRUE(fs::exists(file + ".lock"));
        raise(SIGTERM);  // interrupted: the lock still goes
    }
    EXPECT_FALSE(fs::exists(file + ".lock"));
}
