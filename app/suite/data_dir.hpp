#pragma once
// Where the files the programs read at run time live (the plot scripts, Chart.js for the
// history page, the JSON schema): an installed tree, PREFIX/share/suite beside the program's
// PREFIX/bin, found from the program's own path (/proc/self/exe); else the source tree the
// build came from (compiled in), so that a build tree works as it always has. An installed
// tree is used alone: a file missing from it is never taken from a source tree elsewhere.
#include <string>

namespace suite {

struct DataDir {
    std::string path;        // the directory the relative names below are taken from
    bool installed = false;  // PREFIX/share/suite, not the source tree
};

const DataDir& data_dir();

// DIR/relative when it is readable; otherwise "" and `why` names the file and where it was
// looked for.
std::string data_file(const std::string& relative, std::string& why);

// What `suite --version` and `suite-mpi --version` print: the version, the git revision, the
// compiler and flags, the parts this build has, and where its data directory is.
std::string version_text(const std::string& program);

}  // namespace suite
