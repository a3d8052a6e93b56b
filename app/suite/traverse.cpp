// `suite traverse`: how a loop over a mesh's elements walks it, per ordering and thread count.
// Writes, into --out=DIR, a .vtu per ordering and thread count with each element's visit index,
// owning thread and step within its thread's block; PNG snapshots of the loop at 0, 20, ...,
// 100 % (plots/traverse.py); and summary.json with the numbers that go under the figures
// (elements whose vertices are shared between threads, bandwidth, profile, vertex spread, and
// the fraction of elements sharing a key by depth).
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/plotter.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/units.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mesh/writers.hpp"
#include "kernels/sfc/orderings.hpp"
#include "kernels/sfc/pipeline.hpp"
#include "kernels/sfc/quality.hpp"

namespace suite {
namespace traverse_command {
namespace {

using namespace sfc;

const char* const footer = R"(
Examples:
  ./suite traverse --mesh=disk:refine=4 --out=traverse         # natural, morton, hilbert; 1 and 4 threads
  ./suite traverse --mesh=file:../shared/meshes/unit_circle.txt --ordering=natural,random,morton,hilbert,rcm --threads=1,4 --out=circle
  ./suite traverse --mesh=box:8,8,8 --ordering=natural,hilbert --threads=2 --no-png --out=box

In DIR: ORDERING-tT.vtu (cell data: visit = position in the loop, thread = owner under the static
split, step = position within the thread's block), ORDERING-tT-PPP.png after PPP % of the loop
(colour: visit order with one thread, owning thread with more), summary.json with the numbers.
)";

constexpr std::uint64_t max_traverse_elements = 4'000'000;

struct Options {
    std::string mesh = "disk:refine=4";
    std::string orderings = "natural,morton,hilbert";
    std::string threads = "1,4";
    std::string out;
    std::uint64_t seed = 1;
    std::string depth;  // "": the deepest; else a whole number checked once the mesh's dimension is known
    bool no_png = false;
    bool dry_run = false;
    bool replace = false;
};

}  // namespace
}  // namespace traverse_command

int cmd_traverse(const std::vector<std::string>& args) {
    using namespace traverse_command;
    CLI::App app{
        "suite traverse: the order in which a loop over a mesh visits its elements, per ordering and thread count"};
    app.footer("Orderings:\n" + mesh_orderings().listed() + footer);
    app.get_formatter()->column_width(28);
    Options o;
    app.add_option("--mesh", o.mesh,
                   "disk:refine=K | box:NX,NY,NZ[:refine=K] | file:PATH[:refine=K] (default disk:refine=4)");
    app.add_option("--ordering", o.orderings,
                   "one or more of " + mesh_orderings().accepted() + " (default " + Options{}.orderings + "; below)");
    app.add_option("--threads,-t", o.threads, "how many static blocks the loop is split into: 1,4 | 1-8 (default 1,4)");
    app.add_option("--out,-o", o.out, "directory for the files (created if missing)");
    add_seed_option(app, o.seed, "seed of the random ordering, 0 to 18446744073709551615 (default 1)");
    app.add_option("--depth", o.depth,
                   "key depth in bits per axis, from 1 (default: the most a 64-bit key holds, 32 in 2D, 21 in 3D)")
        ->type_name("UINT");
    app.add_flag("--no-png", o.no_png, "write the .vtu files and numbers only");
    app.add_flag("--replace", o.replace, "replace the files of an earlier run in --out (refused without it)");
    app.add_flag("--dry-run", o.dry_run,
                 "check the options (and read the mesh file), list what would be written, and stop");
    if (!parse_command_line(app, "suite traverse", args)) return 0;

    // Everything is checked before anything is built or written.
    const mesh::MeshSpec spec = mesh::parse_mesh_spec(o.mesh);
    const mesh::MeshCounts counts = mesh::mesh_counts(spec);
    if (counts.elements > max_traverse_elements)
        throw UsageError("--mesh=" + o.mesh + " has " + std::to_string(counts.elements) +
                         " elements; traverse writes every element to .vtu files, so at most " +
                         std::to_string(max_traverse_elements));
    const std::vector<std::string> orderings = parse_name_list(o.orderings, "--ordering");
    for (const auto& name : orderings) mesh_orderings().at(name);
    if (o.threads == "all")
        throw UsageError(
            "--threads=all: traverse splits the loop into the blocks of the thread counts given, e.g. --threads=1,4");
    // Thread counts here are the blocks of a static split, not this machine's processing units.
    const std::vector<int> threads =
        parse_thread_list(o.threads, 1024, "traverse splits the loop into 1 to 1024 static blocks");
    const int deepest = max_depth(counts.dim);
    const int depth =
        o.depth.empty()
            ? deepest
            : static_cast<int>(parse_whole(o.depth, "--depth", 1, static_cast<std::uint64_t>(deepest),
                                           "the key depth in bits per axis, at most " + std::to_string(deepest) +
                                               " in " + std::to_string(counts.dim) + "D"));
    if (!o.no_png) require_plotter("traverse.py", "--no-png");
    if (o.out.empty())
        throw UsageError("traverse needs --out=DIR, the directory for its .vtu, .png and summary.json files");
    const std::vector<FileIdentity> inputs =
        identify_inputs({spec.kind == mesh::MeshSpec::Kind::file ? spec.path : ""});
    const DirPolicy policy{
        .option = "--out", .command = "suite traverse", .inputs = inputs, .replace_earlier = o.replace};
    if (o.dry_run) {
        OutputDir::check(o.out, policy);
        std::printf("mesh %s: %llu %s; into %s: %zu .vtu file(s)%s and summary.json\n", o.mesh.c_str(),
                    static_cast<unsigned long long>(counts.elements), mesh::element_word(counts.dim, true).c_str(),
                    o.out.c_str(), orderings.size() * threads.size(), o.no_png ? "" : ", 6 .png snapshots each");
        for (const auto& name : orderings)
            for (int t : threads) std::printf("  %s-t%d.vtu\n", name.c_str(), t);
        return 0;
    }
    CommandFrame frame("suite");
    OutputDir& out = frame.claim_dir(o.out, policy);

    const mesh::Mesh base = mesh::load_mesh(spec);
    nlohmann::json summary = {{"mesh", o.mesh},
                              {"dim", base.dim},
                              {"elements", base.elements()},
                              {"vertices", base.vertices()},
                              {"depth", depth},
                              {"seed", o.seed},
                              {"threads", threads},
                              {"complete", false},
                              {"orderings", nlohmann::json::array()}};
    std::printf("mesh %s: %zu %s, %zu vertices\n\n", o.mesh.c_str(), base.elements(),
                mesh::element_word(base.dim, true).c_str(), base.vertices());
    std::printf("%-17s %10s %14s %12s %11s   elements with vertices shared between threads\n", "ordering", "bandwidth",
                "profile", "spread-mean", "spread-p95");
    std::size_t done = 0;
    for (const auto& name : orderings) {
        if (frame.stop_requested()) break;  // the safe point: between orderings
        const mesh::Mesh m = ordered(base, name, o.seed, depth);
        const OrderingQuality q = ordering_quality(m);
        nlohmann::json entry = {{"ordering", name},           {"bandwidth", q.bandwidth},
                                {"profile", q.profile},       {"spread_mean", q.spread_mean},
                                {"spread_p95", q.spread_p95}, {"threads", nlohmann::json::array()}};
        std::string shared_text;
        for (int t : threads) {
            const ThreadSharing s = thread_sharing(m.view(), t);
            Traversal walk = traversal(m.elements(), t);
            const std::string file = name + "-t" + std::to_string(t) + ".vtu";
            out.write(file, mesh::vtu_text(m, {{"visit", std::move(walk.visit)},
                                               {"thread", std::move(walk.thread)},
                                               {"step", std::move(walk.step)}}));
            const double fraction = static_cast<double>(s.elements) / static_cast<double>(m.elements());
            entry["threads"].push_back({{"threads", t},
                                        {"shared_elements", s.elements},
                                        {"shared_fraction", fraction},
                                        {"shared_vertices", s.vertices},
                                        {"vtu", file}});
            char buf[96];
            std::snprintf(buf, sizeof buf, "%st=%d: %llu (%.1f%%)", shared_text.empty() ? "" : ", ", t,
                          static_cast<unsigned long long>(s.elements), 100 * fraction);
            shared_text += buf;
        }
        std::printf("%-17s %10llu %14llu %12.1f %11llu   %s\n", name.c_str(),
                    static_cast<unsigned long long>(q.bandwidth), static_cast<unsigned long long>(q.profile),
                    q.spread_mean, static_cast<unsigned long long>(q.spread_p95), shared_text.c_str());
        summary["orderings"].push_back(entry);
        if (++done < orderings.size())
            out.write("summary.json", summary.dump(1) + "\n");  // kept if the next is interrupted
    }
    const std::string finished = std::to_string(done) + " of " + std::to_string(orderings.size()) + " ordering(s)";
    if (done < orderings.size()) {
        out.write("summary.json", summary.dump(1) + "\n");
        std::printf("\nwrote %s (%s, incomplete: interrupted)\n", o.out.c_str(), finished.c_str());
        return frame.finish(0, finished, false);
    }
    summary["complete"] = true;
    // Keys at depth d name cells of the same grid whatever the curve, so one curve gives the
    // fraction for all (the tests check that Morton and Hilbert agree).
    const std::vector<double> shared = shared_key_fraction(base.view(), Curve::morton);
    summary["shared_key_fraction"] = shared;
    std::printf(
        "\nelements that share their key with another at depth d (the thesis's relative error; the same for every "
        "curve):\n ");
    for (std::size_t d = 0; d < shared.size(); ++d) {
        std::printf(" d%zu=%.3f", d + 1, shared[d]);
        if (shared[d] == 0) break;  // deeper levels only split cells further
    }
    std::printf("\n");
    out.write("summary.json", summary.dump(1) + "\n");
    if (o.no_png) {
        summary["png"] = {{"available", false}, {"reason", "--no-png"}};
    } else {
        const Plotter p = find_plotter("traverse.py");
        const std::string why =
            p.reason.empty() ? out.with_writer([&p](const std::string& dir) { return draw(p, dir); }) : p.reason;
        if (why.empty()) {
            summary["png"] = {
                {"available", true}, {"percent", {0, 20, 40, 60, 80, 100}}, {"pattern", "ORDERING-tT-PPP.png"}};
        } else {
            summary["png"] = {{"available", false}, {"reason", why}};
            std::cerr << "suite: note: no PNG snapshots: " << why << "\n";
        }
    }
    out.write("summary.json", summary.dump(1) + "\n");
    std::printf("\nwrote %s (.vtu per ordering and thread count%s, summary.json)\n", o.out.c_str(),
                summary["png"]["available"].get<bool>() ? ", .png snapshots" : "");
    return frame.finish(0, finished, true);
}

}  // namespace suite
