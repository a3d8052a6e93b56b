// The variants of one kernel that --phase, --strategy, --particles and --isa pick, or its default
// ones (a section of make_plan: plan_parts.hpp).
#include <algorithm>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/measure/plan_parts.hpp"

namespace suite::plan_parts {
namespace {

// "phases", "strategies"; "particles" is its own plural ("kernels with particles").
std::string plural(const std::string& noun) {
    if (noun == "particles") return "particle orders";
    return noun.back() == 'y' ? noun.substr(0, noun.size() - 1) + "ies" : noun + "s";
}

// The names a kernel's variant option takes, each with the variant it stands for: the variants but
// "" and the store ones, and the plain kernel by its name ("all" for phases, or plain_variant_name).
std::vector<std::pair<std::string, std::string>> option_choices(const KernelInfo& info) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& v : info.variants)
        if (!v.empty() && !is_store_variant(v)) out.push_back({v, v});
    const bool plain = std::find(info.variants.begin(), info.variants.end(), "") != info.variants.end();
    if (!out.empty() && plain && info.variant_option == "phase")
        out.insert(out.begin(), {"all", ""});
    else if (!out.empty() && plain && !info.plain_variant_name.empty())
        out.insert(out.begin(), {info.plain_variant_name, ""});
    return out;
}

// The refusal of an option the kernel does not take, naming the kernels that do.
UsageError not_its_option(const KernelInfo& info, const std::string& option, bool has_choices) {
    std::vector<std::string> with;
    for (const auto& e : kernels())
        if (e.info.variant_option == option && !option_choices(e.info).empty()) with.push_back(e.info.name);
    return UsageError("kernel '" + info.name + "' has no " + plural(option) + ", so --" + option + " does not apply" +
                      (has_choices ? " (it takes --" + info.variant_option + ")" : "") + "; kernels with " +
                      plural(option) + ": " + (with.empty() ? std::string("none") : join(with, ", ")));
}

}  // namespace

std::vector<std::string> first_of(const std::vector<std::pair<std::string, std::string>>& pairs) {
    std::vector<std::string> out;
    for (const auto& p : pairs) out.push_back(p.first);
    return out;
}

Variants plan_variants(const KernelInfo& info, const std::string& stores_variant,
                       const std::vector<std::pair<std::string, std::string>>& options) {
    Variants out;
    for (const auto& [option, text] : options) {
        if (text.empty()) continue;
        const auto choices = option_choices(info);
        if (info.variant_option != option || choices.empty()) throw not_its_option(info, option, !choices.empty());
        out.named = true;
        out.option = "--" + option + "=" + text;
        for (const auto& name : parse_name_list(text, "--" + option)) {
            auto it = std::find_if(choices.begin(), choices.end(), [&](const auto& c) { return c.first == name; });
            if (it == choices.end()) {
                // A name the kernel has retired: the one that replaced it; else the nearest.
                std::string hint = nearest(name, first_of(choices));
                for (const auto& [old_name, new_name] : info.retired_variants)
                    if (old_name == name) hint = new_name;
                throw UsageError("kernel '" + info.name + "' has no " +
                                 (option == "particles" ? "particle order" : option) + " '" + name + "'" +
                                 (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; " + plural(option) +
                                 ": " + join(first_of(choices), ", "));
            }
            out.list.push_back(*it);
        }
    }
    if (!out.named) {
        if (stores_variant.empty() && !info.default_variants.empty())
            for (const auto& v : info.default_variants) out.list.push_back({v, v});
        else
            out.list.push_back({stores_variant, stores_variant});
    }
    return out;
}

}  // namespace suite::plan_parts
