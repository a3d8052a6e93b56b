#pragma once
// The Python scripts under plots/ that commands run on the directory they wrote (traverse's
// snapshots, matrix's spy plots): which interpreter, and running one with its stderr kept.
#include <string>

namespace suite {

// The interpreter and script that draw the PNGs, or why there are none.
struct Plotter {
    std::string python, script, reason;
};
// `script` is a file name in this source tree's plots/. SUITE_PYTHON overrides the interpreter;
// else Debian's /usr/bin/python3 (which has matplotlib), else python3 on PATH.
Plotter find_plotter(const std::string& script);

// Runs the plot script on DIR; "" on success, else why it failed (its last line of stderr).
std::string draw(const Plotter& p, const std::string& dir);

}  // namespace suite
