#include "harness/results/dashboard.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "harness/common/output_file.hpp"
#include "harness/common/units.hpp"
#include "harness/results/dashboard_page.hpp"
#include "harness/results/history_band.hpp"
#include "harness/results/history_pool.hpp"

namespace suite {

// Named, not anonymous: the harness compiles one unit a folder, and these names must not meet
// another file's helpers there.
namespace dashboard_detail {

std::string html_text(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

// JSON that may sit inside <script>: '<' only occurs inside strings there, and as \u003c no
// label can close the script element ("</script>") or open a comment ("<!--").
std::string script_safe(const std::string& json) {
    std::string out;
    out.reserve(json.size());
    for (char c : json) {
        if (c == '<')
            out += "\\u003c";
        else
            out += c;
    }
    return out;
}

// The window `history check` takes of a series (window_baseline): its last `window` stable
// entries, or its last entries flagged or not where fewer than min_runs are stable. Oldest first.
std::vector<std::size_t> gate_window(const Series& s, std::size_t window, std::size_t min_runs) {
    std::vector<std::size_t> stable, any;
    for (std::size_t i = s.entries.size(); i-- > 0;) {
        if (any.size() < window) any.push_back(i);
        if (!s.entries[i].unstable && stable.size() < window) stable.push_back(i);
    }
    std::vector<std::size_t>& out = stable.size() < min_runs && any.size() > stable.size() ? any : stable;
    std::reverse(out.begin(), out.end());
    return out;
}

// The band `history check` would gate this series' next run against (history_band.hpp), fitted
// as the gate fits it, its spread pooled with the machine's and the machine's jumps taken in
// (history_pool.hpp). "first" is the index of the
// window's oldest entry, where the page starts to draw the band. A band too wide to tell a 2x
// change from noise is not drawn: null, and the reason in "band_reason", as without one.
void add_band(nlohmann::json& out, const RunBand& band, std::size_t first, double alpha) {
    const std::size_t min_runs = HistoryRule{}.min_runs;
    if (band.usable() && band.half_width < std::log(2.0)) {
        out["band"] = {{"centre", band.centre}, {"low", band.low},   {"high", band.high}, {"spread", band.spread},
                       {"df", band.df},         {"runs", band.runs}, {"first", first},    {"alpha", alpha}};
        return;
    }
    out["band"] = nullptr;
    out["band_reason"] = band.usable() ? "too wide to tell a 2x change from noise (x" +
                                             format_significant(std::exp(band.half_width), 3) + " either way over " +
                                             std::to_string(band.runs) + " runs): not drawn"
                                       : no_band_reason(band, min_runs);
}

nlohmann::json series_json(const Series& s, const RunBand& band, std::size_t first, double alpha) {
    nlohmann::json entries = nlohmann::json::array(), steps = nlohmann::json::array();
    for (const auto& e : s.entries)
        entries.push_back({{"commit", e.commit},
                           {"branch", e.branch},
                           {"date", e.date},
                           {"run_id", e.run_id},
                           {"median", e.median},
                           {"noise", e.noise},
                           {"samples", e.samples.size()},
                           {"unstable", e.unstable}});
    for (const auto& st : s.steps)
        steps.push_back({{"index", st.index},
                         {"commit", st.commit},
                         {"before", st.before},
                         {"after", st.after},
                         {"change", st.change},
                         {"p", st.p},
                         {"worse", st.worse}});
    nlohmann::json out = {{"machine", s.machine},
                          {"fingerprint", s.fingerprint},
                          {"context", s.context_class},
                          {"label", s.key.label()},
                          {"kernel", s.key.kernel},
                          {"figure", s.figure},
                          {"unit", s.unit},
                          {"direction", s.direction == Direction::higher_is_better ? "higher" : "lower"},
                          {"entries", std::move(entries)},
                          {"steps", std::move(steps)}};
    add_band(out, band, first, alpha);
    return out;
}

std::string utc_now() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
    return buf;
}

// "12 series on 2 machines, 40 runs of 31 commits, 3 steps (2 worse)".
std::string summary_line(const std::vector<Series>& series) {
    std::set<std::string> machines, commits;
    std::set<std::int64_t> runs;
    std::size_t steps = 0, worse = 0;
    for (const auto& s : series) {
        machines.insert(s.fingerprint);
        for (const auto& e : s.entries) {
            runs.insert(e.run_id);
            commits.insert(e.commit);
        }
        steps += s.steps.size();
        for (const auto& st : s.steps) worse += st.worse ? 1 : 0;
    }
    auto count = [](std::size_t n, const char* one, const char* many) {
        return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    return count(series.size(), "series", "series") + " on " + count(machines.size(), "machine", "machines") + ", " +
           count(runs.size(), "run", "runs") + " of " + count(commits.size(), "commit", "commits") + ", " +
           count(steps, "step", "steps") + " (" + std::to_string(worse) + " worse)";
}

std::string read_chart_library(const std::string& path) {
    const std::string install =
        "; install Debian's libjs-chart.js (apt-get install libjs-chart.js, or scripts/install-deps.sh run)";
    struct stat st {};
    if (stat(path.c_str(), &st) != 0)
        throw UsageError("the history page needs Chart.js, not found at " + path + install);
    if (!S_ISREG(st.st_mode))
        throw UsageError("the history page needs Chart.js, and " + path + " is not a file" + install);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in || text.str().empty())
        throw UsageError("the history page needs Chart.js, and " + path + " cannot be read (" + std::strerror(errno) +
                         ")" + install);
    return text.str();
}

std::string page_html(const std::vector<Series>& series, const DashboardOptions& options) {
    nlohmann::json doc = {{"title", options.title}, {"window", options.window}, {"series", nlohmann::json::array()}};
    // The gate's share of alpha (band_alpha, history_band.hpp) among the figures a run gates, here
    // the series of its machine and build (fingerprint and context class) that the page shows
    // (below). A count that is 0 in every run (a counter that never fired) is listed once, not charted.
    std::vector<const Series*> charted;
    doc["all_zero"] = nlohmann::json::array();
    for (const auto& s : series) {
        const bool zero = !s.entries.empty() && std::all_of(s.entries.begin(), s.entries.end(),
                                                            [](const SeriesEntry& e) { return e.median == 0; });
        if (zero)
            doc["all_zero"].push_back(
                {{"machine", s.machine}, {"label", s.key.label()}, {"figure", s.figure}, {"unit", s.unit}});
        else
            charted.push_back(&s);
    }
    // The spreads of one machine, build and figure pooled as history check pools them.
    const std::size_t min_runs = HistoryRule{}.min_runs;
    std::map<std::string, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < charted.size(); ++i)
        groups[charted[i]->fingerprint + " " + charted[i]->context_class + " " + charted[i]->figure + " " +
               charted[i]->unit]
            .push_back(i);
    // Each series' window: its entries' indices, and their medians and runs.
    std::vector<std::vector<std::size_t>> windows(charted.size());
    std::vector<SeriesWindow> series_windows(charted.size());
    for (std::size_t i = 0; i < charted.size(); ++i) {
        windows[i] = gate_window(*charted[i], options.window, min_runs);
        for (std::size_t k : windows[i]) {
            series_windows[i].medians.push_back(charted[i]->entries[k].median);
            series_windows[i].runs.push_back(charted[i]->entries[k].run_id);
        }
    }
    std::vector<PooledSpread> pooled(charted.size());
    for (const auto& [name, members] : groups) {
        std::vector<SeriesWindow> w;
        for (std::size_t i : members) w.push_back(series_windows[i]);
        const MachineNoise noise = pool_spreads(w, min_runs);
        for (std::size_t m = 0; m < members.size(); ++m) pooled[members[m]] = noise.series[m];
    }
    // The family, as history check counts it for the next run: the figures with a window long
    // enough for a band, as the independent tests they amount to (effective_figures).
    std::map<std::pair<std::string, std::string>, std::map<PointKey, std::vector<SeriesWindow>>> gated;
    for (std::size_t i = 0; i < charted.size(); ++i)
        if (windows[i].size() >= min_runs)
            gated[{charted[i]->fingerprint, charted[i]->context_class}][charted[i]->key].push_back(series_windows[i]);
    std::map<std::pair<std::string, std::string>, double> family;
    for (auto& [machine, points] : gated) {
        std::vector<std::vector<SeriesWindow>> w;
        for (auto& [key, figures] : points) w.push_back(std::move(figures));
        family[machine] = effective_figures(w, min_runs);
    }
    for (std::size_t i = 0; i < charted.size(); ++i) {
        const Series& s = *charted[i];
        const double alpha = band_alpha(options.alpha, family[{s.fingerprint, s.context_class}]);
        const RunBand band = fit_band(series_windows[i].medians, {}, alpha, min_runs, &pooled[i]);
        doc["series"].push_back(
            series_json(s, band, windows[i].empty() ? s.entries.size() : windows[i].front(), alpha));
    }
    // A host name or label with bytes that are not UTF-8 must not cost the whole page.
    const std::string data = script_safe(doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    const std::string title = html_text(options.title);

    std::string html =
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        "<link rel=\"icon\" href=\"data:,\">\n"
        // Nothing but this page's inline code and the chart library beside it: no network.
        "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'self' file: "
        "'unsafe-inline'; "
        "style-src 'unsafe-inline'; img-src data:\">\n"
        "<title>" +
        title + "</title>\n<style>\n" + page_style +
        "</style>\n</head>\n<body>\n"
        "<header class=\"top\">\n<h1>" +
        title +
        "</h1>\n"
        "<p class=\"summary\">Generated " +
        utc_now() + " &middot; " + html_text(summary_line(series)) + "</p>\n";
    if (series.empty()) {
        html +=
            "</header>\n<main>\n<p class=\"empty\" id=\"empty\">The history is empty: no run has been recorded yet, so "
            "there is no "
            "trend to draw.</p>\n</main>\n";
    } else {
        html += page_controls;
        html += "</header>\n<p class=\"failure\" id=\"failure\" hidden></p>\n<main id=\"charts\"></main>\n";
    }
    html += "<script type=\"application/json\" id=\"history-data\">" + data + "</script>\n";
    if (!series.empty())
        html += "<script src=\"chart.min.js\"></script>\n<script>\n" + std::string(page_script) + "</script>\n";
    html += "</body>\n</html>\n";
    return html;
}

}  // namespace dashboard_detail

std::string write_dashboard(const std::vector<Series>& series, const std::string& out_dir,
                            const DashboardOptions& options) {
    // Everything that can fail for want of the library fails before the directory is created.
    const std::string library = dashboard_detail::read_chart_library(options.chart_js);
    const std::string page = dashboard_detail::page_html(series, options);
    // The page's two files, replaced by every `history html` into the same directory; what else
    // the directory holds (a site's CNAME) is left alone.
    OutputDir out = OutputDir::claim(
        out_dir,
        DirPolicy{.option = "--out", .command = "suite history html", .fixed_files = {"chart.min.js", "index.html"}});
    out.write("chart.min.js", library);
    out.write("index.html", page);
    std::string dir = out_dir;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return dir + "/index.html";
}

}  // namespace suite
