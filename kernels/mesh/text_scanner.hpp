#pragma once
// Line-by-line reading of a mesh file held in memory, for the readers: each line split into
// whitespace-separated fields, numbers parsed strictly (std::from_chars, the whole field), and
// every complaint thrown as a MeshError naming the file and the current line.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/mesh/mesh_error.hpp"

namespace suite::mesh {

class TextScanner {
public:
    TextScanner(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}

    // Moves to the next line that is not blank; false at the end of the text.
    bool next() {
        while (pos_ < text_.size()) {
            const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
            line_ = text_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++line_no_;
            split();
            if (!fields_.empty()) return true;
        }
        fields_.clear();
        line_ = {};
        return false;
    }
    // Like next(), but the end of the text is an error that says what was expected.
    void expect_line(const std::string& what) {
        if (!next()) fail("the file ends here, but " + what + " should follow");
    }

    std::size_t size() const { return fields_.size(); }
    std::string_view field(std::size_t i) const { return fields_[i]; }
    std::string_view line() const { return line_; }
    std::size_t line_number() const { return line_no_; }
    const std::string& name() const { return name_; }
    std::size_t bytes() const { return text_.size(); }

    // Exactly `n` fields, or an error naming `what` a line of this kind holds.
    void expect_fields(std::size_t n, const std::string& what) const {
        if (size() != n)
            fail("expected " + std::to_string(n) + " field" + (n == 1 ? "" : "s") + " (" + what + "), found " +
                 std::to_string(size()) + ": '" + shown() + "'");
    }

    std::uint64_t uint(std::size_t i, const char* what) const {
        std::uint64_t v = 0;
        const auto f = field(i);
        auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
        if (ec != std::errc() || p != f.data() + f.size())
            fail(std::string(what) + " must be a non-negative integer, found '" + std::string(f) + "'");
        return v;
    }
    std::int64_t sint(std::size_t i, const char* what) const {
        std::int64_t v = 0;
        const auto f = field(i);
        auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
        if (ec != std::errc() || p != f.data() + f.size())
            fail(std::string(what) + " must be an integer, found '" + std::string(f) + "'");
        return v;
    }
    // A finite number: NaN and infinities are refused here, where the line is known.
    double real(std::size_t i, const char* what) const {
        double v = 0;
        auto f = field(i);
        if (!f.empty() && f[0] == '+') f.remove_prefix(1);  // from_chars takes no '+', files may have it
        auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
        if ((ec != std::errc() && ec != std::errc::result_out_of_range) || p != f.data() + f.size())
            fail(std::string(what) + " must be a number, found '" + std::string(field(i)) + "'");
        if (ec == std::errc::result_out_of_range || !std::isfinite(v))
            fail(std::string(what) + " is not a finite number: '" + std::string(field(i)) +
                 "'; coordinates must be finite");
        return v;
    }

    [[noreturn]] void fail(const std::string& what) const { throw MeshError(name_, line_no_, what); }
    [[noreturn]] void fail_at(std::size_t line, const std::string& what) const { throw MeshError(name_, line, what); }

    // The current line, shortened for a message.
    std::string shown() const {
        std::string s(line_.substr(0, 60));
        while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.pop_back();
        for (auto& c : s)
            if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
        return s + (line_.size() > 60 ? "..." : "");
    }

private:
    void split() {
        fields_.clear();
        std::size_t i = 0;
        while (i < line_.size()) {
            while (i < line_.size() && is_space(line_[i])) ++i;
            const std::size_t start = i;
            while (i < line_.size() && !is_space(line_[i])) ++i;
            if (i > start) fields_.push_back(line_.substr(start, i - start));
        }
    }
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

    std::string_view text_;
    std::string name_;
    std::size_t pos_ = 0;
    std::size_t line_no_ = 0;
    std::string_view line_;
    std::vector<std::string_view> fields_;  // reused from line to line: no allocation per line
};

}  // namespace suite::mesh
