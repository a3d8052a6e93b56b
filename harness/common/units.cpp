#include "harness/common/units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

namespace suite {

std::vector<std::string> split(std::string_view text, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        auto pos = text.find(sep, start);
        out.emplace_back(text.substr(start, pos == std::string_view::npos ? pos : pos - start));
        if (pos == std::string_view::npos) break;
        start = pos + 1;
    }
    return out;
}

std::string join(const std::vector<std::string>& parts, std::string_view sep) {
    std::string out;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (i) out += sep;
        out += parts[i];
    }
    return out;
}

namespace {

std::string quoted(std::string_view s) { return "'" + std::string(s) + "'"; }

// Parses a non-negative decimal number (digits, optional fraction) at the start of `s`.
bool parse_number(std::string_view s, double& value, std::size_t& used) {
    std::size_t i = 0;
    bool digits = false;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; digits = true; }
    if (i < s.size() && s[i] == '.') {
        ++i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; digits = true; }
    }
    if (!digits) return false;
    value = std::stod(std::string(s.substr(0, i)));
    used = i;
    return true;
}

long long parse_int(std::string_view s, std::string_view what) {
    if (s.empty() || !std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
        throw UsageError("invalid " + std::string(what) + " " + quoted(s) + ": expected a non-negative integer");
    if (s.size() > 9) throw UsageError(std::string(what) + " " + quoted(s) + " is too large");
    return std::stoll(std::string(s));
}

}  // namespace

std::uint64_t parse_bytes(std::string_view text) {
    const std::string accepted = "a size such as 4096, 32KiB, 64MiB, 1.5GiB or 100MB";
    if (!text.empty() && text[0] == '-')
        throw UsageError("invalid size " + quoted(text) + ": sizes must be positive; expected " + accepted);
    double value = 0;
    std::size_t used = 0;
    if (!parse_number(text, value, used)) throw UsageError("invalid size " + quoted(text) + ": expected " + accepted);
    std::string unit(text.substr(used));
    static const std::pair<const char*, double> units[] = {
        {"", 1.0},          {"B", 1.0},
        {"K", 1024.0},      {"KiB", 1024.0},      {"k", 1024.0},   {"kB", 1e3},  {"KB", 1e3},
        {"M", 1048576.0},   {"MiB", 1048576.0},   {"MB", 1e6},
        {"G", 1073741824.0}, {"GiB", 1073741824.0}, {"GB", 1e9},
        {"T", 1099511627776.0}, {"TiB", 1099511627776.0}, {"TB", 1e12},
    };
    for (const auto& [name, factor] : units) {
        if (unit != name) continue;
        double bytes = value * factor;
        if (bytes < 1.0) throw UsageError("invalid size " + quoted(text) + ": sizes must be at least 1 byte");
        if (bytes > 1.0e18) throw UsageError("invalid size " + quoted(text) + ": too large");
        return static_cast<std::uint64_t>(std::llround(bytes));
    }
    throw UsageError("invalid size " + quoted(text) + ": unknown unit " + quoted(unit) +
                     "; accepted units are B, KiB, MiB, GiB, TiB (powers of 2) and kB, MB, GB, TB (powers of 10)");
}

std::vector<std::uint64_t> parse_size_list(std::string_view text) {
    if (text.find(':') == std::string_view::npos) {
        std::vector<std::uint64_t> out;
        for (const auto& part : split(text, ',')) out.push_back(parse_bytes(part));
        return out;
    }
    auto parts = split(text, ':');
    if (parts.size() > 3)
        throw UsageError("invalid size sweep " + quoted(text) + ": expected FROM:TO or FROM:TO:xFACTOR, e.g. 16KiB:1GiB:x2");
    std::uint64_t from = parse_bytes(parts[0]);
    std::uint64_t to = parse_bytes(parts[1]);
    double factor = 2.0;
    if (parts.size() == 3) {
        std::string_view f = parts[2];
        if (!f.empty() && (f[0] == 'x' || f[0] == '*')) f.remove_prefix(1);
        std::size_t used = 0;
        if (!parse_number(f, factor, used) || used != f.size() || factor <= 1.0)
            throw UsageError("invalid size sweep step " + quoted(parts[2]) + ": expected a factor above 1, e.g. x2 or x1.5");
    }
    if (from > to) throw UsageError("invalid size sweep " + quoted(text) + ": the first size is larger than the last");
    std::vector<std::uint64_t> out;
    for (double s = static_cast<double>(from); s <= static_cast<double>(to) * (1 + 1e-9); s *= factor) {
        auto v = static_cast<std::uint64_t>(std::llround(s));
        if (out.empty() || v != out.back()) out.push_back(v);
        if (out.size() > 1000) throw UsageError("size sweep " + quoted(text) + " has more than 1000 points");
    }
    return out;
}

