#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"

namespace suite {

namespace {
// A function-local static: registration runs during static initialisation of other files,
// whose order relative to this one is unspecified.
std::vector<KernelEntry>& table() {
    static std::vector<KernelEntry> entries;
    return entries;
}
}  // namespace

namespace {
// The facts of a kernel are data, so that they are checked once, here, rather than in every
// place that reads them.
void check_info(const KernelInfo& info) {
    const std::string who = "kernel " + info.name + ": ";
    auto is_variant = [&](const std::string& v) {
        return std::find(info.variants.begin(), info.variants.end(), v) != info.variants.end();
    };
    if (info.variant_option != "phase" && info.variant_option != "strategy" && info.variant_option != "particles" &&
        info.variant_option != "isa")
        throw std::logic_error(who + "variant_option '" + info.variant_option +
                               "' is not 'phase', 'strategy', 'particles' or 'isa'");
    for (const auto& v : info.default_variants)
        if (!is_variant(v)) throw std::logic_error(who + "default variant '" + v + "' is not one of its variants");
    for (const auto& v : info.single_thread_variants)
        if (!is_variant(v))
            throw std::logic_error(who + "single-thread variant '" + v + "' is not one of its variants");
    for (std::size_t i = 0; i < info.params.size(); ++i) {
        const std::string& n = info.params[i].name;
        const bool lower =
            !n.empty() && std::isalpha(static_cast<unsigned char>(n[0])) && std::all_of(n.begin(), n.end(), [](char c) {
                return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
            });
        if (!lower)
            throw std::logic_error(who + "parameter '" + n +
                                   "' must be lower-case letters, digits and '-', starting with a letter");
        for (std::size_t j = 0; j < i; ++j)
            if (info.params[j].name == n) throw std::logic_error(who + "parameter '" + n + "' declared twice");
        // An old record's index must still name a choice this build has.
        for (const auto& old : info.params[i].v1_order)
            if (std::find(info.params[i].choices.begin(), info.params[i].choices.end(), old) ==
                info.params[i].choices.end())
                throw std::logic_error(who + "parameter '" + n + "': schema-1 name '" + old + "' is not a choice");
    }
}
}  // namespace

bool register_kernel(KernelEntry entry) {
    if (find_kernel(entry.info.name)) throw std::logic_error("kernel registered twice: " + entry.info.name);
    check_info(entry.info);
    auto& t = table();
    t.push_back(std::move(entry));
    std::sort(t.begin(), t.end(), [](const KernelEntry& a, const KernelEntry& b) {
        return a.info.group != b.info.group ? a.info.group < b.info.group : a.info.name < b.info.name;
    });
    return true;
}

const std::vector<KernelEntry>& kernels() { return table(); }

const KernelEntry* find_kernel(const std::string& name) {
    for (const auto& e : table())
        if (e.info.name == name) return &e;
    return nullptr;
}

std::vector<std::string> kernel_names() {
    std::vector<std::string> names;
    for (const auto& e : table()) names.push_back(e.info.name);
    return names;
}

Params default_params(const KernelInfo& info) {
    Params out;
    for (const auto& p : info.params)
        out[p.name] = p.choices.empty() ? ParamValue(p.default_value) : ParamValue(p.choices.front());
    return out;
}

std::string param_text(const ParamValue& v) {
    if (const auto* name = std::get_if<std::string>(&v)) return *name;
    return format_number(std::get<double>(v));
}

ParamValue parse_param(const std::string& name, const std::string& text) {
    const std::vector<std::string>* choices = nullptr;
    bool numbers_too = false;
    for (const auto& e : table())
        for (const auto& p : e.info.params)
            if (p.name == name && !p.choices.empty()) choices = &p.choices, numbers_too = p.numbers_too;
    if (!choices) return parse_finite(text, "--" + name);
    if (std::find(choices->begin(), choices->end(), text) != choices->end()) return text;
    if (numbers_too) {
        try {
            return parse_finite(text, "--" + name);
        } catch (const UsageError&) {
            throw UsageError("--" + name + "=" + text + ": " + join(*choices, ", ") + " or a number");
        }
    }
    const std::string hint = nearest(text, *choices);
    throw UsageError("unknown --" + name + " '" + text + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                     "; accepted: " + join(*choices, ", "));
}

bool single_thread_only(const KernelInfo& info, const std::string& variant) {
    return std::find(info.single_thread_variants.begin(), info.single_thread_variants.end(), variant) !=
           info.single_thread_variants.end();
}

namespace {
const ParamValue& find_param(const Params& params, const std::string& name) {
    auto it = params.find(name);
    if (it == params.end())
        throw std::logic_error("KernelConfig has no parameter '" + name +
                               "' (not declared in KernelInfo::params, or the config was built "
                               "without default_params)");
    return it->second;
}
}  // namespace

double KernelConfig::param(const std::string& name) const {
    const ParamValue& v = find_param(params, name);
    if (!std::holds_alternative<double>(v))
        throw std::logic_error("parameter '" + name + "' is a named one: read it with KernelConfig::choice");
    return std::get<double>(v);
}

const std::string& KernelConfig::choice(const std::string& name) const {
    const ParamValue& v = find_param(params, name);
    if (!std::holds_alternative<std::string>(v))
        throw std::logic_error("parameter '" + name + "' is a number: read it with KernelConfig::param");
    return std::get<std::string>(v);
}

void require_team_size(int got, int asked) {
    if (got != asked)
        throw std::runtime_error("OpenMP gave " + std::to_string(got) + " thread(s) where " + std::to_string(asked) +
                                 " were asked for (is OMP_THREAD_LIMIT set?)");
}

}  // namespace suite
