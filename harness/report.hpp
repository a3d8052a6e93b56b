#pragma once
// Reporters render Records; they compute nothing. JSON and CSV go to files through
// ResultFile, which replaces the target atomically so a reader never sees half a file.
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/result.hpp"

namespace suite {

constexpr int schema_version = 1;

nlohmann::json to_json(const Record& r);
std::string csv_header();
std::string to_csv_row(const Record& r);

// The console table: a header, then one row per record as it arrives.
std::string table_header();
std::string table_row(std::size_t index, std::size_t total, const Record& r);

enum class FileFormat { json, csv };

// A result file that is valid at every moment: each save() writes a temporary file beside the
// target, flushes it to disk and renames it over the target. Nothing is created until the
// first save(); a failed save leaves the previous file as it was and throws std::runtime_error.
class ResultFile {
public:
    ResultFile(std::string path, FileFormat format, nlohmann::json context);
    void add(const Record& r);
    void save(bool complete);
    std::size_t size() const { return records_.size(); }
    const std::string& path() const { return path_; }
    // The whole document as it would be saved.
    std::string render(bool complete) const;

private:
    std::string path_;
    FileFormat format_;
    nlohmann::json context_;
    std::vector<Record> records_;
};

// Writes `content` to `path` atomically (temporary file + fsync + rename).
void write_atomically(const std::string& path, const std::string& content);

}  // namespace suite
