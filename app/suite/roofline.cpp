// `suite roofline`: this machine's ceilings, measured (harness/measure/roofline.hpp), as a table,
// a JSON file and a figure; and the points of a run placed on them (harness/results/
// roofline_place.hpp). Everything given is checked before anything is measured or written.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include <omp.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/defaults.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/plotter.hpp"
#include "harness/common/input_file.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/machine/team.hpp"
#include "harness/measure/roofline.hpp"
#include "harness/results/context.hpp"
#include "harness/results/history.hpp"
#include "harness/results/result_file.hpp"
#include "harness/results/roofline_place.hpp"
#include "rapl/energy.hpp"

namespace suite {
namespace roofline_command {
namespace {

const char* const footer = R"(
Examples:
  ./suite roofline                                        # 1 and all threads: the table, no file
  ./suite roofline --out=results/roofline.json            # and the JSON, and results/roofline.png
  ./suite roofline --threads=1,2,4 --out=roof.json
  ./suite roofline --place=results/latest.json --ceilings=results/roofline.json --out=placed.json
  ./suite roofline --place=run.json                       # measure the ceilings now, then place run.json

The ceilings: peak-flops at each instruction width the build targets (12 independent FMA chains a
thread, in registers), and per memory level the best STREAM-convention GB/s of load, copy, triad and
store (and their non-temporal forms in memory) at half of what the level holds for the threads; the
levels are those the cache probe measures. Placing a run: each point's flop/byte from its kernel's
declared flops and bytes, the level its footprint lives in, min(peak, intensity x level GB/s) there,
and the fraction of it the point reached. A run is placed only on its own machine's ceilings.
)";

// FILE.json -> FILE.png
std::string figure_path(const std::string& out) {
    const auto dot = out.rfind('.');
    const auto slash = out.rfind('/');
    const bool ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    return (ext ? out.substr(0, dot) : out) + ".png";
}

std::string directory_of(const std::string& path) {
    const auto slash = path.rfind('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace
}  // namespace roofline_command

int cmd_roofline(const std::vector<std::string>& args, const std::vector<std::string>& full_argv) {
    using namespace roofline_command;
    CLI::App app{
        "suite roofline: this machine's compute and bandwidth ceilings, measured, and a run's points placed on them"};
    app.footer(footer);
    app.get_formatter()->column_width(30);
    std::string threads_text = "1,all", out, place, ceilings, pin = pin_name(PinMode::compact), dram_size;
    double min_time = 0.2;
    bool no_probe = false, no_png = false;
    app.add_option("--threads,-t", threads_text, "thread counts: 1,2,4 | 1-8 | all (default 1,all)");
    app.add_option(
        "--out,-o", out,
        "JSON file to write: the ceilings, or with --place the placed points; the figure goes beside it as .png");
    app.add_option("--place", place, "a result file of this machine whose points are placed on the ceilings");
    app.add_option("--ceilings", ceilings,
                   "with --place: a roofline file written earlier by `suite roofline --out` (default: measure now)");
    app.add_option("--pin", pin, "how the threads are pinned: " + pin_forms() + " (default " + pin + ")");
    app.add_option(
        "--dram-size", dram_size,
        "footprint of the memory ceiling, e.g. 1GiB (default: the default sweep's memory size, 16x the last level)");
    app.add_option("--min-time", min_time, "seconds of repetitions per point (default 0.2)");
    app.add_flag("--no-probe", no_probe,
                 "take the cache sizes hwloc reports instead of measuring them (the probe takes seconds)");
    app.add_flag("--no-png", no_png, "write no figure");
    if (!parse_command_line(app, "suite roofline", args)) return 0;

    // Everything checked first.
    if (!ceilings.empty() && place.empty())
        throw UsageError("--ceilings=" + ceilings + " is read to place a run: give --place=RESULT.json too");
    if (!ceilings.empty())
        for (const char* measuring : {"--threads", "--pin", "--dram-size", "--min-time", "--no-probe"})
            if (app.count(measuring) > 0)
                throw UsageError(std::string(measuring) + " says how to measure the ceilings, and --ceilings=" +
                                 ceilings + " gives them measured: drop " + measuring + " or --ceilings");
    if (!out.empty() && !no_png && figure_path(out) == out)
        throw UsageError("--out=" + out + ": the JSON goes there and the figure beside it as FILE.png; give --out=" +
                         "a .json name (or --no-png)");
    if (!(min_time > 0 && min_time <= 60))
        throw UsageError("--min-time=" + format_number(min_time) + ": expected seconds between 0 and 60");
    const Topology topo = Topology::load();
    const Instruments instruments = make_instruments("none", "none", open_energy);
    const nlohmann::json context = build_context(topo, full_argv, instruments, bandwidth_convention());
    std::optional<RooflineFile> given;
    if (!ceilings.empty()) given = load_roofline_file(ceilings);
    nlohmann::json result;
    ResultFile file;
    if (!place.empty()) {
        const std::string text = read_input_file(place, "a result file of this machine (e.g. results/latest.json)");
        file = parse_result_text(text, place);  // checks it is a result, of this schema
        if (file.points.empty()) throw InputError(place + ": the result has no records to place");
        const std::string fp = given ? given->fingerprint : machine_fingerprint(context);
        if (machine_fingerprint(file.context) != fp)
            throw InputError(
                place + " was measured on " + file.machine_label() + ", not on " +
                (given ? given->path + "'s machine" : std::string("this machine")) +
                ": a point can only be placed on ceilings measured on its own machine; run `suite roofline` there");
        result = nlohmann::json::parse(text);
    }
    const std::uint64_t dram_bytes = dram_size.empty() ? 0 : parse_bytes(dram_size);
    if (!dram_size.empty() && dram_bytes < (1ULL << 20))
        throw UsageError("--dram-size=" + dram_size + ": expected at least 1MiB, e.g. 1GiB");
    // A memory footprint the caches hold measures a cache, not memory.
    const std::uint64_t last_level = topo.last_level_cache_total_bytes();
    if (!dram_size.empty() && dram_bytes <= last_level)
        throw UsageError("--dram-size=" + dram_size + ": the last-level cache holds " + format_bytes(last_level) +
                         " (as hwloc reports it); the memory ceiling needs more, e.g. " +
                         format_bytes(std::max<std::uint64_t>(4 * last_level, 1ULL << 20)));
    if (dram_bytes > 0) {
        const std::uint64_t have = available_memory_bytes(MemoryPolicy{});
        if (dram_bytes > have)
            throw UsageError("--dram-size=" + dram_size + " needs about " + format_bytes(dram_bytes) +
                             ", more than the " + format_bytes(have) +
                             " of memory available (or left by ulimit -v); give less");
    }
    std::vector<int> threads;
    if (!given) {
        threads = parse_thread_list(threads_text, topo.pu_count());
        if (*std::max_element(threads.begin(), threads.end()) > omp_get_thread_limit())
            throw UsageError("--threads=" + threads_text + ": OpenMP allows at most " +
                             std::to_string(omp_get_thread_limit()) + " threads (OMP_THREAD_LIMIT)");
    }
    const bool figure = !out.empty() && !no_png;
    if (figure) require_plotter("roofline.py", "--no-png");
    std::vector<FileIdentity> inputs = identify_inputs({place, ceilings});
    CommandFrame frame("suite");
    const OutputFile* output = out.empty() ? nullptr : &frame.claim_file(out, "--out", inputs);
    // The figure is an output like the JSON: claimed and checked against every input now.
    OutputFile figure_file;
    // (A placement on ceilings measured now draws none: they are not kept for the script.)
    if (figure && (place.empty() || given)) figure_file = OutputFile::claim(figure_path(out), "--out's figure", inputs);

    RooflineFile roof;
    if (given) {
        roof = *given;
    } else {
        RooflineOptions o = roofline_options();
        o.threads = threads;
        o.pin = parse_pin(topo.this_system ? pin : pin_name(PinMode::none), topo);
        o.min_time_s = min_time;
        o.dram_bytes = dram_bytes;
        o.probe = !no_probe;
        o.stop = frame.stop_flag();
        o.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
        std::fprintf(stderr, "suite roofline: measuring the ceilings at %s thread(s)%s\n", threads_text.c_str(),
                     no_probe ? "" : " (the caches probed first)");
        roof.roofline = measure_roofline(topo, o);
        roof.context = context;
        roof.context["caches_measured"] = roof.roofline.caches_measured;
        roof.fingerprint = machine_fingerprint(context);
        roof.path = out.empty() ? "(measured now)" : out;
        std::cout << render_roofline(roof.roofline);
    }
    const bool complete = roof.roofline.complete;
    nlohmann::json doc;
    if (!place.empty() && complete) {
        const Placement pl = place_points(roof, file, result);
        std::cout << "\n" << render_placement(pl);
        doc = to_json(pl, roof.path, place);
    } else {
        doc = {{"kind", roofline_kind},
               {"schema_version", roofline_schema_version},
               {"context", roof.context},
               {"fingerprint", roof.fingerprint}};
        doc.update(to_json(roof.roofline));
    }
    std::string done =
        std::to_string(roof.roofline.ceilings.size()) + " of " + std::to_string(threads.size()) + " thread count(s)";
    if (!output) return frame.finish(0, done, complete);
    const std::string wrote = output->write(doc.dump(2) + "\n", complete);
    if (wrote != out)
        std::fprintf(stderr,
                     "suite roofline: note: %s holds a complete roofline and is kept; this one, incomplete, is in %s\n",
                     out.c_str(), wrote.c_str());
    std::printf("\nwrote %s\n", wrote.c_str());
    if (figure && complete) {
        const Plotter p = find_plotter("roofline.py");
        std::vector<std::string> plot_args;
        if (!place.empty()) {
            // The figure needs the ceilings too: the given file, or this run's, beside the placement.
            if (given) plot_args = {given->path, "--place", out};
        } else {
            plot_args = {out};
        }
        if (!plot_args.empty()) {
            // Drawn beside, then written through the claimed figure like any output.
            const std::string drawn = directory_of(out) + "/.roofline-figure." + std::to_string(getpid()) + ".png";
            plot_args.insert(plot_args.end(), {"--out", drawn});
            std::string why = p.reason.empty() ? draw_with(p, plot_args, directory_of(out)) : p.reason;
            if (why.empty()) {
                const InputText png = read_regular_file(drawn, 1ULL << 30);
                if (png.ok && figure_file.claimed())
                    figure_file.write(png.text);
                else
                    why = drawn + ": " + png.reason;
            }
            unlink(drawn.c_str());
            if (why.empty())
                std::printf("wrote %s\n", figure_path(out).c_str());
            else
                std::fprintf(stderr, "suite roofline: no figure: %s\n", why.c_str());
        } else {
            std::fprintf(stderr,
                         "suite roofline: no figure of the placement: the ceilings were measured now and not kept; "
                         "give --ceilings=FILE for one\n");
        }
    }
    return frame.finish(0, done, complete);
}

}  // namespace suite
