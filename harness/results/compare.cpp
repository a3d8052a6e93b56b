#include "harness/results/compare.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "harness/common/stats.hpp"
#include "harness/results/compare_context.hpp"
#include "harness/results/compare_figures.hpp"
#include "harness/results/compare_match.hpp"
#include "harness/results/context_fields.hpp"
#include "harness/results/text_table.hpp"

namespace suite {

namespace {

// Performance of `other` relative to `first` from the medians: above 1 is better, whichever way
// the figure goes; with a 95 % bootstrap interval where both have repetitions (NAN otherwise).
struct Ratio {
    double value = NAN, low = NAN, high = NAN;
};
Ratio median_ratio(const Measure& first, const Measure& other) {
    Ratio r;
    if (first.median <= 0 || other.median <= 0) return r;
    const bool higher = first.direction == Direction::higher_is_better;
    r.value = performance_ratio(first.median, other.median, first.direction);
    if (first.samples.size() >= 2 && other.samples.size() >= 2) {
        // The interval of other/first; for a time-like figure performance is its inverse.
        const Interval iv = median_ratio_interval(first.samples, other.samples);
        r.low = higher ? iv.low : 1 / iv.high;
        r.high = higher ? iv.high : 1 / iv.low;
    }
    return r;
}

std::string ratio_text(const Ratio& r) {
    if (std::isnan(r.value)) return "-";
    std::string out = compare_ratio_text(r.value);
    if (!std::isnan(r.low)) {
        char buf[48];
        std::snprintf(buf, sizeof buf, " [%.3f, %.3f]", r.low, r.high);
        out += buf;
    }
    return out;
}

std::string file_tag(std::size_t i) { return "[" + std::to_string(i + 1) + "]"; }

// Why files share no point: they ran different numbers of processes, or their sizes came from
// other caches with no roles recorded to meet by.
std::string no_common_reason(const std::vector<ResultFile>& files) {
    const int first = files.front().mpi ? files.front().mpi->ranks : 0;
    for (std::size_t f = 1; f < files.size(); ++f) {
        const int other = files[f].mpi ? files[f].mpi->ranks : 0;
        if (other == first || (other <= 1 && first <= 1)) continue;
        return "; [1] is a run of " + files.front().processes_label() + " and " + file_tag(f) + " of " +
               files[f].processes_label() +
               ": an MPI run's points are its ranks' and their aggregate, which meet only the same rank or the "
               "aggregate of a run of as many ranks (a plain run's points meet the aggregate of a run of one rank)";
    }
    std::string without;
    for (std::size_t f = 0; f < files.size(); ++f)
        if (roles_of(files[f]).empty()) without += (without.empty() ? "" : ", ") + file_tag(f) + " " + files[f].path;
    if (!without.empty())
        return "; " + without +
               " record(s) no cache role to meet by when sizes differ (sizes given with --sizes, or a file written "
               "before roles)";
    return "";
}

// Geometric means of the ratios to [1], per group (kernel or role) and file.
struct Means {
    std::vector<std::string> order;
    std::map<std::string, std::vector<std::vector<double>>> logs;
    void add(const std::string& group, std::size_t files, std::size_t f, double ratio) {
        if (!logs.count(group)) {
            order.push_back(group);
            logs[group].resize(files);
        }
        if (!std::isnan(ratio)) logs[group][f].push_back(std::log(ratio));
    }
    std::string render(const std::string& what, std::size_t files, bool markdown) const {
        TextTable t{{what}, {}, {false}};
        for (std::size_t f = 1; f < files; ++f) {
            t.header.push_back(file_tag(f) + " vs [1]");
            t.header.push_back("points");
            t.right.insert(t.right.end(), {true, true});
        }
        for (const auto& group : order) {
            std::vector<std::string> row{group};
            for (std::size_t f = 1; f < files; ++f) {
                const auto& v = logs.at(group)[f];
                double sum = 0;
                for (double x : v) sum += x;
                row.push_back(v.empty() ? "-" : compare_ratio_text(std::exp(sum / static_cast<double>(v.size()))));
                row.push_back(std::to_string(v.size()));
            }
            t.rows.push_back(row);
        }
        return markdown ? "\n### Geometric mean per " + what + "\n\n" + t.render_markdown()
                        : "\nGeometric mean of the ratios to [1], per " + what + ":\n" + t.render_text();
    }
};

// The point's label, its size replaced by its role where the table compares by role.
std::string point_label(const LoadedPoint& p, bool by_role, const std::vector<int>& counts) {
    std::string label = p.key.label() + (p.mpi.host.empty() ? "" : " on " + p.mpi.host);
    if (by_role) {
        const std::string size = " " + p.key.size_label() + " ";
        if (auto at = label.find(size); at != std::string::npos)
            label.replace(at, size.size(), " " + p.role.name + " ");
    }
    bool other_counts = false;
    for (int c : counts) other_counts = other_counts || (c >= 0 && c != p.key.threads);
    if (other_counts) {
        std::string all_counts;  // "2 | 16"
        for (std::size_t f = 0; f < counts.size(); ++f)
            all_counts += (f ? " | " : "") + (counts[f] >= 0 ? std::to_string(counts[f]) : std::string("-"));
        label += " (all threads: " + all_counts + ")";
    }
    return label;
}

std::string files_table(const std::vector<ResultFile>& files, bool markdown) {
    TextTable t{{"file", "path", "machine", "date", "git", "points", "complete"}, {}, {}};
    for (std::size_t f = 0; f < files.size(); ++f) {
        const std::string machine = files[f].machine_label() + (files[f].mpi ? ", " + files[f].processes_label() : "");
        t.rows.push_back({file_tag(f), files[f].path, machine, context_text(files[f].context, "date"),
                          context_text(files[f].context, "git_revision"), std::to_string(files[f].points.size()),
                          files[f].complete ? "yes" : "no (interrupted)"});
    }
    return markdown ? t.render_markdown() : t.render_text();
}

}  // namespace

std::string render_comparison(const std::vector<ResultFile>& files, bool markdown, bool force) {
    const ResultFile& first = files.front();
    const PointMatcher matcher(files);
    std::string out = (markdown ? "## suite compare\n\n" : "") + files_table(files, markdown);
    out += render_context_differences(files, markdown, force);
    check_roles(files, force);

    // The rows: every point of [1] that another file has, with each file's point beside it.
    struct Row {
        const LoadedPoint* p;
        std::vector<Match> in;  // per file; [0] is p itself
        bool by_role = false;
    };
    std::vector<Row> rows;
    std::vector<std::set<const LoadedPoint*>> met(files.size());
    bool sizes_differ = false;
    for (const auto& p : first.points) {
        if (p.measures.empty()) continue;
        Row row{&p, {Match{&p, false}}, false};
        bool anywhere = false;
        for (std::size_t f = 1; f < files.size(); ++f) {
            row.in.push_back(matcher.match(f, p));
            const Match& m = row.in.back();
            anywhere = anywhere || (m.point && find_measure(*m.point, p.measures.front().name));
            row.by_role = row.by_role || m.by_role;
            if (m.point) met[f].insert(m.point);
        }
        if (!anywhere) continue;
        sizes_differ = sizes_differ || row.by_role;
        rows.push_back(row);
    }
    if (rows.empty())
        throw InputError("no point of " + first.path +
                         " is in any other file (points are matched by kernel, variant, pattern, size or cache role, "
                         "threads, pinning, placement, kernel parameters and MPI rank); run the same "
                         "--kernel/--pattern/--sizes/--threads on each machine" +
                         no_common_reason(files));

    TextTable table{{"point", "figure"}, {}, {false, false}};
    for (std::size_t f = 0; f < files.size(); ++f) {
        if (sizes_differ) table.header.push_back(file_tag(f) + " size");
        table.header.push_back(file_tag(f) + " best");
        table.header.push_back(file_tag(f) + " median");
        table.right.insert(table.right.end(), sizes_differ ? 3 : 2, true);
        if (f > 0) {
            table.header.push_back("vs [1]");
            table.right.push_back(true);
        }
    }
    Means kernels, roles;
    bool unverified = false;
    for (const auto& row : rows) {
        const LoadedPoint& p = *row.p;
        const Measure& head = p.measures.front();
        const std::string kernel = p.key.variant.empty() ? p.key.kernel : p.key.kernel + "-" + p.key.variant;
        std::vector<int> counts;
        for (const auto& m : row.in) counts.push_back(m.point ? m.point->key.threads : -1);
        std::vector<std::string> cells{point_label(p, sizes_differ && !p.role.name.empty(), counts),
                                       head.name + " " + head.unit};
        for (std::size_t f = 0; f < files.size(); ++f) {
            const LoadedPoint* q = row.in[f].point;
            const Measure* m = q ? find_measure(*q, head.name) : nullptr;
            if (!m) {
                cells.insert(cells.end(), (f ? 3 : 2) + (sizes_differ ? 1 : 0), "-");
                continue;
            }
            const std::string mark = q->verified ? "" : " !";
            unverified = unverified || !q->verified;
            if (sizes_differ) cells.push_back(q->key.size_label());
            cells.push_back(compare_value_text(m->best) + mark);
            cells.push_back(compare_value_text(m->median) + mark);
            if (f == 0) continue;
            const Ratio r = median_ratio(head, *m);
            cells.push_back(ratio_text(r));
            kernels.add(kernel, files.size(), f, r.value);
            if (!p.role.name.empty()) roles.add(p.role.name, files.size(), f, r.value);
        }
        table.rows.push_back(cells);
    }
    out += markdown ? "\n### Points\n\n" : "\n";
    const std::size_t only_first = first.points.size() - rows.size();
    out += std::to_string(rows.size()) + " point(s) of [1] found in another file" +
           (only_first ? "; " + std::to_string(only_first) + " of [1] in no other file (not shown)" : "") + ".";
    for (std::size_t f = 1; f < files.size(); ++f)
        if (const std::size_t extra = files[f].points.size() - met[f].size())
            out += " " + std::to_string(extra) + " point(s) of " + file_tag(f) + " are not in [1].";
    if (sizes_differ)
        out +=
            " Points of the default sweep whose sizes differ met by the cache they were sized from (L1/2: half "
            "an L1 per thread, L2/2, L3/2, DRAM); each file's size is beside its figure.";
    out +=
        " \"vs [1]\": performance relative to [1] from the medians, above 1 is better, with a 95 % bootstrap interval"
        " [low, high] of that ratio where both files kept their repetitions.\n";
    if (!markdown) out += "\n";
    out += markdown ? "\n" + table.render_markdown() : table.render_text();
    if (unverified) out += "! failed verification in that file: not a valid result\n";
    out += kernels.render("kernel", files.size(), markdown);
    if (!roles.order.empty()) out += roles.render("cache role", files.size(), markdown);
    for (const auto& f : files)
        for (const auto& note : f.notes) out += "note: " + note + "\n";
    return out;
}

}  // namespace suite
