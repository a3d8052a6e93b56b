#include <gtest/gtest.h>

#include "harness/common/units.hpp"

using namespace suite;

TEST(ParseBytes, BinaryAndDecimalUnits) {
    EXPECT_EQ(parse_bytes("4096"), 4096u);
    EXPECT_EQ(parse_bytes("64MiB"), 64ull << 20);
    EXPECT_EQ(parse_bytes("1.5GiB"), 3ull << 29);
    EXPECT_EQ(parse_bytes("16KiB"), 16384u);
    EXPECT_EQ(parse_bytes("100MB"), 100000000u);
    EXPECT_EQ(parse_bytes("2kB"), 2000u);
    EXPECT_EQ(parse_bytes("1GB"), 1000000000u);
    EXPECT_EQ(parse_bytes("3G"), 3ull << 30);
}

TEST(ParseBytes, RejectsWhatIsNotASize) {
    for (const char* bad : {"", "0", "-5MiB", "12XB", "MiB", "1.2.3", "5 MiB", "0.1B", "1e3"}) {
        EXPECT_THROW(parse_bytes(bad), UsageError) << bad;
    }
    try {
        parse_bytes("12XB");
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("'XB'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("KiB"), std::string::npos) << e.what();
    }
}

TEST(ParseSizeList, LogSweepsAndLists) {
    EXPECT_EQ(parse_size_list("16KiB:128KiB"), (std::vector<std::uint64_t>{16384, 32768, 65536, 131072}));
    EXPECT_EQ(parse_size_list("1KiB:4KiB:x1.5"), (std::vector<std::uint64_t>{1024, 1536, 2304, 3456}));
    EXPECT_EQ(parse_size_list("32KiB,1MiB"), (std::vector<std::uint64_t>{32768, 1048576}));
    EXPECT_EQ(parse_size_list("64MiB"), (std::vector<std::uint64_t>{64ull << 20}));
    EXPECT_THROW(parse_size_list("1GiB:16KiB"), UsageError);
    EXPECT_THROW(parse_size_list("16KiB:1GiB:x1"), UsageError);
    EXPECT_THROW(parse_size_list("16KiB:1GiB:x0.5"), UsageError);
    EXPECT_THROW(parse_size_list("16KiB:1GiB:2:3"), UsageError);
    EXPECT_THROW(parse_size_list("1B:1TiB:x1.01"), UsageError);  // more than 1000 points
}

TEST(ParseThreadList, ListsRangesStepsAndAll) {
    EXPECT_EQ(parse_thread_list("1,2,4", 8), (std::vector<int>{1, 2, 4}));
    EXPECT_EQ(parse_thread_list("1-4", 8), (std::vector<int>{1, 2, 3, 4}));
    EXPECT_EQ(parse_thread_list("2-8:3", 8), (std::vector<int>{2, 5, 8}));
    EXPECT_EQ(parse_thread_list("all", 8), (std::vector<int>{8}));
    EXPECT_EQ(parse_thread_list("1,all", 8), (std::vector<int>{1, 8}));
    for (const char* bad : {"0", "9", "", "a", "4-2", "1-4:0", "-1", "1-999999999"}) EXPECT_THROW(parse_thread_list(bad, 8), UsageError) << bad;
}

TEST(ParseCpuList, RangesAndDuplicates) {
    EXPECT_EQ(parse_cpu_list("0,2,4-6"), (std::vector<int>{0, 2, 4, 5, 6}));
    EXPECT_THROW(parse_cpu_list("3-1"), UsageError);
    EXPECT_THROW(parse_cpu_list("1,1"), UsageError);
    EXPECT_THROW(parse_cpu_list("x"), UsageError);
    EXPECT_THROW(parse_cpu_list("0-99999999"), UsageError);  // refused before expanding
}

TEST(FormatBytes, ReadableUnits) {
    EXPECT_EQ(format_bytes(64ull << 20), "64MiB");
    EXPECT_EQ(format_bytes(1000), "1000B");
    EXPECT_EQ(format_bytes(3ull << 29), "1.5GiB");
    EXPECT_EQ(format_bytes(1024500), "1000KiB");  // not 1e+03KiB
    EXPECT_EQ(format_bytes(1300), "1.27KiB");
}

TEST(Nearest, SuggestsCloseNamesOnly) {
    const std::vector<std::string> names{"copy", "scale", "add", "triad", "sin-add", "latency"};
    EXPECT_EQ(nearest("ad", names), "add");
    EXPECT_EQ(nearest("tirad", names), "triad");
    EXPECT_EQ(nearest("sinadd", names), "sin-add");
    EXPECT_EQ(nearest("qwertyuiop", names), "");
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}
