#pragma once
// A bad mesh file or mesh specification: a usage error (exit status 2) whose message starts
// with the file name and line number, "PATH:LINE: what is wrong; what is accepted".
#include <string>

#include "harness/common/units.hpp"

namespace suite::mesh {

struct MeshError : UsageError {
    MeshError(const std::string& file, std::size_t line, const std::string& what)
        : UsageError(message(file, line, what)) {}

private:
    static std::string message(const std::string& file, std::size_t line, const std::string& what) {
        std::string m = file;
        if (line) m.append(":").append(std::to_string(line));
        return m.append(": ").append(what);
    }
};

}  // namespace suite::mesh
