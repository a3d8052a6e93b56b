#include <string>

#include <gtest/gtest.h>

#include "harness/common/did_you_mean.hpp"
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

// The message of the UsageError `f` throws ("" when it throws none).
template <class F>
std::string refusal(F f) {
    try {
        f();
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

TEST(ParseBytes, FractionsAreExactAndAWholeNumberOfBytes) {
    EXPECT_EQ(parse_bytes("1.5KiB"), 1536u);
    EXPECT_EQ(parse_bytes("1.1MB"), 1100000u);  // exact, not 1.1 * 1e6 in floating point
    EXPECT_EQ(parse_bytes("0.0009765625KiB"), 1u);
    EXPECT_EQ(parse_bytes("1.50KiB"), 1536u);
    EXPECT_EQ(parse_bytes("1000000000000000000"), 1000000000000000000u);
    const std::string half = refusal([] { parse_bytes("1.5B"); });
    EXPECT_NE(half.find("'1.5B': that is 1.5 bytes, not a whole number of bytes"), std::string::npos) << half;
    EXPECT_NE(refusal([] { parse_bytes("0.3KiB"); }).find("307.2 bytes"), std::string::npos);
    // Never an exception other than UsageError, whatever the digits (std::stod threw out_of_range).
    EXPECT_NE(refusal([] { parse_bytes(std::string(400, '9')); }).find("too large"), std::string::npos);
    EXPECT_NE(refusal([] { parse_bytes("1000000000000000001"); }).find("at most 1000000000000000000 bytes"),
              std::string::npos);
    EXPECT_NE(refusal([] { parse_bytes("0." + std::string(60, '0') + "1KiB"); }), "");
}

TEST(WholeNumbers, StrictDigitsAndTheRangeInTheMessage) {
    EXPECT_EQ(whole_number("0"), 0u);
    EXPECT_EQ(whole_number("18446744073709551615"), UINT64_MAX);
    for (const char* bad :
         {"", "-1", "+1", " 1", "1 ", "1.0", "1e3", "0x10", "18446744073709551616", "99999999999999999999999"})
        EXPECT_FALSE(whole_number(bad).has_value()) << bad;
    EXPECT_FALSE(whole_number("33", 32).has_value());
    EXPECT_EQ(parse_whole("7", "--reps", 1, 10), 7u);
    EXPECT_EQ(refusal([] { parse_whole("0", "--reps", 1, 10000000); }),
              "--reps=0: expected a whole number from 1 to 10000000");
    EXPECT_EQ(refusal([] { parse_whole("40", "--depth", 1, 32, "in 2D"); }),
              "--depth=40: expected a whole number from 1 to 32 (in 2D)");
}

TEST(ParseSeed, ZeroToTwoToThe64MinusOneExactly) {
    EXPECT_EQ(parse_seed("0"), 0u);
    EXPECT_EQ(parse_seed("18446744073709551615"), UINT64_MAX);
    for (const char* bad : {"-1", "+1", "18446744073709551616", "1.5", "", "abc"}) {
        const std::string m = refusal([&] { parse_seed(bad); });
        EXPECT_EQ(m, "--seed=" + std::string(bad) + ": expected a whole number from 0 to 18446744073709551615") << bad;
    }
}

TEST(ParseNameList, EachNameOnceInTheOrderGiven) {
    EXPECT_EQ(parse_name_list("triad,add", "--kernel"), (std::vector<std::string>{"triad", "add"}));
    EXPECT_EQ(refusal([] { parse_name_list("add,triad,add", "--kernel"); }),
              "--kernel=add,triad,add names 'add' twice; give each once");
    EXPECT_NE(refusal([] { parse_name_list("add,", "--kernel"); }).find("empty name"), std::string::npos);
}

TEST(ParseSizeList, AValueGivenTwiceIsRefused) {
    EXPECT_NE(refusal([] { parse_size_list("1MiB,1MiB"); }).find("names 1MiB twice"), std::string::npos);
    EXPECT_NE(refusal([] { parse_size_list("1MiB,1024KiB"); }).find("(as '1MiB' and '1024KiB')"), std::string::npos);
    // A sweep whose steps round to the same byte count twice.
    EXPECT_NE(refusal([] { parse_size_list("1:16:x1.2"); }).find("gives 1B twice"), std::string::npos);
    EXPECT_EQ(parse_size_list("1:16:x2"), (std::vector<std::uint64_t>{1, 2, 4, 8, 16}));
}

TEST(ParseSizeList, TheSweepFactorIsAPlainDecimalAboveOne) {
    for (const char* bad : {"1KiB:1MiB:x1e9", "1KiB:1MiB:x-2", "1KiB:1MiB:x", "1KiB:1MiB:x1", "1KiB:1MiB:x0.5"}) {
        const std::string m = refusal([&] { parse_size_list(bad); });
        EXPECT_NE(m.find("expected x and a decimal number above 1"), std::string::npos) << bad << ": " << m;
    }
    EXPECT_NE(refusal([] { parse_size_list("1KiB:1MiB:x" + std::string(400, '9')); }), "");  // no std::out_of_range
}

TEST(ParseCountList, WholeCountsInTheKernelsUnit) {
    EXPECT_EQ(parse_count("10000", "elements", "sfc-build"), 10000u);
    EXPECT_EQ(parse_count_list("1000:100000:x10", "elements", "sfc-build"),
              (std::vector<std::uint64_t>{1000, 10000, 100000}));
    for (const char* bad : {"0", "1.5", "1MiB", "-3"}) {
        const std::string m = refusal([&] { parse_count(bad, "elements", "sfc-build"); });
        EXPECT_NE(m.find("for sfc-build, which is sized by a count of elements"), std::string::npos) << m;
        EXPECT_EQ(m.find("byte"), std::string::npos) << m;
    }
    EXPECT_NE(refusal([] { parse_count_list("10,10", "elements", "sfc-build"); }).find("10 elements twice"),
              std::string::npos);
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
    for (const char* bad : {"0", "9", "", "a", "4-2", "1-4:0", "-1", "1-999999999"})
        EXPECT_THROW(parse_thread_list(bad, 8), UsageError) << bad;
}

TEST(ParseThreadList, MessagesNameTheValueAndRepeatsAreRefused) {
    EXPECT_NE(refusal([] {
                  parse_thread_list("-1", 8);
              }).find("invalid thread count '-1' in '-1': expected whole numbers from 1 to 8"),
              std::string::npos);
    EXPECT_NE(refusal([] { parse_thread_list("1-", 8); }).find("invalid thread range '1-'"), std::string::npos);
    EXPECT_NE(refusal([] { parse_thread_list("1,,2", 8); }).find("empty item"), std::string::npos);
    EXPECT_NE(refusal([] {
                  parse_thread_list("2,1-4", 8);
              }).find("thread count 2 is given twice in '2,1-4' (by '2' and '1-4')"),
              std::string::npos);
    EXPECT_NE(refusal([] { parse_thread_list("8,all", 8); }).find("thread count 8 is given twice"), std::string::npos);
    EXPECT_NE(
        refusal([] { parse_thread_list("99999999999999999999999", 8); }).find("is more than the 8 processing units"),
        std::string::npos);
    // With a limit other than this machine's PUs, 'all' means nothing and the limit is named.
    EXPECT_NE(
        refusal([] { parse_thread_list("2000", 1024, "the most blocks"); }).find("more than 1024: the most blocks"),
        std::string::npos);
    EXPECT_NE(refusal([] { parse_thread_list("1,all", 1024, "the most blocks"); }).find("'all'"), std::string::npos);
}

TEST(ParseCpuList, RangesAndDuplicates) {
    EXPECT_EQ(parse_cpu_list("0,2,4-6"), (std::vector<int>{0, 2, 4, 5, 6}));
    EXPECT_THROW(parse_cpu_list("3-1"), UsageError);
    EXPECT_THROW(parse_cpu_list("1,1"), UsageError);
    EXPECT_THROW(parse_cpu_list("x"), UsageError);
    EXPECT_THROW(parse_cpu_list("0-99999999"), UsageError);  // refused before expanding
    EXPECT_NE(refusal([] { parse_cpu_list("0-"); }).find("invalid CPU range '0-' in '0-'"), std::string::npos);
    EXPECT_NE(refusal([] { parse_cpu_list("-1"); }).find("invalid CPU number '-1'"), std::string::npos);
    EXPECT_NE(refusal([] { parse_cpu_list("0-3,2"); }).find("CPU 2 is given twice in '0-3,2'"), std::string::npos);
    EXPECT_NE(refusal([] { parse_cpu_list("99999999999"); }).find("too large"), std::string::npos);
}

TEST(FormatBytes, ReadableUnits) {
    EXPECT_EQ(format_bytes(64ull << 20), "64MiB");
    EXPECT_EQ(format_bytes(1000), "1000B");
    EXPECT_EQ(format_bytes(3ull << 29), "1.5GiB");
    EXPECT_EQ(format_bytes(1024500), "1000KiB");  // not 1e+03KiB
    // Near the largest size an option takes, never rounded past it: the text must parse back.
    EXPECT_EQ(format_bytes(999999999999999966ull), "909494TiB");
    EXPECT_NO_THROW(parse_bytes(format_bytes(999999999999999966ull)));
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
