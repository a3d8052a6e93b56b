#include "harness/cli_run.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <iostream>
#include <set>

#include "harness/context.hpp"
#include "harness/report.hpp"
#include "harness/units.hpp"

namespace suite {

namespace {

std::atomic<int> g_signal{0};

extern "C" void on_signal(int sig) { g_signal.store(sig); }

const std::vector<std::string> default_kernels = {"copy", "triad", "add", "sin-add", "latency"};

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
    return out;
}

Access parse_access(const std::string& text, const std::string& option) {
    Access a;
    if (text.rfind("strided", 0) == 0) {
        a.name = "strided";
        if (text.size() < 9 || text[7] != ':')
            throw UsageError("--" + option + "=" + text + ": strided needs a stride in elements, e.g. strided:8");
        std::string s = text.substr(8);
        if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }) || std::stoll(s) < 1)
            throw UsageError("--" + option + "=" + text + ": the stride must be a positive integer number of elements, e.g. strided:8");
        a.stride = std::stoull(s);
        return a;
    }
    a.name = text;
    return a;
}

// Checks that `dir` of `path` exists and is writable, and that `path` is not a directory.
void check_output_path(const std::string& path) {
    if (path.empty()) throw UsageError("--out needs a file name, e.g. --out=results/run.json");
    struct stat st{};
    if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        throw UsageError("--out=" + path + " is a directory; give a file name, e.g. " + path + "/run.json");
    auto slash = path.rfind('/');
    std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw UsageError("--out=" + path + ": the directory '" + dir + "' does not exist");
    // Create and remove a probe file: access(W_OK) says yes to root even where nothing can be
    // created (e.g. /proc), and the result file is written through a temporary file beside it.
    const std::string probe = path + ".probe." + std::to_string(getpid());
    int fd = open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw UsageError("--out=" + path + ": the directory '" + dir + "' is not writable (" + std::strerror(errno) + ")");
    close(fd);
    unlink(probe.c_str());
}

}  // namespace

std::vector<std::uint64_t> default_sizes(const Topology& topo) {
    const std::uint64_t llc = topo.last_level_cache_bytes();
    // Capped at 1 GiB so the default sweep stays short where a VM reports a huge LLC it does not
    // really give (ask for larger sizes with --size/--sizes).
    const std::uint64_t dram = std::clamp<std::uint64_t>(3 * 4 * llc, 64ULL << 20, 1ULL << 30);
    return {32ULL << 10, 1ULL << 20, dram};
}

void setup_run_options(CLI::App& app, RunOptions& o) {
    app.add_option("--kernel,-k", o.kernels, "kernels, comma separated (see ./suite list); default: the default sweep");
    app.add_option("--pattern,-p", o.patterns, "access patterns: sequential, random, strided:S (default: the kernel's first)");
    app.add_option("--ordering", o.orderings, "data orderings of application kernels: natural, random, morton, hilbert, rcm");
    app.add_option("--stores", o.stores, "default | nt (non-temporal stores; copy, scale, add, triad, sequential only)");
    app.add_option("--size", o.size, "footprint of all the kernel's arrays together, e.g. 64MiB");
    app.add_option("--sizes", o.sizes, "sizes: a sweep FROM:TO[:xF] (e.g. 16KiB:1GiB, 16KiB:1GiB:x1.5) or a list 32KiB,1MiB");
    app.add_option("--threads,-t", o.threads, "thread counts: 1,2,4 | 1-8 | 1-8:2 | all (default: 1 and all)");
    app.add_option("--pin", o.pin, "compact | scatter | none | a CPU list such as 0,2,4-7 (default: compact)");
    app.add_option("--placement", o.placement, "local | node:N | remote | interleave (default: local, first touch)");
    app.add_option("--reps", o.reps, "counted repetitions per point (default: enough for 0.2 s, at least 5; plus 1 warm-up)");
    app.add_option("--min-time", o.min_time, "seconds of counted repetitions per point when --reps is not given (default 0.2)");
    app.add_option("--seed", o.seed, "seed of the random permutations (default 1)");
    app.add_option("--out,-o", o.out, "write results to FILE (JSON, or CSV for *.csv or with --format=csv)");
    app.add_option("--format", o.format, "table | json | csv: format of --out, or of stdout without --out");
    app.add_flag("--quiet,-q", o.quiet, "no table or progress on the console");
    app.add_flag("--dry-run", o.dry_run, "check the options, list the points that would run, and stop");
}

