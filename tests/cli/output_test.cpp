// Every file the suite writes goes through one writer with one policy (harness/common/
// output_file.hpp): a regular file this user may write or a new name; never a device, FIFO,
// socket or symlink, never one of the run's inputs; one run at a time per output; nothing left
// behind. Each case runs the binary as a user would and checks the exit status, the one line,
// and what is on disk afterwards.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;
using nlohmann::json;

namespace {

const std::vector<std::string> kQuick = {"--kernel=copy",   "--size=64KiB",  "--threads=1", "--reps=1",
                                         "--counters=none", "--energy=none", "--quiet"};

std::vector<std::string> quick(const std::vector<std::string>& more) {
    std::vector<std::string> a = kQuick;
    a.insert(a.end(), more.begin(), more.end());
    return a;
}

// Exit status 2, nothing on stdout, exactly one line on stderr holding every piece of `expected`.
void expect_refused(const Outcome& r, const std::vector<std::string>& expected) {
    ASSERT_FALSE(r.timed_out) << describe(r);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "stderr must be one line\n" << describe(r);
    for (const auto& s : expected)
        EXPECT_NE(r.err.find(s), std::string::npos) << "stderr lacks \"" << s << "\"\n" << describe(r);
}

// Names in `dir` that a write leaves behind when it should not: temporary, probe and lock files.
std::vector<std::string> leftovers(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.find(".tmp.") != std::string::npos || n.find(".probe.") != std::string::npos ||
            n.find(".lock") != std::string::npos)
            out.push_back(n);
    }
    return out;
}

// A small valid result file at `path`, made by the suite itself.
std::string make_result(const std::string& path) {
    const Outcome r = run_suite(quick({"--out=" + path}));
    EXPECT_EQ(r.status, 0) << describe(r);
    return slurp(path);
}

bool is_char_device(const std::string& p) {
    struct stat st {};
    return lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

// The reported case: `check --markdown=/dev/full` exited 0 and, as root, replaced the device.
// As root the test makes its own node of /dev/full's kind (so a failure cannot damage the
// machine's); unprivileged, /dev/full itself, which the user could not replace anyway.
TEST(Output, CheckMarkdownToADeviceIsRefusedAndTheDeviceStays) {
    TempDir d;
    const std::string base = d.file("base.json"), run = d.file("run.json");
    make_result(base);
    make_result(run);
    std::string device = "/dev/full";
    if (geteuid() == 0) {
        device = d.file("full");
        ASSERT_EQ(mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)), 0) << std::strerror(errno);
    }
    ASSERT_TRUE(is_char_device(device));
    const Outcome r = run_suite({"check", "--baseline", base, run, "--markdown=" + device});
    expect_refused(r, {"--markdown=" + device, "character device", "regular file"});
    EXPECT_TRUE(is_char_device(device)) << device << " is no longer a device";
    EXPECT_TRUE(leftovers(d.path()).empty()) << join(leftovers(d.path()));
}

// `--markdown=BASELINE` overwrote the baseline with the report. Inputs are recognised by
// device and inode: the same path, another spelling, and a hard link are all refused.
TEST(Output, CheckMarkdownOverAnInputIsRefusedByInodeAndTheInputStays) {
    TempDir d;
    const std::string base = d.file("base.json"), run = d.file("run.json");
    const std::string base_text = make_result(base), run_text = make_result(run);
    fs::create_directory(d.file("sub"));
    ASSERT_EQ(link(base.c_str(), d.file("hard.json").c_str()), 0);
    const std::vector<std::pair<std::string, std::string>> spellings = {{base, "base.json"},
                                                                        {d.file("sub/../base.json"), "base.json"},
                                                                        {d.file("hard.json"), "base.json"},
                                                                        {run, "run.json"}};
    for (const auto& [target, input] : spellings) {
        SCOPED_TRACE(target);
        const Outcome r = run_suite({"check", "--baseline", base, run, "--markdown=" + target});
        expect_refused(r, {"--markdown=" + target, "is the same file as the input", input});
    }
    EXPECT_EQ(slurp(base), base_text);
    EXPECT_EQ(slurp(run), run_text);
    EXPECT_TRUE(leftovers(d.path()).empty()) << join(leftovers(d.path()));
}

// A run's --out over its own mesh file (here a hard link to it) is refused before anything runs.
TEST(Output, RunOutOverItsMeshFileIsRefused) {
    TempDir d;
    const std::string mesh = d.file("square.txt");
    {
        std::ofstream f(mesh);
        f << " 4 vertices in the domain\n Index of vertex | x coordinate | y coordinate\n 0 0 0\n 1 1 0\n 2 1 1\n 3 0 "
             "1\n"
             " 2 faces in the domain\n index of vertex 0 | index of vertex 1 | index of vertex 2\n 0 1 2\n 0 2 3\n";
    }
    const std::string text = slurp(mesh);
    ASSERT_EQ(link(mesh.c_str(), d.file("alias.json").c_str()), 0);
    const Outcome r = run_suite({"--kernel=sfc-build", "--mesh=file:" + mesh, "--threads=1", "--reps=1",
                                 "--counters=none", "--energy=none", "--quiet", "--out=" + d.file("alias.json")});
    expect_refused(r, {"--out=" + d.file("alias.json"), "is the same file as the input", mesh});
    EXPECT_EQ(slurp(mesh), text);
    // traverse reads the same mesh: its directory's files are checked against it too, and a
    // directory that is a regular file is refused.
    const Outcome t = run_suite({"traverse", "--mesh=file:" + mesh, "--threads=1", "--no-png", "--out=" + mesh});
    expect_refused(t, {"--out=" + mesh, "not a directory"});
    EXPECT_EQ(slurp(mesh), text);
}

