#pragma once
// What the `suite history` subcommands share: the database and filter options, and the series
// they select. history.cpp has add, list, steps and html; history_check.cpp has check and noise.
#include <cctype>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/parse.hpp"
#include "harness/results/history.hpp"
#include "harness/results/steps.hpp"

namespace suite {
namespace history_command {

struct HistoryArgs {
    std::string db = "results/history.sqlite";
    unsigned wait_s = 10;
    std::string kernel, machine;
};

inline void add_db_options(CLI::App& app, HistoryArgs& a) {
    app.add_option("--db", a.db, "the history database (default results/history.sqlite)");
    add_whole_option(app, "--wait", a.wait_s, 0, 3600,
                     "seconds to wait while another process holds the database (default 10)");
}

inline void add_filter_options(CLI::App& app, HistoryArgs& a) {
    app.add_option("--kernel", a.kernel, "only this kernel's series");
    app.add_option("--machine", a.machine,
                   "only this machine: a part of its label (host, CPU) or the start of its fingerprint");
}

// The one rule for a commit named on the command line (--commit, --base-commit): a hash of 7 to
// 40 hex digits, either case, kept in lower case as git writes it. Anything else (a branch name,
// `ab`, text with `;` or a newline) would be stored, or matched, as if it were one.
inline std::string commit_option(const std::string& text, const std::string& option) {
    if (text.empty()) return text;
    const bool hex = text.find_first_not_of("0123456789abcdefABCDEF") == std::string::npos;
    if (!hex || text.size() < 7 || text.size() > 40) {
        std::string shown;
        for (char c : text) shown += (c == '\n' ? std::string("\\n") : std::string(1, c));
        throw UsageError(option + "='" + shown + "': give a commit's hash, 7 to 40 hex digits, e.g. " + option +
                         "=\"$(git rev-parse HEAD)\"");
    }
    std::string lower = text;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower;
}

inline HistoryOptions history_options(const HistoryArgs& a) {
    HistoryOptions o;
    o.wait_ms = static_cast<int>(a.wait_s * 1000);
    return o;
}

// The series --kernel and --machine ask for, with their steps; a filter that matches nothing is
// a usage error that names what there is.
inline std::vector<Series> filtered_series(const History& h, const HistoryArgs& a) {
    SeriesFilter f;
    if (!a.machine.empty()) {
        const auto found = h.machines_matching(a.machine);
        if (found.empty()) {
            std::string known;
            for (const auto& [fp, label] : h.machines_matching(""))
                known += (known.empty() ? "" : "; ") + fp + " " + label;
            throw UsageError("no machine in " + h.path() + " matches --machine '" + a.machine +
                             "'; its machines: " + known);
        }
        for (const auto& m : found) f.fingerprints.push_back(m.first);
    }
    std::vector<Series> all = h.series(f);
    if (a.kernel.empty()) return all;
    std::vector<Series> out;
    std::set<std::string> kernels;
    for (auto& s : all) {
        kernels.insert(s.key.kernel);
        if (s.key.kernel == a.kernel) out.push_back(std::move(s));
    }
    if (out.empty())
        require_known({a.kernel}, std::vector<std::string>(kernels.begin(), kernels.end()), "kernel in this history");
    return out;
}

// filtered_series, each with its steps.
inline std::vector<Series> series_with_steps(const History& h, const HistoryArgs& a) {
    std::vector<Series> series = filtered_series(h, a);
    for (auto& s : series) s.steps = detect_steps(s);
    return series;
}

inline std::string signed_percent(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%+.1f%%", x * 100);
    return buf;
}

int history_check(const std::vector<std::string>& args);
int history_noise(const std::vector<std::string>& args);

}  // namespace history_command
}  // namespace suite
