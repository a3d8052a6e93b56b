#include "harness/results/context_fields.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <set>

#include "harness/common/units.hpp"

namespace suite {

using nlohmann::json;

namespace {

// A setting read from the system: its value, or "unknown" when the record says why not.
std::string setting_text(const json& v) {
    if (!v.is_object()) return "?";
    auto it = v.find("value");
    if (it == v.end()) return "?";
    return it->is_string() ? it->get<std::string>() : "unknown";
}

}  // namespace

std::string instruction_set_text(const nlohmann::json& is) {
    if (!is.is_object()) return "?";
    auto flag = [&](const char* k) { return is.contains(k) && is[k].is_boolean() && is[k].get<bool>(); };
    if (is.value("arch", "x86_64") == "aarch64") {
        if (!flag("sve")) return "NEON";
        const auto bits = is.find("sve_vector_bits");
        return "SVE" + (bits != is.end() && bits->is_number_integer() ? " " + std::to_string(bits->get<int>()) + "-bit"
                                                                      : std::string());
    }
    return flag("avx512f") ? "AVX-512" : flag("avx2") ? "AVX2" : "SSE2";
}

std::string context_text(const json& c, const std::string& field) {
    if (!c.is_object()) return "?";
    if (field == "caches") {
        const auto topo = c.find("topology");
        if (topo == c.end() || !topo->is_object() || !topo->contains("caches") || !(*topo)["caches"].is_array())
            return "?";
        std::string out;
        for (const auto& cache : (*topo)["caches"]) {
            if (!cache.is_object() || !cache.contains("level") || !cache["level"].is_number_integer() ||
                !cache.contains("size_bytes") || !cache["size_bytes"].is_number_unsigned())
                return "?";
            const std::string type =
                cache.contains("type") && cache["type"].is_string() ? cache["type"].get<std::string>() : "";
            std::string item = "L" + std::to_string(cache["level"].get<std::int64_t>()) +
                               (type == "data"          ? "d"
                                : type == "instruction" ? "i"
                                                        : "") +
                               " " + format_bytes(cache["size_bytes"].get<std::uint64_t>());
            if (cache.contains("instances") && cache["instances"].is_number_integer())
                item += " x" + std::to_string(cache["instances"].get<std::int64_t>());
            out += (out.empty() ? "" : ", ") + item;
        }
        return out.empty() ? "none reported" : out;
    }
    const auto it = c.find(field);
    if (it == c.end()) return "?";
    if (field == "transparent_hugepages" || field == "frequency_governor") return setting_text(*it);
    if (field == "instruction_set") {
        if (!it->is_object()) return "?";
        return instruction_set_text(*it);
    }
    if (field == "memory_bytes" && it->is_number_unsigned()) return format_bytes(it->get<std::uint64_t>());
    if (it->is_string()) return it->get<std::string>();
    if (it->is_number_integer()) return std::to_string(it->get<std::int64_t>());
    return "?";
}

const std::vector<std::string>& context_fields_that_matter() {
    static const std::vector<std::string> fields = {"cpu_model",
                                                    "sockets",
                                                    "numa_node_count",
                                                    "cores",
                                                    "pus",
                                                    "caches",
                                                    "memory_bytes",
                                                    "compiler",
                                                    "compiler_flags",
                                                    "build_type",
                                                    "instruction_set",
                                                    "transparent_hugepages",
                                                    "frequency_governor"};
    return fields;
}

std::vector<std::pair<std::string, std::vector<std::string>>> context_differences(
    const std::vector<const ResultFile*>& files) {
    std::vector<std::pair<std::string, std::vector<std::string>>> out;
    for (const auto& field : context_fields_that_matter()) {
        std::vector<std::string> values;
        for (const auto* f : files) values.push_back(context_text(f->context, field));
        if (std::adjacent_find(values.begin(), values.end(), std::not_equal_to<>()) != values.end())
            out.push_back({field, values});
    }
    std::vector<std::string> huge;
    for (const auto* f : files) {
        std::set<std::string> asked;
        for (const auto& p : f->points) asked.insert(p.hugepages.empty() ? "not recorded" : p.hugepages);
        std::string text;
        for (const auto& a : asked) text += (text.empty() ? "" : ", ") + a;
        huge.push_back(text.empty() ? "no points" : text);
    }
    if (std::adjacent_find(huge.begin(), huge.end(), std::not_equal_to<>()) != huge.end())
        out.push_back({"hugepages", huge});
    // The processes of the run: one, or MPI ranks on hosts (which rank ran where).
    std::vector<std::string> procs;
    for (const auto* f : files) {
        std::string text = f->processes_label();
        if (f->mpi) {
            text += " (" + f->mpi->layout + "):";
            for (const auto& h : f->mpi->hosts) {
                text += " " + h.host + " [";
                for (std::size_t i = 0; i < h.ranks.size(); ++i)
                    text.append(i ? "," : "").append(std::to_string(h.ranks[i]));
                text += "]";
            }
        }
        procs.push_back(text);
    }
    if (std::adjacent_find(procs.begin(), procs.end(), std::not_equal_to<>()) != procs.end())
        out.push_back({"mpi", procs});
    return out;
}

namespace {

std::vector<std::string> flag_words(const nlohmann::json& context) {
    std::vector<std::string> out;
    std::string word;
    for (char c : context_text(context, "compiler_flags") + " ") {
        if (c != ' ' && c != '\t') {
            word += c;
        } else if (!word.empty()) {
            if (std::find(out.begin(), out.end(), word) == out.end()) out.push_back(word);
            word.clear();
        }
    }
    return out;
}

}  // namespace

FieldKind context_field_kind(const std::string& field, const std::vector<const ResultFile*>& files) {
    if (field == "instruction_set" && !files.empty() && std::all_of(files.begin(), files.end(), [](const auto* f) {
            const auto words = flag_words(f->context);
            return std::find(words.begin(), words.end(), "-march=native") != words.end();
        }))
        return FieldKind::machine;
    return context_field_kind(field);
}

std::string flags_difference(const std::vector<const ResultFile*>& files) {
    std::vector<std::vector<std::string>> words;
    std::vector<std::string> all;
    for (const auto* f : files) {
        words.push_back(flag_words(f->context));
        for (const auto& w : words.back())
            if (std::find(all.begin(), all.end(), w) == all.end()) all.push_back(w);
    }
    std::string out;
    for (const auto& w : all) {
        std::string in;
        std::size_t count = 0;
        for (std::size_t i = 0; i < words.size(); ++i)
            if (std::find(words[i].begin(), words[i].end(), w) != words[i].end())
                in += (count++ ? "," : "") + std::string("[") + std::to_string(i + 1) + "]";
        if (count < words.size()) out += (out.empty() ? "" : ", ") + w + " only in " + in;
    }
    return out;
}

FieldKind context_field_kind(const std::string& field) {
    static const std::set<std::string> machine = {"cpu_model", "sockets", "numa_node_count",
                                                  "cores",     "pus",     "memory_bytes"};
    static const std::set<std::string> setting = {"compiler",        "compiler_flags",        "build_type",
                                                  "instruction_set", "transparent_hugepages", "hugepages"};
    if (machine.count(field)) return FieldKind::machine;
    if (setting.count(field)) return FieldKind::setting;
    return FieldKind::informational;
}

}  // namespace suite
