#include "harness/results/text_table.hpp"

#include <algorithm>

namespace suite {

namespace {

bool is_right(const TextTable& t, std::size_t c) { return c < t.right.size() && t.right[c]; }

// Markdown cells cannot hold a '|' or a line break.
std::string md_cell(std::string s) {
    std::string out;
    for (char ch : s) {
        if (ch == '|')
            out += "\\|";
        else if (ch == '\n')
            out += ' ';
        else
            out += ch;
    }
    return out;
}

}  // namespace

std::string TextTable::render_text() const {
    std::vector<std::size_t> width(header.size(), 0);
    for (std::size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
    for (const auto& row : rows)
        for (std::size_t c = 0; c < row.size() && c < width.size(); ++c) width[c] = std::max(width[c], row[c].size());
    auto line = [&](const std::vector<std::string>& cells) {
        std::string out;
        for (std::size_t c = 0; c < width.size(); ++c) {
            const std::string cell = c < cells.size() ? cells[c] : "";
            const std::string pad(width[c] - std::min(width[c], cell.size()), ' ');
            out += (c ? "  " : "") + (is_right(*this, c) ? pad + cell : cell + (c + 1 < width.size() ? pad : ""));
        }
        return out + "\n";
    };
    std::string out = line(header);
    std::size_t total = 0;
    for (auto w : width) total += w + 2;
    out += std::string(total > 2 ? total - 2 : 0, '-') + "\n";
    for (const auto& row : rows) out += line(row);
    return out;
}

std::string TextTable::render_markdown() const {
    std::string out = "|";
    for (const auto& h : header) out.append(" ").append(md_cell(h)).append(" |");
    out += "\n|";
    for (std::size_t c = 0; c < header.size(); ++c) out += is_right(*this, c) ? " ---: |" : " --- |";
    out += "\n";
    for (const auto& row : rows) {
        out += "|";
        for (std::size_t c = 0; c < header.size(); ++c)
            out.append(" ").append(md_cell(c < row.size() ? row[c] : "")).append(" |");
        out += "\n";
    }
    return out;
}

}  // namespace suite
