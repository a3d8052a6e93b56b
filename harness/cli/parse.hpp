#pragma once
// One way for every subcommand to parse its options: CLI11 errors propagate to main() (exit 2),
// --help prints the subcommand's help and asks the caller to stop with exit status 0.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace suite {

// Parses `args` (without the program and command) into `app`, named `name` in messages;
// returns false after printing the help for --help.
inline bool parse_command_line(CLI::App& app, const char* name, const std::vector<std::string>& args) {
    std::vector<const char*> argv{name};
    for (const auto& a : args) argv.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return false;
    }
    return true;
}

}  // namespace suite
