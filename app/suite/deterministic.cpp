#include "app/suite/commands.hpp"
#include "app/suite/frame.hpp"
#include "harness/results/callgrind_dump.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/parse.hpp"
#include "app/suite/run.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/instruments/callgrind_marks.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/measure/output_formats.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/result.hpp"
#include "harness/results/build_info.hpp"

namespace suite {
namespace deterministic_command {
namespace {

using nlohmann::json;

const char* const inner_env = "SUITE_CALLGRIND_INNER";

const char* const det_examples = R"(
Runs the points under valgrind's callgrind with its cache simulator, counting only inside the
kernel's calls (not setup, warm-up or clocks), and writes a suite result whose records carry a
"callgrind" block: instructions (Ir), data reads and writes, and simulated I1/D1/LL misses per
kernel call. The counts repeat exactly from run to run, so `suite check` can gate on them where
timings are too noisy or there is no PMU. Timings in such a file were taken under valgrind and
are not hardware figures; check and compare use the callgrind counts instead.

Defaults here: --threads=1 (valgrind runs threads one at a time), --reps=3, one kernel call per
sample, sizes 16KiB,1MiB,32MiB (in the simulated L1, in the simulated 8 MiB last level, beyond
it) unless --mesh gives the size. Simulated caches: I1 and D1 32 KiB 8-way, LL 8 MiB 16-way, 64 B lines (whatever the host).

valgrind 3.19 cannot decode AVX-512: use a build for x86-64-v3, e.g. build/suite-x86-64-v3
(built beside ./suite when valgrind is installed) or make BUILD=build-v3 ARCH=x86-64-v3
CMAKE_FLAGS=-DSUITE_LINK_TOP=OFF.

Examples:
  build/suite-x86-64-v3 deterministic --kernel=triad,add --pattern=sequential,random --out=det.json
  build/suite-x86-64-v3 deterministic --kernel=latency --sizes=64KiB,16MiB --out=lat-det.json
  build/suite-x86-64-v3 deterministic --kernel=fem-spmv --mesh=disk:refine=7 --ordering=natural,hilbert
  ./suite check --baseline results/baseline/ci-deterministic.json det.json --tolerance=1%
)";

std::string self_exe() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) throw std::runtime_error("cannot find this program's path (/proc/self/exe)");
    return std::string(buf, static_cast<std::size_t>(n));
}

std::string find_on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    for (const auto& dir : split(path ? path : "/usr/bin:/bin", ':')) {
        const std::string p = (dir.empty() ? "." : dir) + "/" + name;
        if (access(p.c_str(), X_OK) == 0) return p;
    }
    return "";
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The last lines of valgrind's log that say what went wrong (its "==PID==" prefix removed).
std::string log_tail(const std::string& log) {
    std::vector<std::string> lines;
    for (auto& l : split(log, '\n')) {
        if (l.rfind("==", 0) == 0) {
            auto end = l.find("== ");
            l = end == std::string::npos ? "" : l.substr(end + 3);
        }
        if (!l.empty()) lines.push_back(l);
    }
    for (const auto& l : lines)
        if (l.find("unhandled instruction") != std::string::npos ||
            l.find("Unrecognised instruction") != std::string::npos)
            return "valgrind met an instruction it cannot decode (" + l +
                   "); build for x86-64-v3 (see ./suite deterministic --help)";
    std::string out;
    for (std::size_t i = lines.size() > 3 ? lines.size() - 3 : 0; i < lines.size(); ++i)
        out += (out.empty() ? "" : " | ") + lines[i];
    return out;
}