// A FIFO, a socket and a symlink are refused, and are still what they were afterwards.
TEST(Output, SpecialFilesAreRefusedAndLeftAsTheyWere) {
    TempDir d;
    const std::string fifo = d.file("fifo.json"), sock = d.file("sock.json"), link_path = d.file("link.json");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
    const int s = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    ASSERT_LT(sock.size(), sizeof addr.sun_path);
    std::strcpy(addr.sun_path, sock.c_str());
    ASSERT_EQ(bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0) << std::strerror(errno);
    const std::string target = d.file("target.json");
    const std::string target_text = make_result(target);
    ASSERT_EQ(symlink(target.c_str(), link_path.c_str()), 0);
    for (const auto& [path, kind] : std::vector<std::pair<std::string, std::string>>{
             {fifo, "a named pipe (FIFO)"}, {sock, "a socket"}, {link_path, "a symlink"}}) {
        SCOPED_TRACE(path);
        expect_refused(run_suite(quick({"--out=" + path})), {"--out=" + path, kind, "regular file"});
    }
    struct stat st {};
    EXPECT_TRUE(lstat(fifo.c_str(), &st) == 0 && S_ISFIFO(st.st_mode));
    EXPECT_TRUE(lstat(sock.c_str(), &st) == 0 && S_ISSOCK(st.st_mode));
    EXPECT_TRUE(lstat(link_path.c_str(), &st) == 0 && S_ISLNK(st.st_mode));
    EXPECT_EQ(slurp(target), target_text);
    close(s);
    EXPECT_TRUE(leftovers(d.path()).empty()) << join(leftovers(d.path()));
}

// As an unprivileged user, --out=FILE where FILE is read-only and another user's, in a
// directory the user may write: the rename would succeed, and must not be tried. As root the
// test runs the suite as uid 65534 (setpriv); unprivileged, the file is its own but mode 0444.
TEST(Output, AFileThisUserMayNotWriteIsNotReplaced) {
    TempDir d;
    fs::permissions(d.path(), fs::perms::all, fs::perm_options::add);  // a writable directory for anyone
    const std::string out = d.file("theirs.json");
    const std::string text = make_result(out);
    fs::permissions(out, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read,
                    fs::perm_options::replace);
    std::vector<std::string> argv;
    if (geteuid() == 0) argv = {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"};
    argv.push_back(SUITE_BINARY);
    for (const auto& a : quick({"--out=" + out})) argv.push_back(a);
    const Outcome r = run_program(argv, 120);
    if (r.status != 2 && r.err.find("Permission denied") != std::string::npos &&
        r.err.find("suite:") == std::string::npos)
        GTEST_SKIP() << "uid 65534 cannot reach the binary here: " << r.err;
    expect_refused(r, {"--out=" + out, "may not write it"});
    EXPECT_EQ(slurp(out), text);
    EXPECT_EQ(fs::status(out).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    EXPECT_TRUE(leftovers(d.path()).empty()) << join(leftovers(d.path()));
}

// Two runs on one --out: the second refuses at start and names the first; the first finishes
// with all its records; no lock file is left.
TEST(Output, ASecondRunOnTheSameOutputRefusesAtStartNamingTheFirst) {
    TempDir d;
    const std::string out = d.file("r.json");
    int o, e;
    const pid_t first = spawn({SUITE_BINARY, "--kernel=copy", "--sizes=16KiB,32KiB,64KiB", "--threads=1",
                               "--min-time=0.5", "--counters=none", "--energy=none", "--quiet", "--out=" + out},
                              o, e);
    bool locked = false;
    for (int i = 0; i < 400 && !locked; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        locked = fs::exists(out + ".lock");
    }
    ASSERT_TRUE(locked) << "the first run took no lock within 4 s";
    const Outcome second = run_suite(quick({"--out=" + out}));
    const Outcome first_done = finish(first, o, e, 120);
    expect_refused(second, {"--out=" + out, "another suite run", "pid " + std::to_string(first)});
    ASSERT_EQ(first_done.status, 0) << describe(first_done);
    const json doc = json::parse(slurp(out));
    EXPECT_EQ(doc["results"].size(), 3u);
    EXPECT_TRUE(doc["complete"].get<bool>());
    EXPECT_TRUE(leftovers(d.path()).empty()) << join(leftovers(d.path()));
}
