#include "harness/measure/output_formats.hpp"

#include <stdexcept>
#include <vector>

#include "harness/common/text.hpp"

namespace suite {

const ChoiceTable<OutputFormatBehaviour>& output_formats() {
    static const ChoiceTable<OutputFormatBehaviour> table{
        "--format",
        {{"table", "a table on the console, the default without --out", {OutputFormat::table, false, ""}},
         {"json", "suite's JSON, the default with --out", {OutputFormat::json, true, ""}},
         {"csv", "one line a record, the default for --out=*.csv", {OutputFormat::csv, true, ".csv"}},
         {"gbench", "Google Benchmark's JSON", {OutputFormat::gbench, true, ""}}}};
    return table;
}

const std::string& format_name(OutputFormat f) {
    for (const auto& c : output_formats().all())
        if (c.what.format == f) return c.name;
    throw std::logic_error("--format: a format without a name");
}

std::string file_format_names() {
    std::vector<std::string> names;
    for (const auto& c : output_formats().all())
        if (c.what.to_file) names.push_back(c.name);
    const std::string last = names.back();
    names.pop_back();
    return names.empty() ? last : join(names, ", ") + " or " + last;
}

}  // namespace suite
