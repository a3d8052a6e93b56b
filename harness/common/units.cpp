#include "harness/common/units.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <set>
#include <system_error>

#include "harness/common/text.hpp"

namespace suite {

namespace {

// Not "quoted": with <iomanip> seen (the precompiled header has it), ADL would pick std::quoted.
std::string in_quotes(std::string_view s) { return "'" + std::string(s) + "'"; }

bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// The largest size or count accepted: 10^18 (bytes, or elements).
constexpr std::uint64_t max_size = 1000000000000000000ull;

// A decimal number "D", "D.F" or ".F" at the start of a text, kept exact: mantissa / 10^scale,
// with the fraction's trailing zeros dropped (1.50 = 15 / 10^1). `value` is the same as a
// double, for messages and sweep factors only.
struct Decimal {
    unsigned __int128 mantissa = 0;
    int scale = 0;
    double value = 0;
    std::size_t used = 0;        // characters taken from the text
    std::size_t int_digits = 0;  // significant digits before the point
    bool too_long = false;       // more than 24 significant digits: not kept exactly
};

bool parse_decimal(std::string_view s, Decimal& d) {
    std::size_t i = 0;
    std::string digits;  // without the point
    int fraction = 0;
    while (i < s.size() && is_digit(s[i])) digits += s[i++];
    const std::size_t int_len = digits.size();
    if (i < s.size() && s[i] == '.') {
        ++i;
        while (i < s.size() && is_digit(s[i])) {
            digits += s[i++];
            ++fraction;
        }
    }
    if (digits.empty()) return false;
    d = Decimal{};
    d.used = i;
    d.value = std::strtod(std::string(s.substr(0, i)).c_str(), nullptr);  // never throws; inf for 400 digits
    const std::size_t lead = std::min(digits.find_first_not_of('0'), int_len);
    d.int_digits = int_len - lead;
    while (fraction > 0 && digits.back() == '0') {
        digits.pop_back();
        --fraction;
    }
    const std::size_t first = digits.find_first_not_of('0');
    if (first == std::string::npos) return true;  // zero
    digits.erase(0, first);
    if (digits.size() > 24 || fraction > 36) {
        d.too_long = true;
        return true;
    }
    for (char c : digits) d.mantissa = d.mantissa * 10 + static_cast<unsigned>(c - '0');
    d.scale = fraction;
    return true;
}

unsigned __int128 pow10(int n) {
    unsigned __int128 p = 1;
    while (n-- > 0) p *= 10;
    return p;
}

// A number for a message: 307.2, 1.5, 1e+40; never more than 10 significant digits.
std::string shown(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

// The list and sweep forms of --sizes, for byte sizes and counts alike: `one` parses one value,
// `show` prints one for a message. A value given twice, or generated twice by a sweep whose steps
// are closer than one unit, is refused: the same point is never run twice.
template <class One, class Show>
std::vector<std::uint64_t> sizes_from(std::string_view text, One one, Show show, const std::string& unit) {
    std::vector<std::uint64_t> out;
    if (text.find(':') == std::string_view::npos) {
        std::vector<std::string> given;
        for (const auto& part : split(text, ',')) {
            const std::uint64_t v = one(part);
            for (std::size_t i = 0; i < out.size(); ++i)
                if (out[i] == v)
                    throw UsageError(
                        "size list " + in_quotes(text) + " names " + show(v) + " twice" +
                        (given[i] != part ? " (as " + in_quotes(given[i]) + " and " + in_quotes(part) + ")" : "") +
                        "; give each size once");
            out.push_back(v);
            given.push_back(part);
        }
        return out;
    }
    auto parts = split(text, ':');
    if (parts.size() > 3)
        throw UsageError("invalid size sweep " + in_quotes(text) +
                         ": expected FROM:TO or FROM:TO:xFACTOR, e.g. 16KiB:1GiB:x2");
    const std::uint64_t from = one(parts[0]);
    const std::uint64_t to = one(parts[1]);
    double factor = 2.0;
    if (parts.size() == 3) {
        std::string_view f = parts[2];
        if (!f.empty() && (f[0] == 'x' || f[0] == '*')) f.remove_prefix(1);
        Decimal d;
        if (!parse_decimal(f, d) || d.used != f.size() || d.too_long || !(d.value > 1.0))
            throw UsageError("invalid size sweep step " + in_quotes(parts[2]) +
                             ": expected x and a decimal number above 1, such as x2 or x1.5 (digits and one point "
                             "only: no sign, no exponent)");
        factor = d.value;
    }
    if (from > to)
        throw UsageError("invalid size sweep " + in_quotes(text) + ": the first size is larger than the last");
    // Counted before generating, so that a tiny factor costs nothing.
    if (std::log(static_cast<double>(to) / static_cast<double>(from)) / std::log(factor) >= 1000 - 1e-9)
        throw UsageError("size sweep " + in_quotes(text) + " has more than 1000 points; use a larger factor");
    for (double s = static_cast<double>(from); s <= static_cast<double>(to) * (1 + 1e-9); s *= factor) {
        // Within the tolerance a step that lands past TO by rounding error means TO.
        const auto v = std::min(static_cast<std::uint64_t>(std::llround(s)), to);
        if (!out.empty() && v == out.back())
            throw UsageError("size sweep " + in_quotes(text) + " gives " + show(v) +
                             " twice: its steps are less than one " + unit +
                             " apart there; use a larger factor or a larger first size");
        out.push_back(v);
    }
    return out;
}

}  // namespace

std::optional<std::uint64_t> whole_number(std::string_view text, std::uint64_t hi) {
    if (text.empty()) return std::nullopt;
    std::uint64_t v = 0;
    for (char c : text) {
        if (!is_digit(c)) return std::nullopt;
        const auto d = static_cast<std::uint64_t>(c - '0');
        if (v > (UINT64_MAX - d) / 10) return std::nullopt;
        v = v * 10 + d;
    }
    if (v > hi) return std::nullopt;
    return v;
}

std::uint64_t parse_whole(std::string_view text, std::string_view option, std::uint64_t lo, std::uint64_t hi,
                          std::string_view about) {
    const auto v = whole_number(text, hi);
    if (!v || *v < lo)
        throw UsageError(std::string(option) + "=" + std::string(text) + ": expected a whole number from " +
                         std::to_string(lo) + " to " + std::to_string(hi) +
                         (about.empty() ? "" : " (" + std::string(about) + ")"));
    return *v;
}

double parse_finite(std::string_view text, std::string_view option) {
    const std::string given = std::string(option) + "=" + std::string(text) + ": ";
    const char* accepted = "expected a finite number such as 0.05, 3 or 1e-8";
    // The grammar first: from_chars alone would take "inf", "nan", hex and a leading part of "1x".
    static const std::regex decimal(R"([+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?)");
    if (!std::regex_match(text.begin(), text.end(), decimal)) throw UsageError(given + accepted);
    double v = 0;
    const std::size_t skip = text[0] == '+' ? 1 : 0;  // from_chars takes no '+'
    const auto [end, ec] = std::from_chars(text.data() + skip, text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
        throw UsageError(given + "out of the range of a double; " + accepted);
    return v;
}

std::string format_number(double value) {
    // Whole numbers in full (100000, not 1e+05), the rest as short as reads back the same.
    if (value == std::trunc(value) && std::fabs(value) < 1e15) return std::to_string(static_cast<long long>(value));
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    return ec == std::errc() ? std::string(buf, end) : std::to_string(value);
}

std::uint64_t parse_seed(std::string_view text, std::string_view option) {
    return parse_whole(text, option, 0, UINT64_MAX);
}

std::vector<std::string> parse_name_list(std::string_view text, std::string_view option) {
    std::vector<std::string> out;
    const std::string given = std::string(option) + "=" + std::string(text);
    for (auto& name : split(text, ',')) {
        if (name.empty()) throw UsageError(given + " has an empty name; separate the names by single commas");
        if (std::find(out.begin(), out.end(), name) != out.end())
            throw UsageError(given + " names '" + name + "' twice; give each once");
        out.push_back(std::move(name));
    }
    return out;
}

std::uint64_t parse_count(std::string_view text, std::string_view noun, std::string_view owner) {
    const std::string what = "invalid size " + in_quotes(text) + " for " + std::string(owner) +
                             ", which is sized by a count of " + std::string(noun);
    const auto v = whole_number(text);
    if (v && *v > max_size) throw UsageError(what + ": at most " + std::to_string(max_size));
    if (!v || *v < 1)
        throw UsageError(what + ": expected a whole number of " + std::string(noun) +
                         ", at least 1 (no unit), e.g. 10000");
    return *v;
}

std::uint64_t parse_bytes(std::string_view text) {
    const std::string accepted = "a whole number of bytes such as 4096, 32KiB, 64MiB, 1.5GiB or 100MB";
    if (!text.empty() && text[0] == '-')
        throw UsageError("invalid size " + in_quotes(text) + ": sizes must be positive; expected " + accepted);
    Decimal d;
    if (!parse_decimal(text, d)) throw UsageError("invalid size " + in_quotes(text) + ": expected " + accepted);
    const std::string unit(text.substr(d.used));
    static const std::pair<const char*, std::uint64_t> units[] = {
        {"", 1},
        {"B", 1},
        {"K", 1ull << 10},
        {"KiB", 1ull << 10},
        {"k", 1ull << 10},
        {"kB", 1000},
        {"KB", 1000},
        {"M", 1ull << 20},
        {"MiB", 1ull << 20},
        {"MB", 1000000},
        {"G", 1ull << 30},
        {"GiB", 1ull << 30},
        {"GB", 1000000000},
        {"T", 1ull << 40},
        {"TiB", 1ull << 40},
        {"TB", 1000000000000},
    };
    for (const auto& [name, factor] : units) {
        if (unit != name) continue;
        const std::string too_large =
            "invalid size " + in_quotes(text) + ": too large; at most " + std::to_string(max_size) + " bytes";
        if (d.int_digits > 19) throw UsageError(too_large);
        if (d.too_long) throw UsageError("invalid size " + in_quotes(text) + ": too many digits; expected " + accepted);
        // Exact: mantissa < 10^24 and factor <= 2^40 stay far below 2^128.
        const unsigned __int128 num = d.mantissa * factor, den = pow10(d.scale);
        if (num % den != 0)
            throw UsageError("invalid size " + in_quotes(text) + ": that is " +
                             shown(d.value * static_cast<double>(factor)) +
                             " bytes, not a whole number of bytes; expected " + accepted);
        const unsigned __int128 bytes = num / den;
        if (bytes < 1) throw UsageError("invalid size " + in_quotes(text) + ": sizes must be at least 1 byte");
        if (bytes > max_size) throw UsageError(too_large);
        return static_cast<std::uint64_t>(bytes);
    }
    throw UsageError("invalid size " + in_quotes(text) + ": unknown unit " + in_quotes(unit) +
                     "; accepted units are B, KiB, MiB, GiB, TiB (powers of 2) and kB, MB, GB, TB (powers of 10)");
}

std::vector<std::uint64_t> parse_size_list(std::string_view text) {
    return sizes_from(
        text, [](std::string_view t) { return parse_bytes(t); }, [](std::uint64_t v) { return format_bytes(v); },
        "byte");
}

std::vector<std::uint64_t> parse_count_list(std::string_view text, std::string_view noun, std::string_view owner) {
    const std::string n(noun);
    return sizes_from(
        text, [&](std::string_view t) { return parse_count(t, noun, owner); },
        [&](std::uint64_t v) { return std::to_string(v) + " " + n; },
        n.empty() ? n : n.substr(0, n.size() - (n.back() == 's')));
}

std::vector<int> parse_thread_list(std::string_view text, int max_threads, std::string_view limit) {
    const bool here = limit.empty();  // this machine's PUs: 'all' means them
    const std::string max = std::to_string(max_threads), whole(text);
    const std::string accepted = "expected whole numbers from 1 to " + max +
                                 " as a list such as 1,2,4, a range 1-8 or 1-8:2" + (here ? ", or 'all'" : "");
    auto too_many = [&](const std::string& t) {
        if (here)
            return UsageError("thread count " + t + " is more than the " + max +
                              " processing units (PUs) available here; use at most " + max + " or 'all'");
        return UsageError("thread count " + t + " is more than " + max + ": " + std::string(limit));
    };
    auto all_digits = [](std::string_view t) { return !t.empty() && std::all_of(t.begin(), t.end(), is_digit); };
    if (text.empty()) throw UsageError("empty thread list: " + accepted);
    std::vector<int> out;
    std::vector<std::string> given;  // the part each count came from, for the message on a repeat
    auto add = [&](std::uint64_t t, const std::string& part) {
        if (t < 1) throw UsageError("invalid thread count 0 in '" + whole + "': at least 1 thread is needed");
        if (t > static_cast<std::uint64_t>(max_threads)) throw too_many(std::to_string(t));
        for (std::size_t i = 0; i < out.size(); ++i)
            if (out[i] == static_cast<int>(t))
                throw UsageError("thread count " + std::to_string(t) + " is given twice in '" + whole + "'" +
                                 (given[i] != part ? " (by '" + given[i] + "' and '" + part + "')" : "") +
                                 "; give each once");
        out.push_back(static_cast<int>(t));
        given.push_back(part);
    };
    for (const auto& part : split(text, ',')) {
        if (part == "all" && here) {
            add(static_cast<std::uint64_t>(max_threads), part);
            continue;
        }
        if (part.empty())
            throw UsageError("thread list '" + whole + "' has an empty item (a comma too many): " + accepted);
        const auto dash = part.find('-');
        if (dash == std::string::npos || dash == 0) {  // "-1" is a negative count, not a range
            const auto t = whole_number(part);
            if (!t && all_digits(part)) throw too_many(part);
            if (!t) throw UsageError("invalid thread count '" + part + "' in '" + whole + "': " + accepted);
            add(*t, part);
            continue;
        }
        const auto colon = part.find(':', dash);
        const std::string_view p(part);
        const auto lo = whole_number(p.substr(0, dash));
        const auto hi =
            whole_number(p.substr(dash + 1, colon == std::string::npos ? std::string::npos : colon - dash - 1));
        const auto step =
            colon == std::string::npos ? std::optional<std::uint64_t>(1) : whole_number(p.substr(colon + 1));
        if (!lo || !hi || !step || *step < 1 || *lo > *hi)
            throw UsageError("invalid thread range '" + part + "' in '" + whole +
                             "': expected FROM-TO or FROM-TO:STEP, whole numbers from 1 to " + max +
                             " with FROM at most TO and STEP at least 1, e.g. 1-8 or 1-8:2");
        if (*hi > static_cast<std::uint64_t>(max_threads))
            throw too_many(std::to_string(*hi));  // checked before expanding, so a huge range costs nothing
        for (std::uint64_t t = *lo; t <= *hi; t += *step) add(t, part);
    }
    return out;
}

std::vector<int> parse_cpu_list(std::string_view text) {
    const std::string whole(text);
    const std::string accepted = "expected CPU numbers (whole numbers from 0) as a list such as 0,2,4-7";
    constexpr std::uint64_t max_cpu = 2147483647;
    if (text.empty()) throw UsageError("empty CPU list: " + accepted);
    auto number = [&](std::string_view t, const std::string& part) {
        const auto v = whole_number(t);
        if (v && *v > max_cpu)
            throw UsageError("CPU number " + std::string(t) + " in '" + whole + "' is too large; at most " +
                             std::to_string(max_cpu));
        if (!v)
            throw UsageError((part == t ? "invalid CPU number '" : "invalid CPU range '") + part + "' in '" + whole +
                             "': " + accepted);
        return *v;
    };
    std::vector<int> out;
    std::set<int> seen;
    for (const auto& part : split(text, ',')) {
        if (part.empty())
            throw UsageError("CPU list '" + whole + "' has an empty item (a comma too many): " + accepted);
        const auto dash = part.find('-');
        const std::string_view p(part);
        const std::uint64_t lo = number(dash == std::string::npos || dash == 0 ? p : p.substr(0, dash), part);
        const std::uint64_t hi = dash == std::string::npos ? lo : number(p.substr(dash + 1), part);
        if (lo > hi)
            throw UsageError("invalid CPU range '" + part + "' in '" + whole +
                             "': the first CPU is above the last; expected e.g. 0-3");
        if (hi - lo > 1000000)
            throw UsageError("CPU range '" + part +
                             "' is implausibly large (more than 1000000 CPUs)");  // before expanding it
        for (std::uint64_t c = lo; c <= hi; ++c) {
            if (!seen.insert(static_cast<int>(c)).second)
                throw UsageError("CPU " + std::to_string(c) + " is given twice in '" + whole + "'; give each once");
            out.push_back(static_cast<int>(c));
        }
    }
    return out;
}

std::string format_bytes(std::uint64_t bytes) {
    static const char* names[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = static_cast<double>(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 4) {
        v /= 1024.0;
        ++u;
    }
    // Whole numbers as they are; otherwise up to 3 significant digits, never in e-notation.
    char buf[32];
    const int decimals = std::fabs(v - std::round(v)) < 1e-9 ? 0 : v < 10 ? 2 : v < 100 ? 1 : 0;
    // Never rounded past the largest size a size option takes (909494.7TiB is shown as
    // 909494TiB, not 909495TiB, which parse_bytes would refuse as too large).
    if (decimals == 0 && std::round(v) * std::ldexp(1.0, 10 * u) > static_cast<double>(max_size)) v = std::floor(v);
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    std::string text = buf;
    if (text.find('.') != std::string::npos) {
        while (text.back() == '0') text.pop_back();
        if (text.back() == '.') text.pop_back();
    }
    return text + names[u];
}

}  // namespace suite
