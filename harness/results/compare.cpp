#include "harness/results/compare.hpp"
#include "harness/common/stats.hpp"
#include "harness/results/compare_figures.hpp"
#include "harness/results/context_fields.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

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

// A point run on every CPU the machine has ("--threads=all", or the same count given by
// number): two machines' "all threads" points are one comparable point whatever their counts.
// In an MPI run a rank's machine is its host, and the aggregate's is every host together.
bool on_all_threads(const ResultFile& f, const LoadedPoint& p) {
    if (p.key.threads <= 1) return false;
    if (f.mpi && p.mpi.scope != RankOrigin::Scope::none) {
        long pus = 0;
        for (const auto& h : f.mpi->hosts)
            if (p.mpi.scope == RankOrigin::Scope::aggregate || h.host == p.mpi.host) pus += h.pus;
        return pus == p.key.threads;
    }
    return context_text(f.context, "pus") == std::to_string(p.key.threads);
}

PointKey all_threads_key(PointKey k) {
    k.threads = -1;
    return k;
}

std::string file_tag(std::size_t i) { return "[" + std::to_string(i + 1) + "]"; }

// Why files share no point when they ran different numbers of processes ("" when they did not).
std::string process_mismatch(const std::vector<ResultFile>& files) {
    const int first = files.front().mpi ? files.front().mpi->ranks : 0;
    for (std::size_t f = 1; f < files.size(); ++f) {
        const int other = files[f].mpi ? files[f].mpi->ranks : 0;
        if (other == first || (other <= 1 && first <= 1)) continue;
        return "; [1] is a run of " + files.front().processes_label() + " and " + file_tag(f) + " of " +
               files[f].processes_label() +
               ": an MPI run's points are its ranks' and their aggregate, which meet only the same rank or the "
               "aggregate of a run "
               "of as many ranks (a plain run's points meet the aggregate of a run of one rank)";
    }
    return "";
}

}  // namespace

