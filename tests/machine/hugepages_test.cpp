// --hugepages: the option's parsing, the smaps reading that says how much of an array huge
// pages back, the Arena's advice on this machine (page histograms still whole), and the field in
// a result file, validated against the schema.
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/machine/placement.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;
using json = nlohmann::json;

namespace {

const char* const smaps_text =
    "55d0c0a00000-55d0c0a21000 rw-p 00000000 00:00 0                          [heap]\n"
    "Size:                132 kB\n"
    "AnonHugePages:         0 kB\n"
    "7f1200000000-7f1200800000 rw-p 00000000 00:00 0 \n"
    "Size:               8192 kB\n"
    "Rss:                8192 kB\n"
    "AnonHugePages:      6144 kB\n"
    "VmFlags: rd wr mr mw me ac hg\n"
    "7f1200800000-7f1200801000 ---p 00000000 00:00 0 \n"
    "Size:                  4 kB\n"
    "7f1300000000-7f1300001000 rw-p 00000000 00:00 0 \n"
    "Size:                  4 kB\n"
    "VmFlags: rd wr mr mw me ac\n";

std::string thp_setting() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    std::getline(in, line);
    return line;
}

// Allocates `bytes` under `h`, touches every byte, and returns what the Arena observed.
ArrayPlacement touched_array(HugePages h, std::size_t bytes) {
    MemoryPolicy policy;
    policy.hugepages = h;
    Arena arena(policy);
    auto* p = static_cast<char*>(arena.allocate_bytes("x", bytes));
    if (h == HugePages::thp && bytes >= (2u << 20)) {
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % (2u << 20), 0u)
            << "an array asked to use huge pages starts on 2 MiB";
    }
    std::memset(p, 1, bytes);
    auto seen = arena.observe();
    EXPECT_EQ(seen.size(), 1u);
    return seen.at(0);
}

void expect_whole_histogram(const ArrayPlacement& a, std::size_t bytes) {
    const auto page = static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
    EXPECT_EQ(a.bytes, bytes);
    EXPECT_EQ(a.pages, bytes / page);
    std::uint64_t counted = a.pages_not_present;
    for (const auto& [node, n] : a.pages_per_node) counted += n;
    EXPECT_EQ(counted, a.pages) << "every base page is counted once, huge or not";
    EXPECT_EQ(a.pages_not_present, 0u) << a.error;
}

}  // namespace

TEST(HugePagesSmaps, ReadsTheMappingWithExactlyTheseBounds) {
    EXPECT_EQ(anon_huge_bytes_in_smaps(smaps_text, 0x7f1200000000, 0x7f1200800000),
              std::optional<std::uint64_t>(6144u * 1024));
    EXPECT_EQ(anon_huge_bytes_in_smaps(smaps_text, 0x55d0c0a00000, 0x55d0c0a21000), std::optional<std::uint64_t>(0));
    // Bounds that are not a mapping's (a merged or partial range) are not guessed at.
    EXPECT_FALSE(anon_huge_bytes_in_smaps(smaps_text, 0x7f1200000000, 0x7f1200400000));
    EXPECT_FALSE(anon_huge_bytes_in_smaps(smaps_text, 0x7f1200100000, 0x7f1200800000));
    // A mapping without the line (the next header comes first, or the file ends).
    EXPECT_FALSE(anon_huge_bytes_in_smaps(smaps_text, 0x7f1200800000, 0x7f1200801000));
    EXPECT_FALSE(anon_huge_bytes_in_smaps(smaps_text, 0x7f1300000000, 0x7f1300001000));
    EXPECT_FALSE(anon_huge_bytes_in_smaps("", 0x1000, 0x2000));
}