// The valgrind child's exit status; waits through EINTR.
int wait_child(pid_t pid) {
    int st = 0;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

// The inner run's arguments, rebuilt from the options in one canonical form: the counts must
// not depend on how the command was typed, nor on the output path (argv and the environment sit
// on the stack, whose layout moves the cache sets the kernel's stack frame maps to).
std::vector<std::string> inner_args(const RunOptions& o) {
    std::vector<std::string> a;
    auto add = [&](const char* flag, const std::string& v) {
        if (!v.empty()) a.push_back(std::string(flag) + "=" + v);
    };
    add("--kernel", o.kernels);
    add("--pattern", o.patterns);
    add("--ordering", o.orderings);
    add("--mesh", o.mesh);
    add("--phase", o.phases);
    add("--strategy", o.strategies);
    add("--particles", o.particles);
    add("--isa", o.isas);
    add("--stores", o.stores);
    add("--size", o.size);
    add("--sizes", o.sizes);
    add("--threads", o.threads);
    add("--pin", o.pin);
    add("--placement", o.placement);
    if (o.hugepages != hugepages_name(HugePages::system))
        add("--hugepages", o.hugepages);  // only when asked: the baselines' argv stays as it was
    add("--reps", std::to_string(o.reps));
    add("--seed", std::to_string(o.seed));
    for (const auto& [name, text] : o.params) add(("--" + name).c_str(), text);
    return a;
}

int run_outer(const RunOptions& opts, const std::string& valgrind, const OutputFile& out) {
    // Always under /tmp, not $TMPDIR: a path of the same length on every machine (see inner_args).
    std::string tmpl = "/tmp/suite-callgrind-XXXXXX";
    if (!mkdtemp(tmpl.data()))
        throw std::runtime_error(std::string("cannot create a temporary directory in /tmp: ") + std::strerror(errno));
    const std::string dir = tmpl;
    struct Cleanup {
        std::string dir;
        ~Cleanup() {
            std::error_code ec;
            std::filesystem::remove_all(dir, ec);
        }
    } cleanup{dir};
    // The program by a path of fixed length, wherever the build lives.
    const std::string program = dir + "/suite";
    if (symlink(self_exe().c_str(), program.c_str()) != 0)
        throw std::runtime_error(std::string("symlink: ") + std::strerror(errno));

    std::vector<std::string> argv = {valgrind,
                                     "--tool=callgrind",
                                     "--cache-sim=yes",
                                     "--collect-atstart=no",
                                     std::string("--I1=") + callgrind_sim_i1,
                                     std::string("--D1=") + callgrind_sim_d1,
                                     std::string("--LL=") + callgrind_sim_ll,
                                     "--callgrind-out-file=" + dir + "/callgrind.out",
                                     "--log-file=" + dir + "/valgrind.log",
                                     program,
                                     "deterministic"};
    for (const auto& a : inner_args(opts)) argv.push_back(a);
    // A fixed environment, for the same reason; hwloc's x86 CPUID backend cannot work under
    // valgrind and would say so, the OS's view of the topology suffices. Every allocation of
    // 1 KiB or more is its own mmap: a kernel's call runs an OpenMP region, and libgomp
    // allocates and frees a team in each one (for one thread it keeps none); from glibc's heap
    // that costs whatever path the heap's layout takes, so a change anywhere in the program
    // (an allocation more during set-up) moved a small kernel's count by up to 8 %. An mmap
    // costs the same instructions every time. (The kernel's own instructions never moved.)
    std::vector<std::string> env_strings = {std::string(inner_env) + "=" + dir + "/run.json", "HWLOC_COMPONENTS=-x86",
                                            "LC_ALL=C", "PATH=/usr/bin:/bin",
                                            "GLIBC_TUNABLES=glibc.malloc.mmap_threshold=1024"};
    std::vector<char*> cargv, cenv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    for (auto& e : env_strings) cenv.push_back(e.data());
    cenv.push_back(nullptr);

    // Ctrl-C reaches valgrind and its program (same process group); this process waits for
    // them, cleans up and reports, rather than dying first and leaving files behind.
    struct sigaction ignore {
    }, old_int{}, old_term{};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGINT, &ignore, &old_int);
    sigaction(SIGTERM, &ignore, &old_term);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    if (pid == 0) {
        sigaction(SIGINT, &old_int, nullptr);
        sigaction(SIGTERM, &old_term, nullptr);
        execve(cargv[0], cargv.data(), cenv.data());
        _exit(127);
    }
    const int status = wait_child(pid);
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    if (status == 130 || status == 143 || status == 128 + SIGINT || status == 128 + SIGTERM) {
        std::cerr << "suite: interrupted; nothing written\n";
        return status;
    }
    const std::string run_json = dir + "/run.json";
    if ((status != 0 && status != 1 && status != 3) || access(run_json.c_str(), R_OK) != 0)
        throw std::runtime_error("the run under valgrind failed (exit status " + std::to_string(status) +
                                 "): " + log_tail(slurp(dir + "/valgrind.log")));

    json doc = json::parse(slurp(run_json));
    std::string version = "valgrind";
    {
        const std::string log = slurp(dir + "/valgrind.log");
        const auto at = log.find("Using Valgrind-");
        if (at != std::string::npos)
            version = "valgrind " + log.substr(at + 15, log.find_first_of(" \n", at + 15) - at - 15);
    }
    auto& records = doc["results"];
    for (std::size_t i = 0; i < records.size(); ++i) {
        json& rec = records[i];
        const std::string dump_path = dir + "/callgrind.out." + std::to_string(i + 1);
        const CallgrindDump dump = parse_callgrind_dump(slurp(dump_path));
        const std::string kind = rec["size"]["kind"];
        const std::uint64_t size = rec["size"]["requested"];
        const std::string expected = "suite point " + rec["name"].get<std::string>() + " " +
                                     rec[rec["axis"].get<std::string>()].get<std::string>() + " " +
                                     (kind == "bytes" ? format_bytes(size) : std::to_string(size)) +
                                     " t=" + std::to_string(rec["threads"].get<int>());
        if (dump.label.find(expected) == std::string::npos)
            throw std::runtime_error("callgrind dump " + std::to_string(i + 1) + " is labelled '" + dump.label +
                                     "', expected '" + expected + "'");
        const double calls = rec["repetitions"]["counted"].get<double>() * rec["repetitions"]["batch"].get<double>();
        rec["callgrind"] = callgrind_block(dump, calls, version);
    }
    const std::string text = doc.dump(1) + "\n";
    if (!out.claimed())
        std::cout << text << std::flush;
    else {
        out.write(text);
        std::cerr << "wrote " << records.size() << " record(s) with callgrind counts to " << out.path() << "\n";
    }
    return status;
}

}  // namespace
}  // namespace deterministic_command

