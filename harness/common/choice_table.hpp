#pragma once
// A named choice (an MPM case, a particle order, a scatter strategy, a store variant, ...) declared
// once as a table of {name, help line, behaviour}: parsing, --help text, "did you mean" and the
// records all read the table, as LLVM's cl::values and CLI11's CheckedTransformer do, so that no
// list of names is ever copied by hand and no code compares a choice with a string literal.
// Records keep the name, never a position in the table: inserting a choice changes no old file.
#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"

namespace suite {

template <class Behaviour>
struct Choice {
    std::string name;
    std::string help;  // one short phrase, for --help and `suite list`
    Behaviour what{};
};

template <class Behaviour>
class ChoiceTable {
public:
    // `what` names the choice in messages ("MPM case"); `retired` maps names no longer accepted to
    // the names that replaced them, so that the refusal says where the old name went.
    ChoiceTable(std::string what, std::vector<Choice<Behaviour>> choices,
                std::vector<std::pair<std::string, std::string>> retired = {})
        : what_(std::move(what)), choices_(std::move(choices)), retired_(std::move(retired)) {}

    const std::vector<Choice<Behaviour>>& all() const { return choices_; }
    const std::string& what() const { return what_; }

    // The entries whose behaviour `keep` accepts, in order, with the retired names that lead to
    // them: a user of some of a table's choices reads them from the table, never from a copy.
    template <class Keep>
    ChoiceTable subset(Keep keep) const {
        std::vector<Choice<Behaviour>> kept;
        for (const auto& c : choices_)
            if (keep(c.what)) kept.push_back(c);
        std::vector<std::pair<std::string, std::string>> retired;
        for (const auto& r : retired_)
            for (const auto& c : kept)
                if (c.name == r.second) retired.push_back(r);
        return ChoiceTable(what_, std::move(kept), std::move(retired));
    }

    // nullptr for a name that is not in the table.
    const Choice<Behaviour>* find(std::string_view name) const {
        for (const auto& c : choices_)
            if (c.name == name) return &c;
        return nullptr;
    }

    // The entry named `name`, else a UsageError "unknown WHAT 'x' (did you mean 'y'?); accepted:
    // a, b, c" (for a retired name: "(now called 'y')").
    const Choice<Behaviour>& at(std::string_view name) const {
        if (const Choice<Behaviour>* c = find(name)) return *c;
        std::string hint = nearest(name, names());
        std::string why = hint.empty() ? "" : " (did you mean '" + hint + "'?)";
        for (const auto& [old_name, new_name] : retired_)
            if (old_name == name) why = " (now called '" + new_name + "')";
        throw UsageError("unknown " + what_ + " '" + std::string(name) + "'" + why + "; accepted: " + accepted());
    }

    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& c : choices_) out.push_back(c.name);
        return out;
    }
    // "a, b, c": what a message lists as accepted.
    std::string accepted() const { return join(names(), ", "); }
    // "a (help), b (help), c (help)": an option's --help text.
    std::string described() const {
        std::vector<std::string> out;
        for (const auto& c : choices_) out.push_back(c.help.empty() ? c.name : c.name + " (" + c.help + ")");
        return join(out, ", ");
    }
    // A --help block: a line a choice, "  name  help", the help wrapped at 100 columns under itself.
    std::string listed() const {
        std::size_t indent = 0;
        for (const auto& c : choices_) indent = std::max(indent, c.name.size() + 4);
        std::string out;
        for (const auto& c : choices_) {
            std::string line = "  " + c.name + std::string(indent - 2 - c.name.size(), ' ');
            std::size_t width = indent;
            for (const auto& word : split(c.help, ' ')) {
                const bool first = width == indent;
                if (!first && width + 1 + word.size() > 100) line += "\n" + std::string(indent, ' '), width = indent;
                line += (width == indent ? "" : " ") + word;
                width += word.size() + (width == indent ? 0 : 1);
            }
            out += line + "\n";
        }
        return out;
    }
    // The names no longer accepted, each with the one that replaced it.
    const std::vector<std::pair<std::string, std::string>>& retired() const { return retired_; }
    // The name that replaced a retired one; "" when `name` was never retired.
    std::string renamed(std::string_view name) const {
        for (const auto& [old_name, new_name] : retired_)
            if (old_name == name) return new_name;
        return "";
    }

private:
    std::string what_;
    std::vector<Choice<Behaviour>> choices_;
    std::vector<std::pair<std::string, std::string>> retired_;
};

}  // namespace suite