TEST(HugePagesOption, ParsesRefusesThpWhereTheKernelHasNoneAndWarnsWhereItIsOff) {
    TempDir dir;
    const std::string madvise = dir.file("madvise"), never = dir.file("never");
    std::ofstream(madvise) << "always [madvise] never\n";
    std::ofstream(never) << "always madvise [never]\n";
    std::string note;
    EXPECT_EQ(parse_hugepages("thp", madvise, &note), HugePages::thp);
    EXPECT_TRUE(note.empty()) << note;
    EXPECT_EQ(parse_hugepages("none", never, &note), HugePages::none);
    EXPECT_EQ(parse_hugepages("system", never, &note), HugePages::system);
    EXPECT_TRUE(note.empty()) << note;
    // Switched off: the run may go on (madvise succeeds and gets nothing), and is told so.
    EXPECT_EQ(parse_hugepages("thp", never, &note), HugePages::thp);
    EXPECT_NE(note.find("switched off"), std::string::npos) << note;
    // No THP in the kernel at all: madvise would fail, so it is refused up front.
    EXPECT_THROW(parse_hugepages("thp", dir.file("no-such-file")), UsageError);
    try {
        parse_hugepages("huge", madvise);
        ADD_FAILURE() << "an unknown value was accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("accepted: thp, none, system"), std::string::npos) << e.what();
    }
    EXPECT_STREQ(hugepages_name(HugePages::thp), "thp");
    EXPECT_STREQ(hugepages_name(HugePages::none), "none");
    EXPECT_STREQ(hugepages_name(HugePages::system), "system");
}

TEST(HugePagesArena, NoneGetsNoHugePagesAndTheHistogramStaysWhole) {
    const std::size_t bytes = 8u << 20;
    const ArrayPlacement a = touched_array(HugePages::none, bytes);
    expect_whole_histogram(a, bytes);
    ASSERT_TRUE(a.anon_huge_bytes) << a.huge_error;
    EXPECT_EQ(*a.anon_huge_bytes, 0u) << "MADV_NOHUGEPAGE must keep huge pages out";
}

TEST(HugePagesArena, ThpBacksTheArrayWithHugePagesAndTheHistogramStaysWhole) {
    const std::string setting = thp_setting();
    if (setting.empty() || setting.find("[never]") != std::string::npos)
        GTEST_SKIP() << "transparent huge pages are not available here (" << setting << ")";
    const std::size_t bytes = 8u << 20;
    const ArrayPlacement a = touched_array(HugePages::thp, bytes);
    expect_whole_histogram(a, bytes);
    ASSERT_TRUE(a.anon_huge_bytes) << a.huge_error;
    // The fault handler gives a huge page to each aligned 2 MiB of an advised range when it can
    // find one; with memory this free (a test machine) at least one of the four is expected.
    EXPECT_GT(*a.anon_huge_bytes, 0u);
    EXPECT_LE(*a.anon_huge_bytes, bytes);
}

TEST(HugePagesE2E, TheRecordSaysWhatWasAskedAndWhatHappenedAndValidates) {
    TempDir dir;
    const std::string setting = thp_setting();
    const bool thp_possible = !setting.empty() && setting.find("[never]") == std::string::npos;
    for (const std::string mode : {"system", "none", "thp"}) {
        if (mode == "thp" && !thp_possible) continue;
        const std::string out = dir.file(mode + ".json");
        Outcome r = run_suite({"--kernel=triad,load", "--size=24MiB", "--threads=1", "--reps=1", "--quiet",
                               "--hugepages=" + mode, "--out=" + out});
        ASSERT_EQ(r.status, 0) << describe(r);
        const json doc = json::parse(slurp(out));
        for (const auto& rec : doc["results"]) {
            EXPECT_EQ(rec["hugepages"]["requested"], mode);
            ASSERT_TRUE(rec["hugepages"]["anon_huge_bytes"].is_number_integer()) << rec["hugepages"].dump();
            std::uint64_t sum = 0;
            for (const auto& a : rec["placement"]["arrays"]) sum += a["anon_huge_bytes"].get<std::uint64_t>();
            EXPECT_EQ(rec["hugepages"]["anon_huge_bytes"].get<std::uint64_t>(), sum);
            if (mode == "none") {
                EXPECT_EQ(sum, 0u);
            }
            if (mode == "thp") {
                EXPECT_GT(sum, 0u);
            }
        }
        Outcome v = validate_against_schema(out);
        EXPECT_EQ(v.status, 0) << v.out << v.err;
    }
}
