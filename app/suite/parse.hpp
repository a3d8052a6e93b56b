#pragma once
// One way for every subcommand to parse its options: CLI11 errors propagate to main() (exit 2),
// --help prints the subcommand's help and asks the caller to stop with exit status 0. An option
// given an empty value is refused here, once for every command; whole numbers go through
// parse_whole (harness/common/units.hpp).
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include <algorithm>

#include <CLI/CLI.hpp>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/units.hpp"

namespace suite {

// An option of `app` given an empty value: "--out=" (which CLI11 would let take the next
// argument as its value) or "--out ''". Throws UsageError naming the option and what it takes.
inline void refuse_empty_values(const CLI::App& app, const std::vector<std::string>& args) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--") return;  // what follows is positional
        if (a.size() < 2 || a[0] != '-') continue;
        const auto eq = a.find('=');
        const std::string name = a.substr(0, eq);
        const CLI::Option* opt = app.get_option_no_throw(name);
        if (!opt) continue;  // unknown: CLI11 says so
        const bool flag = opt->get_expected_max() == 0;
        const std::string takes =
            flag ? name + " is a flag and takes no value" : "give one (" + name + ": " + opt->get_description() + ")";
        if (eq != std::string::npos && eq + 1 == a.size()) throw UsageError(name + "= has an empty value; " + takes);
        if (eq == std::string::npos && !flag && i + 1 < args.size() && args[i + 1].empty())
            throw UsageError(name + " is given an empty value ''; " + takes);
    }
}

// Parses `args` (without the program and command) into `app`, named `name` in messages;
// returns false after printing the help for --help.
inline bool parse_command_line(CLI::App& app, const char* name, const std::vector<std::string>& args) {
    refuse_empty_values(app, args);
    std::vector<const char*> argv{name};
    for (const auto& a : args) argv.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return false;
    } catch (const CLI::ExtrasError&) {
        // An option typed wrong: name the nearest one this command has.
        for (const auto& a : app.remaining()) {
            if (a.rfind("--", 0) != 0) continue;
            const std::string given = a.substr(0, a.find('='));
            std::vector<std::string> known;  // without the dashes, which would make every name look close
            for (const CLI::Option* o : app.get_options())
                for (const auto& n : o->get_lnames()) known.push_back(n);
            const std::string hint = nearest(given.substr(2), known);
            throw UsageError("unknown option '" + given + "'" +
                             (hint.empty() ? "" : " (did you mean '--" + hint + "'?)") + "; see ./" +
                             std::string(name) + " --help");
        }
        throw;
    }
    return true;
}

// An option whose value is a whole number from lo to hi, e.g. --reps: a sign, a fraction, an
// overflow or a value out of range is one message naming the value and the range.
template <class T>
CLI::Option* add_whole_option(CLI::App& app, const std::string& names, T& target, std::uint64_t lo, std::uint64_t hi,
                              const std::string& help) {
    const std::string option = names.substr(0, names.find(','));  // "--threads,-t" -> "--threads"
    return app
        .add_option_function<std::string>(
            names,
            [&target, option, lo, hi](const std::string& text) {
                target = static_cast<T>(parse_whole(text, option, lo, hi));
            },
            help)
        ->type_name("UINT");
}

// --seed of every command that has one: parse_seed, 0 to 2^64-1 exactly as typed.
inline CLI::Option* add_seed_option(CLI::App& app, std::uint64_t& seed, const std::string& help) {
    return app
        .add_option_function<std::string>(
            "--seed", [&seed](const std::string& text) { seed = parse_seed(text); }, help)
        ->type_name("UINT");
}

// Throws a UsageError "unknown WHAT 'name' (did you mean 'x'?); accepted: a, b, c" for the first of
// `names` that is not in `accepted`.
inline void require_known(const std::vector<std::string>& names, const std::vector<std::string>& accepted,
                          std::string_view what) {
    for (const auto& name : names) {
        if (std::find(accepted.begin(), accepted.end(), name) != accepted.end()) continue;
        const std::string hint = nearest(name, accepted);
        std::string list;
        for (const auto& a : accepted) list += (list.empty() ? "" : ", ") + a;
        throw UsageError("unknown " + std::string(what) + " '" + name + "'" +
                         (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; accepted: " + list);
    }
}

}  // namespace suite
