#pragma once
// Checked access to the JSON of one result file, for the reader (result_file.cpp) and its MPI
// part (result_file_mpi.cpp): every failure is an InputError that names the file and the field.
// Internal to harness/results; the tools see only result_file.hpp.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "harness/results/result_file.hpp"

namespace suite {

struct FieldReader {
    std::string file;

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw InputError(file + ": " + where + ": " + what + " (is it a result file written by suite?)");
    }
    const nlohmann::json& field(const nlohmann::json& obj, const char* key, const std::string& where) const {
        if (!obj.is_object()) fail(where, "expected an object");
        auto it = obj.find(key);
        if (it == obj.end()) fail(where + "." + key, "missing");
        return *it;
    }
    std::string string(const nlohmann::json& obj, const char* key, const std::string& where,
                       bool may_be_empty = false) const {
        const nlohmann::json& v = field(obj, key, where);
        if (!v.is_string()) fail(where + "." + key, "expected a string");
        if (!may_be_empty && v.get_ref<const std::string&>().empty()) fail(where + "." + key, "empty");
        return v.get<std::string>();
    }
    double number(const nlohmann::json& v, const std::string& where) const {
        if (!v.is_number()) fail(where, "expected a number");
        const double x = v.get<double>();
        if (!std::isfinite(x) || x < 0) fail(where, "expected a finite non-negative number");
        return x;
    }
    double number(const nlohmann::json& obj, const char* key, const std::string& where) const {
        return number(field(obj, key, where), where + "." + key);
    }
    std::uint64_t count(const nlohmann::json& obj, const char* key, const std::string& where,
                        std::uint64_t least) const {
        return count(field(obj, key, where), where + "." + key, least);
    }
    std::uint64_t count(const nlohmann::json& v, const std::string& where, std::uint64_t least) const {
        if (!v.is_number_integer() || (!v.is_number_unsigned() && v.get<std::int64_t>() < 0))
            fail(where, "expected a non-negative integer");
        const std::uint64_t x = v.get<std::uint64_t>();
        if (x < least) fail(where, "expected at least " + std::to_string(least));
        return x;
    }
    // A count that must also fit an int (ranks, hosts, CPUs): at most 2^30.
    int small_count(const nlohmann::json& obj, const char* key, const std::string& where, std::uint64_t least) const {
        const std::uint64_t x = count(obj, key, where, least);
        if (x > (1u << 30)) fail(where + "." + key, "expected at most " + std::to_string(1u << 30));
        return static_cast<int>(x);
    }
    bool boolean(const nlohmann::json& obj, const char* key, const std::string& where) const {
        const nlohmann::json& v = field(obj, key, where);
        if (!v.is_boolean()) fail(where + "." + key, "expected true or false");
        return v.get<bool>();
    }
};

// result_file_mpi.cpp: the record's `mpi` (absent: a run of one process), checked against the
// file's context.mpi (`job`, empty for a plain file); and context.mpi itself.
RankOrigin read_rank_origin(const FieldReader& r, const nlohmann::json& rec, const std::string& where,
                            const std::optional<LoadedMpiJob>& job);
std::optional<LoadedMpiJob> read_mpi_job(const FieldReader& r, const nlohmann::json& context);

}  // namespace suite
