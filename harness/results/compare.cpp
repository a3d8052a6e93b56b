#include "harness/results/compare.hpp"
#include "harness/common/stats.hpp"
#include "harness/results/context_fields.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

#include "harness/results/text_table.hpp"

namespace suite {

namespace {

std::string fmt_value(double v) {
    char buf[32];
    if (v != 0 && (std::fabs(v) >= 1e6 || std::fabs(v) < 1e-2)) std::snprintf(buf, sizeof buf, "%.3e", v);
    else std::snprintf(buf, sizeof buf, v >= 100 ? "%.1f" : v >= 1 ? "%.2f" : "%.3g", v);
    return buf;
}

std::string fmt_ratio(double r) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3fx", r);
    return buf;
}

const Measure* find_measure(const LoadedPoint& p, const std::string& name) {
    for (const auto& m : p.measures)
        if (m.name == name) return &m;
    return nullptr;
}

// Performance of `other` relative to `first`: above 1 is better, whichever way the figure goes.
double performance_ratio(const Measure& first, const Measure& other) {
    if (first.best <= 0 || other.best <= 0) return NAN;
    return first.direction == Direction::higher_is_better ? other.best / first.best : first.best / other.best;
}

std::string file_tag(std::size_t i) { return "[" + std::to_string(i + 1) + "]"; }

}  // namespace

std::string render_comparison(const std::vector<ResultFile>& files, bool markdown) {
    const ResultFile& first = files.front();
    std::vector<std::map<PointKey, const LoadedPoint*>> index(files.size());
    for (std::size_t f = 0; f < files.size(); ++f)
        for (const auto& p : files[f].points) index[f][p.key] = &p;

    std::string out = markdown ? "## suite compare\n\n" : "";
    std::vector<const ResultFile*> ptrs;
    for (const auto& f : files) ptrs.push_back(&f);
    {
        TextTable t{{"file", "path", "machine", "date", "git", "points", "complete"}, {}, {}};
        for (std::size_t f = 0; f < files.size(); ++f)
            t.rows.push_back({file_tag(f), files[f].path, files[f].machine_label(), context_text(files[f].context, "date"),
                              context_text(files[f].context, "git_revision"), std::to_string(files[f].points.size()),
                              files[f].complete ? "yes" : "no (interrupted)"});
        out += markdown ? t.render_markdown() : t.render_text();
    }
    const auto diffs = context_differences(ptrs);
    out += markdown ? "\n### Context differences\n\n" : "\nContext differences that matter:\n";
    if (diffs.empty()) {
        out += "none: the same CPU, sockets, NUMA nodes, caches, memory, compiler and flags, instruction set, THP and governor\n";
    } else {
        TextTable t{{"field"}, {}, {}};
        for (std::size_t f = 0; f < files.size(); ++f) t.header.push_back(file_tag(f));
        for (const auto& [field, values] : diffs) {
            std::vector<std::string> row{field};
            row.insert(row.end(), values.begin(), values.end());
            t.rows.push_back(row);
        }
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
        for (std::size_t f = 1; f < files.size(); ++f) {
            auto it = index[f].find(p.key);
            anywhere = anywhere || (it != index[f].end() && find_measure(*it->second, head.name));
        }
        if (!anywhere) continue;
        ++common;
        const std::string kernel = p.key.variant.empty() ? p.key.kernel : p.key.kernel + "-" + p.key.variant;
        if (!logs.count(kernel)) {
            kernel_order.push_back(kernel);
            logs[kernel].resize(files.size());
        }
        std::vector<std::string> row{p.key.label(), head.name + " " + head.unit};
        for (std::size_t f = 0; f < files.size(); ++f) {
            auto it = index[f].find(p.key);
            const Measure* m = it == index[f].end() ? nullptr : find_measure(*it->second, head.name);
            if (!m) {
                row.insert(row.end(), f ? 3 : 2, "-");
                continue;
            }
            const std::string mark = it->second->verified ? "" : " !";
            unverified = unverified || !it->second->verified;
            row.push_back(fmt_value(m->best) + mark);
            row.push_back(fmt_value(m->median) + mark);
            if (f > 0) {
                const double r = performance_ratio(head, *m);
                row.push_back(std::isnan(r) ? "-" : fmt_ratio(r));
                if (!std::isnan(r)) logs[kernel][f].push_back(std::log(r));
            }
        }
        table.rows.push_back(row);
    }
    if (common == 0)
        throw InputError("no point of " + first.path + " is in any other file (points are matched by kernel, variant, pattern, size, "
                         "threads, pinning, placement and kernel parameters); run the same --kernel/--pattern/--sizes/--threads on each machine");
    std::size_t only_first = first.points.size() - common;
    out += markdown ? "\n### Points\n\n" : "\n";
    out += std::to_string(common) + " point(s) of [1] found in another file" +
           (only_first ? "; " + std::to_string(only_first) + " of [1] in no other file (not shown)" : "") + ".";
    for (std::size_t f = 1; f < files.size(); ++f) {
        std::size_t extra = 0;
        for (const auto& p : files[f].points)
            if (!index[0].count(p.key)) ++extra;
        if (extra) out += " " + std::to_string(extra) + " point(s) of " + file_tag(f) + " are not in [1].";
    }
    out += " \"vs [1]\": performance relative to [1] from the best figures, above 1 is better.\n";
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
            row.push_back(v.empty() ? "-" : fmt_ratio(std::exp(sum / static_cast<double>(v.size()))));
            row.push_back(std::to_string(v.size()));
        }
        geo.rows.push_back(row);
    }
    out += markdown ? "\n### Geometric mean per kernel\n\n" + geo.render_markdown() : "\nGeometric mean of the ratios to [1], per kernel:\n" + geo.render_text();
    for (const auto& f : files)
        for (const auto& note : f.notes) out += "note: " + note + "\n";
    return out;
}

}  // namespace suite
