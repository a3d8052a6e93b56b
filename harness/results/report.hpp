#pragma once
// Reporters render Records; they compute nothing. Files are replaced atomically
// (write_atomically), so a reader never sees half a file.
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/measure/result.hpp"

namespace suite {

// The result files this suite writes (results/schema/v2.json); result_file.hpp says which it reads.
constexpr int schema_version = 2;

nlohmann::json to_json(const Record& r);
nlohmann::json to_json(const Stability& s);
// Under the table: how many points were flagged unstable and why (the reasons' kinds, counted);
// "" when none was.
std::string stability_summary(const std::vector<Record>& records);
std::string csv_header(const Record* first = nullptr);  // first: where counter and energy columns come from
// `context`: the run's context, whose host, CPU model, date and git revision each row repeats.
std::string to_csv_row(const Record& r, const nlohmann::json& context = {});
// A record's parameters as the CSV column holds them: "delta=0.05;tol=1e-08" ("" for none).
std::string params_text(const Params& params);

// The console table: a header, then one row per record as it arrives, with the kernel's facts
// (Record::facts) on an indented line under it when it reported any.
std::string table_header();
std::string table_row(std::size_t index, std::size_t total, const Record& r);

enum class FileFormat { json, csv, gbench };

// A run's results in memory: the context and the records measured so far.
struct ResultDocument {
    nlohmann::json context;
    std::vector<Record> records;
    // JSON: {schema_version, complete, context, results}; CSV: a header and one row per record;
    // gbench: Google Benchmark's JSON (render_gbench).
    std::string render(FileFormat format, bool complete) const;
};

// Google Benchmark's JSON format ({context, benchmarks[]}, as --benchmark_format=json writes it),
// so that tools reading that format take a suite run: each counted sample is an "iteration"
// run of `batch` calls, followed by the mean, median, stddev and cv aggregates. Defined in
// report_gbench.cpp.
std::string render_gbench(const nlohmann::json& context, const std::vector<Record>& records, bool complete);
// The benchmark name shared by --format=gbench and suite-gbench: kernel/pattern/size/threads,
// with Google Benchmark's "/real_time" suffix (the time is the wall clock of the whole team).
std::string gbench_name(const std::string& kernel_name, const std::string& access, const std::string& size,
                        int threads);

}  // namespace suite
