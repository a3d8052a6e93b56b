#include "harness/results/compare_context.hpp"

#include "harness/results/context_fields.hpp"
#include "harness/results/text_table.hpp"

namespace suite {

std::string render_context_differences(const std::vector<ResultFile>& files, bool markdown, bool force) {
    std::vector<const ResultFile*> ptrs;
    for (const auto& f : files) ptrs.push_back(&f);
    const auto diffs = context_differences(ptrs);
    std::string out = markdown ? "\n### Context differences\n\n" : "\nContext differences that matter:\n";
    if (diffs.empty())
        return out +
               "none: the same CPU, sockets, NUMA nodes, caches, memory, compiler and flags, build type, instruction "
               "set, THP, huge pages asked and governor\n";
    TextTable t{{"field", "kind"}, {}, {}};
    for (std::size_t f = 0; f < files.size(); ++f) t.header.push_back("[" + std::to_string(f + 1) + "]");
    std::string machine, setting;
    for (const auto& [field, values] : diffs) {
        const FieldKind kind = context_field_kind(field, ptrs);
        std::vector<std::string> row{field, kind == FieldKind::machine   ? "machine"
                                            : kind == FieldKind::setting ? "build/setting"
                                                                         : "info"};
        row.insert(row.end(), values.begin(), values.end());
        t.rows.push_back(row);
        if (kind == FieldKind::machine) machine += (machine.empty() ? "" : ", ") + field;
        if (kind != FieldKind::setting) continue;
        // Named as the user would change it: the flags that differ, or each file's value.
        std::string what = field == "compiler_flags" ? flags_difference(ptrs) : "";
        if (what.empty()) {
            for (std::size_t i = 0; i < values.size(); ++i) what += (i ? " | " : "") + values[i];
        }
        setting += (setting.empty() ? "" : "; ") + field + ": " + what;
    }
    // One comparison answers one question: these machines, or these settings on one machine.
    // When both changed, a ratio mixes two causes that nothing here can separate.
    if (!machine.empty() && !setting.empty() && !force)
        throw InputError("the files differ both as machines (" + machine + ") and in settings the user chose (" +
                         setting +
                         "), so a ratio cannot say which made the difference; build and run both alike, or pass "
                         "--force");
    return out + (markdown ? t.render_markdown() : t.render_text());
}

}  // namespace suite
