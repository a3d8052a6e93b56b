// read_attribute: a kernel attribute file is read as one answers (a regular file, at most 4 KiB,
// there at once); anything else is refused at once with the reason, never waited on.
#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "harness/common/sysfs_file.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite;

namespace {

void write(const std::string& path, const std::string& content) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
}

}  // namespace

TEST(SysfsFile, FirstLineOfARegularFile) {
    test::TempDir d;
    write(d.file("energy_uj"), "123456\n");
    const AttributeText a = read_attribute(d.file("energy_uj"));
    ASSERT_TRUE(a.ok) << a.reason;
    EXPECT_EQ(a.text, "123456");
    write(d.file("exactly"), std::string(max_attribute_bytes, '7'));
    EXPECT_TRUE(read_attribute(d.file("exactly")).ok);
}

TEST(SysfsFile, AFifoIsRefusedAtOnceNotWaitedOn) {
    test::TempDir d;
    const std::string fifo = d.file("energy_uj");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
    const auto t0 = std::chrono::steady_clock::now();
    const AttributeText a = read_attribute(fifo);  // no writer: open(O_RDONLY) alone would block forever
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    EXPECT_FALSE(a.ok);
    EXPECT_EQ(a.error, 0);
    EXPECT_NE(a.reason.find(fifo + " is a named pipe (FIFO), which a sysfs attribute never is"), std::string::npos)
        << a.reason;
}

TEST(SysfsFile, DevicesDirectoriesAndLargeFilesAreRefused) {
    test::TempDir d;
    const AttributeText zero = read_attribute("/dev/zero");  // would answer forever
    EXPECT_FALSE(zero.ok);
    EXPECT_NE(zero.reason.find("a character device"), std::string::npos) << zero.reason;
    const AttributeText dir = read_attribute(d.path().string());
    EXPECT_FALSE(dir.ok);
    EXPECT_NE(dir.reason.find("a directory"), std::string::npos) << dir.reason;
    write(d.file("big"), std::string(max_attribute_bytes + 1, '1'));
    const AttributeText big = read_attribute(d.file("big"));
    EXPECT_FALSE(big.ok);
    EXPECT_NE(big.reason.find("holds more than 4096 bytes"), std::string::npos) << big.reason;
}

TEST(SysfsFile, AMissingFileGivesItsErrno) {
    test::TempDir d;
    const AttributeText a = read_attribute(d.file("nothing"));
    EXPECT_FALSE(a.ok);
    EXPECT_EQ(a.error, ENOENT);
    EXPECT_NE(a.reason.find("cannot read " + d.file("nothing") + ": No such file or directory"), std::string::npos)
        << a.reason;
}
