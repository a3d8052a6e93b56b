#pragma once
// A table of strings rendered for a terminal (aligned columns) or as a Markdown table (for a
// review or a CI comment). It only lays out text; the commands decide what goes in it.
#include <string>
#include <vector>

namespace suite {

struct TextTable {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    // Columns aligned to the right (numbers); the others are aligned to the left.
    std::vector<bool> right;

    std::string render_text() const;
    std::string render_markdown() const;
};

}  // namespace suite
