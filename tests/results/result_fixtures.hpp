#pragma once
// The committed fixture results (tests/fixtures/results/) and the helpers that read them and
// write changed copies of them, for the tests of compare and check.
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace suite::test {

inline std::string fixture(const std::string& name) {
    return std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/" + name;
}

inline nlohmann::json load(const std::string& path) { return nlohmann::json::parse(slurp(path)); }

inline void save(const nlohmann::json& doc, const std::string& path) { std::ofstream(path) << doc.dump(1); }

}  // namespace suite::test
