#pragma once
// The Python scripts under plots/ that commands run on the directory they wrote (traverse's
// snapshots, matrix's spy plots): which interpreter, and running one with its stderr kept.
#include <string>
#include <vector>

namespace suite {

// The interpreter and script that draw the PNGs, or why there are none.
struct Plotter {
    std::string python, script, reason;
};
// `script` is a file name in the data directory's plots/ (data_dir.hpp). SUITE_PYTHON overrides
// the interpreter; else Debian's /usr/bin/python3 (which has matplotlib), else python3 on PATH.
Plotter find_plotter(const std::string& script);

// For a command about to draw: in an installed tree a missing script is a broken install, said
// before any work (UsageError naming the file, where it was looked for, and `skip`, the option
// that does without the figure); in a build tree the figure is only skipped, with a note.
void require_plotter(const std::string& script, const std::string& skip);

// Runs the plot script on DIR; "" on success, else why it failed (its last line of stderr).
std::string draw(const Plotter& p, const std::string& dir);
// Runs the plot script with `args`; its stderr is kept in a file in `scratch_dir` meanwhile.
std::string draw_with(const Plotter& p, const std::vector<std::string>& args, const std::string& scratch_dir);

}  // namespace suite
