// A named choice's table: lookup, the one-line refusal with "did you mean" or a retired name's
// new one, and the help texts, all from the one list.
#include "harness/common/choice_table.hpp"

#include <gtest/gtest.h>

#include <string>

namespace suite {
namespace {

enum class Mode { fast, exact };

const ChoiceTable<Mode>& modes() {
    static const ChoiceTable<Mode> table{
        "mode",
        {{"fast", "quick and rough", Mode::fast}, {"exact", "slow and right", Mode::exact}},
        {{"quick", "fast"}}};
    return table;
}

std::string refusal(const std::string& name) {
    try {
        modes().at(name);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

TEST(ChoiceTable, FindsByNameAndRefusesOthersInOneLine) {
    EXPECT_EQ(modes().at("exact").what, Mode::exact);
    EXPECT_EQ(modes().find("slow"), nullptr);
    EXPECT_EQ(refusal("exakt"), "unknown mode 'exakt' (did you mean 'exact'?); accepted: fast, exact");
    EXPECT_EQ(refusal("quick"), "unknown mode 'quick' (now called 'fast'); accepted: fast, exact");
    EXPECT_EQ(refusal("zzzzzzzz"), "unknown mode 'zzzzzzzz'; accepted: fast, exact");
    EXPECT_EQ(modes().renamed("quick"), "fast");
    EXPECT_EQ(modes().renamed("fast"), "");
}

TEST(ChoiceTable, HelpTextsComeFromTheTable) {
    EXPECT_EQ(modes().accepted(), "fast, exact");
    EXPECT_EQ(modes().described(), "fast (quick and rough), exact (slow and right)");
    EXPECT_EQ(modes().listed(), "  fast   quick and rough\n  exact  slow and right\n");
}

TEST(ChoiceTable, SubsetKeepsOrderAndTheRetiredNamesLeadingIntoIt) {
    const ChoiceTable<Mode> exact = modes().subset([](Mode m) { return m == Mode::exact; });
    EXPECT_EQ(exact.accepted(), "exact");
    EXPECT_EQ(exact.what(), "mode");
    EXPECT_TRUE(exact.retired().empty());
    const ChoiceTable<Mode> both = modes().subset([](Mode) { return true; });
    EXPECT_EQ(both.accepted(), "fast, exact");
    EXPECT_EQ(both.renamed("quick"), "fast");
    try {
        exact.at("fast");
        ADD_FAILURE() << "a name left out of the subset was accepted";
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "unknown mode 'fast'; accepted: exact");
    }
}

TEST(ChoiceTable, ListedWrapsLongHelpUnderItself) {
    const ChoiceTable<int> t{"word", {{"w", std::string(60, 'a') + " " + std::string(60, 'b'), 0}}};
    EXPECT_EQ(t.listed(), "  w  " + std::string(60, 'a') + "\n     " + std::string(60, 'b') + "\n");
}

}  // namespace
}  // namespace suite
