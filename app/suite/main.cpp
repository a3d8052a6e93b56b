// suite: the command line. main() only picks the command (one file each in this folder) and maps
// errors to exit statuses: 0 success, 1 a kernel failed verification or the run failed, 2 a
// usage error, 128+N a signal.
#include <signal.h>

#include <cstdio>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/data_dir.hpp"
#include "harness/common/did_you_mean.hpp"
#include "harness/common/units.hpp"

namespace {

// An error is one line: a value typed with a newline or another control character in it
// (`--sizes=$'64KiB\n'`) is shown escaped, not as a second line that looks like another message.
std::string one_line(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (c == '\n')
            out += "\\n";
        else if (c == '\r')
            out += "\\r";
        else if (c == '\t')
            out += "\\t";
        else if (c < 0x20 || c == 0x7f) {
            char b[8];
            std::snprintf(b, sizeof b, "\\x%02x", c);
            out += b;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace suite;
    // Past a file size limit (ulimit -f) a write must fail with EFBIG, so that the writer can
    // say so, remove its temporary file and keep the previous result, rather than the process
    // being killed mid-write by SIGXFSZ with nothing said.
    signal(SIGXFSZ, SIG_IGN);
    std::vector<std::string> all(argv, argv + argc);
    std::vector<std::string> args(all.begin() + 1, all.end());
    if (args.size() == 1 && args[0] == "--version") {
        std::cout << version_text("suite");
        return 0;
    }
    std::string command = "run";
    if (!args.empty() && !args[0].empty() && args[0][0] != '-') {
        command = args[0];
        args.erase(args.begin());
    }
    try {
        if (command == "run") return cmd_run(args, all);
        if (command == "list") return cmd_list(args);
        if (command == "info") return cmd_info(args);
        if (command == "compare") return cmd_compare(args);
        if (command == "check") return cmd_check(args);
        if (command == "history") return cmd_history(args);
        if (command == "deterministic") return cmd_deterministic(args, all);
        if (command == "traverse") return cmd_traverse(args);
        if (command == "matrix") return cmd_matrix(args);
        if (command == "mpm") return cmd_mpm(args);
        if (command == "roofline") return cmd_roofline(args, all);
        std::string hint = nearest(command, {"run", "list", "info", "compare", "check", "history", "deterministic",
                                             "traverse", "matrix", "mpm", "roofline"});
        throw UsageError("unknown command '" + command + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                         "; commands: run, list, info, compare, check, history, deterministic, traverse, matrix, mpm, "
                         "roofline (see ./suite --help)");
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return 0;
        std::string msg = e.what();
        std::cerr << "suite: error: " << one_line(msg) << " (see ./suite --help)\n";
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "suite: error: " << one_line(e.what()) << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        // Past every estimate made before the work: say what ran out, not "std::bad_alloc".
        std::cerr << "suite: error: out of memory: an allocation failed beyond the estimate made before the run "
                     "(the machine's memory, or the address-space limit of ulimit -v); give a smaller size\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "suite: error: " << one_line(e.what()) << "\n";
        return 1;
    }
}
