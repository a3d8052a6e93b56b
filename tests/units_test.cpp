#include <gtest/gtest.h>

#include "harness/units.hpp"

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