int cmd_deterministic(const std::vector<std::string>& args, const std::vector<std::string>& full_argv) {
    using namespace deterministic_command;
    CLI::App app{"suite deterministic: exact instruction and simulated cache-miss counts under valgrind's callgrind"};
    app.footer(det_examples);
    app.get_formatter()->column_width(28);
    RunOptions opts;
    setup_run_options(app, opts);
    std::string valgrind;
    app.add_option("--valgrind", valgrind, "the valgrind program (default: valgrind on PATH)");
    if (!parse_command_line(app, "suite deterministic", args)) return 0;
    if (opts.threads.empty()) opts.threads = "1";
    // A mesh gives a mesh kernel its size: default sizes beside it would be refused as a contradiction.
    if (opts.size.empty() && opts.sizes.empty() && opts.mesh.empty()) opts.sizes = "16KiB,1MiB,32MiB";
    if (opts.reps == -1) opts.reps = 3;
    // Callgrind's counts are the measurement here. Perf counters under valgrind would count its
    // translation work, and their bookkeeping between calls would disturb the simulated caches.
    opts.counters = "none";
    opts.energy = "none";
    const auto* asked = output_formats().find(opts.format);
    if (!opts.format.empty() && (!asked || asked->what.format != OutputFormat::json))
        throw UsageError("--format=" + opts.format +
                         ": deterministic writes suite's JSON only (--out=FILE.json or stdout)");
    const Topology topo = Topology::load();
    Plan plan = make_plan(opts, topo);
    for (const auto& p : plan.points)
        if (p.threads != 1)
            throw UsageError("--threads=" + opts.threads +
                             ": deterministic runs one thread (valgrind runs threads one at a time, "
                             "and waiting at barriers would count differently each run); use --threads=1");

    const char* inner_out = std::getenv(inner_env);
    if (inner_out && callgrind::running_on_valgrind()) {
        // The inner run, under valgrind: one call per sample, so that each dump holds whole calls.
        plan.out_path = inner_out;
        plan.format = OutputFormat::json;
        plan.quiet = true;
        plan.settings.min_sample_s = 0;
        CommandFrame frame("suite");
        frame.claim_file(plan.out_path, "--out");
        return execute_plan(plan, topo, full_argv, frame);
    }
#ifdef __AVX512F__
    throw UsageError("this build uses AVX-512 (built with " + std::string(build::flags) +
                     "), which valgrind 3.19 cannot decode; run a build for x86-64-v3, e.g. build/suite-x86-64-v3 "
                     "deterministic ...");
#endif
    if (!callgrind::available)
        throw UsageError(
            "this build has no callgrind marks (<valgrind/callgrind.h> was missing when it was built); install "
            "valgrind and rebuild");
    if (valgrind.empty()) valgrind = find_on_path("valgrind");
    if (valgrind.empty())
        throw UsageError(
            "valgrind is not on PATH; install it (Debian: apt-get install valgrind) or give --valgrind=PATH");
    if (access(valgrind.c_str(), X_OK) != 0)
        throw UsageError("--valgrind=" + valgrind + " is not an executable program");
    // Claimed before the minutes under valgrind: a second run on the same file refuses now.
    OutputFile out;
    if (!plan.out_path.empty()) out = OutputFile::claim(plan.out_path, "--out", run_inputs(opts));
    if (plan.dry_run) {
        std::cout << plan.points.size() << " point(s) under " << valgrind
                  << " --tool=callgrind --cache-sim=yes --collect-atstart=no (I1 " << callgrind_sim_i1 << ", D1 "
                  << callgrind_sim_d1 << ", LL " << callgrind_sim_ll << ")"
                  << (plan.out_path.empty() ? "" : ", output " + plan.out_path) << "\n";
        for (const auto& p : plan.points)
            std::cout << "  " << p.kernel->info.name << (p.variant.empty() ? "" : "-" + p.variant) << " "
                      << p.access.label() << " " << size_label(p.kernel->info.size_kind, p.size)
                      << " threads=" << p.threads << "\n";
        return 0;
    }
    return run_outer(opts, valgrind, out);
}

}  // namespace suite