std::vector<int> parse_thread_list(std::string_view text, int max_threads) {
    const std::string accepted = "a list such as 1,2,4, a range 1-8 or 1-8:2, or 'all'";
    std::vector<int> out;
    if (text == "all") {
        out.push_back(max_threads);
        return out;
    }
    if (text.empty()) throw UsageError("empty thread list: expected " + accepted);
    for (const auto& part : split(text, ',')) {
        if (part == "all") { out.push_back(max_threads); continue; }
        auto dash = part.find('-');
        if (dash == std::string::npos) {
            out.push_back(static_cast<int>(parse_int(part, "thread count")));
        } else {
            auto colon = part.find(':', dash);
            long long lo = parse_int(std::string_view(part).substr(0, dash), "thread count");
            long long hi = parse_int(std::string_view(part).substr(dash + 1, colon == std::string::npos ? std::string::npos : colon - dash - 1), "thread count");
            long long step = colon == std::string::npos ? 1 : parse_int(std::string_view(part).substr(colon + 1), "thread step");
            if (step < 1 || lo > hi) throw UsageError("invalid thread range '" + part + "': expected " + accepted);
            if (hi > max_threads)  // checked before expanding, so a huge range costs nothing
                throw UsageError("thread count " + std::to_string(hi) + " is more than the " + std::to_string(max_threads) +
                                 " processing units (PUs) available here; use at most " + std::to_string(max_threads) + " or 'all'");
            for (long long t = lo; t <= hi; t += step) out.push_back(static_cast<int>(t));
        }
    }
    for (int t : out) {
        if (t < 1) throw UsageError("invalid thread count 0 in '" + std::string(text) + "': at least 1 thread is needed");
        if (t > max_threads)
            throw UsageError("thread count " + std::to_string(t) + " is more than the " + std::to_string(max_threads) +
                             " processing units (PUs) available here; use at most " + std::to_string(max_threads) + " or 'all'");
    }
    return out;
}

std::vector<int> parse_cpu_list(std::string_view text) {
    std::vector<int> out;
    std::set<int> seen;
    for (const auto& part : split(text, ',')) {
        auto dash = part.find('-');
        long long lo = parse_int(std::string_view(part).substr(0, dash), "CPU number");
        long long hi = dash == std::string::npos ? lo : parse_int(std::string_view(part).substr(dash + 1), "CPU number");
        if (lo > hi) throw UsageError("invalid CPU range '" + part + "': expected e.g. 0-3");
        if (hi - lo > 1000000) throw UsageError("CPU range '" + part + "' is implausibly large");  // before expanding it
        for (long long c = lo; c <= hi; ++c) {
            if (!seen.insert(static_cast<int>(c)).second)
                throw UsageError("CPU " + std::to_string(c) + " appears twice in --pin list '" + std::string(text) + "'");
            out.push_back(static_cast<int>(c));
        }
    }
    return out;
}

std::string format_bytes(std::uint64_t bytes) {
    static const char* names[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = static_cast<double>(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 4) { v /= 1024.0; ++u; }
    // Whole numbers as they are; otherwise up to 3 significant digits, never in e-notation.
    char buf[32];
    const int decimals = std::fabs(v - std::round(v)) < 1e-9 ? 0 : v < 10 ? 2 : v < 100 ? 1 : 0;
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    std::string text = buf;
    if (text.find('.') != std::string::npos) {
        while (text.back() == '0') text.pop_back();
        if (text.back() == '.') text.pop_back();
    }
    return text + names[u];
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

std::string nearest(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t best_d = std::string::npos;
    for (const auto& c : candidates) {
        std::size_t d = edit_distance(word, c);
        if (d < best_d) { best_d = d; best = c; }
    }
    // Only suggest when fewer than half the letters differ: "adx" -> "add", not "qwerty" -> "copy".
    if (best_d == std::string::npos || best_d * 2 > std::max(word.size(), best.size())) return "";
    return best;
}

}  // namespace suite
