#pragma once
// --format's choices, one table: the plan parses --format through it and keeps the behaviour, the
// programs decide from that behaviour what they write, and messages and --help list its names.
#include <string>

#include "harness/common/choice_table.hpp"

namespace suite {

enum class OutputFormat { table, json, csv, gbench };

struct OutputFormatBehaviour {
    OutputFormat format = OutputFormat::table;
    bool to_file = true;     // can be written by --out (the console table cannot)
    std::string out_suffix;  // an --out name ending so chooses this format when --format is not given
};

// table, json, csv, gbench.
const ChoiceTable<OutputFormatBehaviour>& output_formats();

// The name of `f` in output_formats(), e.g. for a message or a dry run's summary.
const std::string& format_name(OutputFormat f);

// The formats --out can write, the last two joined by "or": "json, csv or gbench".
std::string file_format_names();

}  // namespace suite