std::string render_comparison(const std::vector<ResultFile>& files, bool markdown, bool force) {
    const ResultFile& first = files.front();
    std::vector<std::map<PointKey, const LoadedPoint*>> index(files.size());
    // "All threads" points by a key without the count, for machines with different core counts.
    std::vector<std::map<PointKey, const LoadedPoint*>> all_index(files.size());
    for (std::size_t f = 0; f < files.size(); ++f)
        for (const auto& p : files[f].points) {
            index[f][matching_key(p.key)] = &p;
            if (on_all_threads(files[f], p)) all_index[f][all_threads_key(matching_key(p.key))] = &p;
        }
    // The point of file f that matches p of the first file: the same key, or both on all threads.
    auto match = [&](std::size_t f, const LoadedPoint& p) -> const LoadedPoint* {
        if (auto it = index[f].find(matching_key(p.key)); it != index[f].end()) return it->second;
        if (!on_all_threads(first, p)) return nullptr;
        auto it = all_index[f].find(all_threads_key(matching_key(p.key)));
        return it == all_index[f].end() ? nullptr : it->second;
    };

    std::string out = markdown ? "## suite compare\n\n" : "";
    std::vector<const ResultFile*> ptrs;
    for (const auto& f : files) ptrs.push_back(&f);
    {
        TextTable t{{"file", "path", "machine", "date", "git", "points", "complete"}, {}, {}};
        for (std::size_t f = 0; f < files.size(); ++f) {
            const std::string machine =
                files[f].machine_label() + (files[f].mpi ? ", " + files[f].processes_label() : "");
            t.rows.push_back({file_tag(f), files[f].path, machine, context_text(files[f].context, "date"),
                              context_text(files[f].context, "git_revision"), std::to_string(files[f].points.size()),
                              files[f].complete ? "yes" : "no (interrupted)"});
        }
        out += markdown ? t.render_markdown() : t.render_text();
    }
    const auto diffs = context_differences(ptrs);
    out += markdown ? "\n### Context differences\n\n" : "\nContext differences that matter:\n";
    if (diffs.empty()) {
        out +=
            "none: the same CPU, sockets, NUMA nodes, caches, memory, compiler and flags, build type, instruction set, "
            "THP, huge pages "
            "asked and governor\n";
    } else {
        TextTable t{{"field", "kind"}, {}, {}};
        for (std::size_t f = 0; f < files.size(); ++f) t.header.push_back(file_tag(f));
        std::string machine, setting;
        for (const auto& [field, values] : diffs) {
            const FieldKind kind = context_field_kind(field);
            std::vector<std::string> row{field, kind == FieldKind::machine   ? "machine"
                                                : kind == FieldKind::setting ? "build/setting"
                                                                             : "info"};
            row.insert(row.end(), values.begin(), values.end());
            t.rows.push_back(row);
            if (kind == FieldKind::machine) machine += (machine.empty() ? "" : ", ") + field;
            if (kind == FieldKind::setting) setting += (setting.empty() ? "" : ", ") + field;
        }
        // One comparison answers one question: these machines, or these settings on one machine.
        // When both changed, a ratio mixes two causes that nothing here can separate.
        if (!machine.empty() && !setting.empty() && !force)
            throw InputError(
                "the files differ both as machines (" + machine + ") and in how they were built or set up (" + setting +
                "), so a ratio cannot say which made the difference; compare like with like, or pass --force");
        out += markdown ? t.render_markdown() : t.render_text();
    }

    TextTable table{{"point", "figure"}, {}, {false, false}};
    for (std::size_t f = 0; f < files.size(); ++f) {
        table.header.push_back(file_tag(f) + " best");
        table.header.push_back(file_tag(f) + " median");
        table.right.insert(table.right.end(), {true, true});
        if (f > 0) {
            table.header.push_back("vs [1]");
            table.right.push_back(true);
        }
    }
    // Per kernel and file: the log-ratios, for the geometric mean.
    std::map<std::string, std::vector<std::vector<double>>> logs;
    std::vector<std::string> kernel_order;
    std::size_t common = 0;
    bool unverified = false;
    for (const auto& p : first.points) {
        if (p.measures.empty()) continue;
        const Measure& head = p.measures.front();
        bool anywhere = false;
        bool other_counts = false;  // matched as "all threads" on a machine of another core count
        for (std::size_t f = 1; f < files.size(); ++f) {
            const LoadedPoint* q = match(f, p);
            anywhere = anywhere || (q && find_measure(*q, head.name));
            other_counts = other_counts || (q && q->key.threads != p.key.threads);
        }
        if (!anywhere) continue;
        ++common;
        const std::string kernel = p.key.variant.empty() ? p.key.kernel : p.key.kernel + "-" + p.key.variant;
        if (!logs.count(kernel)) {
            kernel_order.push_back(kernel);
            logs[kernel].resize(files.size());
        }
        std::string label = p.key.label() + (p.mpi.host.empty() ? "" : " on " + p.mpi.host);
        if (other_counts) {
            std::string all_counts;  // "2 | 16"
            for (std::size_t f = 0; f < files.size(); ++f) {
                const LoadedPoint* q = f ? match(f, p) : &p;
                all_counts += (f ? " | " : "") + (q ? std::to_string(q->key.threads) : std::string("-"));
            }
            label += " (all threads: " + all_counts + ")";
        }
        std::vector<std::string> row{label, head.name + " " + head.unit};
        for (std::size_t f = 0; f < files.size(); ++f) {
            const LoadedPoint* q = f ? match(f, p) : &p;
            const Measure* m = q ? find_measure(*q, head.name) : nullptr;
            if (!m) {
                row.insert(row.end(), f ? 3 : 2, "-");
                continue;
            }
            const std::string mark = q->verified ? "" : " !";
            unverified = unverified || !q->verified;
            row.push_back(compare_value_text(m->best) + mark);
            row.push_back(compare_value_text(m->median) + mark);
            if (f > 0) {
                const Ratio r = median_ratio(head, *m);
                row.push_back(ratio_text(r));
                if (!std::isnan(r.value)) logs[kernel][f].push_back(std::log(r.value));
            }
        }
        table.rows.push_back(row);
    }
    if (common == 0)
        throw InputError("no point of " + first.path +
                         " is in any other file (points are matched by kernel, variant, pattern, size, "
                         "threads, pinning, placement, kernel parameters and MPI rank); run the same "
                         "--kernel/--pattern/--sizes/--threads on each machine" +
                         process_mismatch(files));
    std::size_t only_first = first.points.size() - common;
    out += markdown ? "\n### Points\n\n" : "\n";
    out += std::to_string(common) + " point(s) of [1] found in another file" +
           (only_first ? "; " + std::to_string(only_first) + " of [1] in no other file (not shown)" : "") + ".";
    for (std::size_t f = 1; f < files.size(); ++f) {
        std::size_t extra = 0;
        for (const auto& p : files[f].points)
            if (!index[0].count(matching_key(p.key)) &&
                !(on_all_threads(files[f], p) && all_index[0].count(all_threads_key(matching_key(p.key)))))
                ++extra;
        if (extra) out += " " + std::to_string(extra) + " point(s) of " + file_tag(f) + " are not in [1].";
    }
    out +=
        " \"vs [1]\": performance relative to [1] from the medians, above 1 is better, with a 95 % bootstrap interval"
        " [low, high] of that ratio where both files kept their repetitions.\n";
    if (!markdown) out += "\n";
    out += markdown ? "\n" + table.render_markdown() : table.render_text();
    if (unverified) out += "! failed verification in that file: not a valid result\n";

    TextTable geo{{"kernel"}, {}, {false}};
    for (std::size_t f = 1; f < files.size(); ++f) {
        geo.header.push_back(file_tag(f) + " vs [1]");
        geo.header.push_back("points");
        geo.right.insert(geo.right.end(), {true, true});
    }
    for (const auto& kernel : kernel_order) {
        std::vector<std::string> row{kernel};
        for (std::size_t f = 1; f < files.size(); ++f) {
            const auto& v = logs[kernel][f];
            double sum = 0;
            for (double x : v) sum += x;
            row.push_back(v.empty() ? "-" : compare_ratio_text(std::exp(sum / static_cast<double>(v.size()))));
            row.push_back(std::to_string(v.size()));
        }
        geo.rows.push_back(row);
    }
    out += markdown ? "\n### Geometric mean per kernel\n\n" + geo.render_markdown()
                    : "\nGeometric mean of the ratios to [1], per kernel:\n" + geo.render_text();
    for (const auto& f : files)
        for (const auto& note : f.notes) out += "note: " + note + "\n";
    return out;
}

}  // namespace suite