Plan make_plan(const RunOptions& o, const Topology& topo) {
    Plan plan;
    plan.quiet = o.quiet;
    plan.dry_run = o.dry_run;

    // Kernels.
    std::vector<const KernelEntry*> ks;
    const bool default_sweep = o.kernels.empty();
    for (const auto& name : default_sweep ? default_kernels : split(o.kernels, ',')) {
        const KernelEntry* k = find_kernel(name);
        if (!k) {
            std::string hint = nearest(name, kernel_names());
            throw UsageError("unknown kernel '" + name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; kernels: " + join(kernel_names()) + " (see ./suite list)");
        }
        ks.push_back(k);
    }

    // Output.
    if (!o.format.empty() && o.format != "table" && o.format != "json" && o.format != "csv")
        throw UsageError("unknown --format '" + o.format + "'; accepted: table, json, csv");
    if (!o.out.empty()) {
        check_output_path(o.out);
        if (o.format == "table") throw UsageError("--format=table cannot be written to a file; use json or csv with --out");
        plan.out_path = o.out;
        const bool csv_name = o.out.size() > 4 && o.out.substr(o.out.size() - 4) == ".csv";
        plan.format = o.format.empty() ? (csv_name ? "csv" : "json") : o.format;
    } else {
        plan.format = o.format.empty() ? "table" : o.format;
    }

    // Threads, pinning, placement.
    const std::vector<int> threads =
        o.threads.empty() ? std::vector<int>{1, topo.pu_count()} : parse_thread_list(o.threads, topo.pu_count());
    std::vector<int> unique_threads;
    for (int t : threads)
        if (std::find(unique_threads.begin(), unique_threads.end(), t) == unique_threads.end()) unique_threads.push_back(t);
    plan.settings.pin = parse_pin(o.pin, topo);
    if (plan.settings.pin.mode == PinMode::list) {
        const int most = *std::max_element(unique_threads.begin(), unique_threads.end());
        if (static_cast<int>(plan.settings.pin.cpus.size()) < most)
            throw UsageError("--pin=" + o.pin + " lists " + std::to_string(plan.settings.pin.cpus.size()) + " CPU(s) but up to " +
                             std::to_string(most) + " threads were asked for; list at least one CPU per thread");
    }
    if (plan.settings.pin.mode != PinMode::none && !topo.this_system)
        throw UsageError("the topology is not this machine's (HWLOC_SYNTHETIC or HWLOC_XMLFILE is set), so threads cannot be pinned; use --pin=none");
    plan.settings.placement = parse_placement(o.placement, topo);
    if (plan.settings.placement.kind == PlacementKind::remote && plan.settings.pin.mode == PinMode::none)
        throw UsageError("--placement=remote needs pinned threads (the threads' node must be known); use --pin=compact or a CPU list");

    // Repetitions.
    if (o.reps == 0 || o.reps < -1) throw UsageError("--reps=" + std::to_string(o.reps) + ": at least 1 counted repetition is needed");
    if (o.reps > 10000000) throw UsageError("--reps=" + std::to_string(o.reps) + " is too many; at most 10000000");
    plan.settings.reps = o.reps > 0 ? o.reps : 0;
    if (!(o.min_time > 0) || o.min_time > 3600) throw UsageError("--min-time must be between 0 and 3600 seconds");
    plan.settings.min_time_s = o.min_time;
    plan.settings.seed = o.seed;
    plan.settings.stop = &g_signal;

    // Sizes.
    if (!o.size.empty() && !o.sizes.empty()) throw UsageError("--size and --sizes cannot be used together; give one of them");
    std::vector<std::uint64_t> sizes;
    if (!o.size.empty()) sizes = {parse_bytes(o.size)};
    else if (!o.sizes.empty()) sizes = parse_size_list(o.sizes);
    else sizes = default_sizes(topo);

    // Stores.
    if (o.stores != "default" && o.stores != "nt") throw UsageError("unknown --stores '" + o.stores + "'; accepted: default, nt");
    const std::string variant = o.stores == "nt" ? "nt" : "";

    // Patterns and orderings: each kernel takes the ones of its axis.
    const std::vector<std::string> given_patterns = o.patterns.empty() ? std::vector<std::string>{} : split(o.patterns, ',');
    const std::vector<std::string> given_orderings = o.orderings.empty() ? std::vector<std::string>{} : split(o.orderings, ',');
    for (const KernelEntry* k : ks) {
        const KernelInfo& info = k->info;
        const bool by_pattern = info.axis == AccessAxis::pattern;
        if (by_pattern && !given_orderings.empty())
            throw UsageError("kernel '" + info.name + "' takes --pattern, not --ordering (orderings are for application kernels)");
        if (!by_pattern && !given_patterns.empty())
            throw UsageError("kernel '" + info.name + "' takes --ordering, not --pattern");
        const auto& given = by_pattern ? given_patterns : given_orderings;
        std::vector<Access> accesses;
        if (given.empty()) {
            // The default sweep shows sequential against random where a kernel has both.
            if (default_sweep && info.name != "copy" && info.name != "triad" && info.accesses.size() > 1 && info.accesses[1] == "random")
                accesses = {{info.accesses[0], 0}, {info.accesses[1], 0}};
            else
                accesses = {{info.accesses.front(), 0}};
        }
        for (const auto& text : given) {
            Access a = parse_access(text, by_pattern ? "pattern" : "ordering");
            if (std::find(info.accesses.begin(), info.accesses.end(), a.name) == info.accesses.end()) {
                std::string hint = nearest(a.name, info.accesses);
                throw UsageError("kernel '" + info.name + "' has no " + (by_pattern ? "pattern" : "ordering") + " '" + text + "'" +
                                 (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; it accepts: " +
                                 join(info.accesses));
            }
            accesses.push_back(a);
        }
        if (!variant.empty()) {
            if (std::find(info.variants.begin(), info.variants.end(), variant) == info.variants.end())
                throw UsageError("--stores=nt: kernel '" + info.name + "' has no non-temporal-store variant; those that do: copy, scale, add, triad");
            for (const auto& a : accesses)
                if (a.name != "sequential")
                    throw UsageError("--stores=nt works with --pattern=sequential only, not '" + a.label() + "'");
        }
        for (const auto& a : accesses)
            for (std::uint64_t size : sizes)
                for (int t : unique_threads) {
                    const std::uint64_t least = k->min_size_per_thread * static_cast<std::uint64_t>(t);
                    if (info.size_kind == SizeKind::bytes && size < least)
                        throw UsageError("size " + format_bytes(size) + " is too small for kernel '" + info.name + "' with " +
                                         std::to_string(t) + " thread(s); use at least " + format_bytes(least));
                    if (a.name == "strided" && info.size_kind == SizeKind::bytes && a.stride * 8 * 4 > size)
                        throw UsageError("--pattern=" + a.label() + " needs a size of at least " + format_bytes(a.stride * 32) +
                                         " (a few elements per stride)");
                    plan.points.push_back({k, a, variant, size, t});
                }
    }

    // Memory: refuse before allocating anything.
    if (plan.settings.placement.kind != PlacementKind::remote) {
        MemoryPolicy policy;
        policy.kind = plan.settings.placement.kind;
        policy.node = plan.settings.placement.node;
        const std::uint64_t available = available_memory_bytes(policy);
        for (const auto& p : plan.points)
            if (p.kernel->info.size_kind == SizeKind::bytes && p.size > available)
                throw UsageError("size " + format_bytes(p.size) + " is larger than the memory available (" + format_bytes(available) +
                                 (policy.kind == PlacementKind::node ? " free on node " + std::to_string(policy.node) : "") + ")");
    }
    return plan;
}

int execute_plan(Plan& plan, const Topology& topo, const std::vector<std::string>& argv) {
    if (plan.dry_run) {
        std::cout << plan.points.size() << " point(s), pin=" << plan.settings.pin.text << ", placement=" << plan.settings.placement.text
                  << (plan.out_path.empty() ? "" : ", output " + plan.out_path + " (" + plan.format + ")") << "\n";
        for (const auto& p : plan.points)
            std::cout << "  " << display_name(p.kernel->info.name, p.variant) << " " << p.access.label() << " "
                      << (p.kernel->info.size_kind == SizeKind::bytes ? format_bytes(p.size) : std::to_string(p.size))
                      << " threads=" << p.threads << "\n";
        return 0;
    }
    struct sigaction sa{};
    sa.sa_handler = on_signal;
    sa.sa_flags = SA_RESETHAND;  // a second Ctrl-C ends the program at once; the file on disk stays valid
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);

    const bool table = plan.format == "table" || !plan.out_path.empty();
    const bool console_table = table && !plan.quiet;
    const bool progress = !plan.quiet && isatty(STDERR_FILENO);
    std::unique_ptr<ResultFile> file;
    if (!plan.out_path.empty())
        file = std::make_unique<ResultFile>(plan.out_path, plan.format == "csv" ? FileFormat::csv : FileFormat::json,
                                            build_context(topo, argv));
    // Without --out, json/csv go to stdout at the end (collected in a ResultFile-like buffer).
    std::vector<Record> records;

    if (console_table) std::cout << table_header() << std::flush;
    int status = 0;
    const std::size_t total = plan.points.size();
    for (std::size_t i = 0; i < total; ++i) {
        const Point& p = plan.points[i];
        if (progress) {
            std::fprintf(stderr, "\r[%zu/%zu] %s %s %s threads=%d ...", i + 1, total, display_name(p.kernel->info.name, p.variant).c_str(),
                         p.access.label().c_str(), format_bytes(p.size).c_str(), p.threads);
            std::fflush(stderr);
        }
        Record rec;
        try {
            rec = run_point(p, plan.settings, topo);
        } catch (const Interrupted&) {
            break;
        }
        if (progress) std::fprintf(stderr, "\r\033[K");
        if (!rec.verification.passed) {
            std::cerr << "suite: error: " << rec.name << " " << rec.access << " " << format_bytes(rec.size_requested)
                      << " failed verification: " << rec.verification.detail << "\n";
            status = 1;
        }
        if (console_table) std::cout << table_row(i + 1, total, rec) << std::flush;
        if (file) {
            file->add(rec);
            file->save(false);
        }
        records.push_back(std::move(rec));
        if (g_signal.load()) break;
    }
    if (progress) std::fprintf(stderr, "\r\033[K");
    const int sig = g_signal.load();
    if (file) {
        file->save(sig == 0);
        if (!plan.quiet) std::cerr << "wrote " << file->size() << " record(s) to " << file->path() << (sig ? " (incomplete: interrupted)" : "") << "\n";
    } else if (plan.format == "json" || plan.format == "csv") {
        ResultFile out("/dev/null", plan.format == "csv" ? FileFormat::csv : FileFormat::json, build_context(topo, argv));
        for (const auto& r : records) out.add(r);
        std::cout << out.render(sig == 0) << std::flush;
    }
    if (sig) {
        std::cerr << "suite: interrupted by signal " << sig << " after " << records.size() << " of " << total << " point(s)\n";
        return 128 + sig;
    }
    return status;
}

}  // namespace suite
