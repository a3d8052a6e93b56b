#include "harness/results/check.hpp"
#include "harness/common/stats.hpp"
#include "harness/results/context_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

#include "harness/results/report.hpp"
#include "harness/results/text_table.hpp"

namespace suite {

namespace {

std::string pct(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", x * 100);
    return buf;
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, (v != 0 && (std::fabs(v) >= 1e6 || std::fabs(v) < 1e-2)) ? "%.4e" : "%.4g", v);
    return buf;
}

const char* verdict_word(Verdict v) {
    switch (v) {
        case Verdict::regressed:
            return "REGRESSED";
        case Verdict::improved:
            return "improved";
        case Verdict::inconclusive:
            return "inconclusive";
        case Verdict::unchanged:
            break;
    }
    return "unchanged";
}

// A failed verification has no figures to show; an inconclusive finding shows them.
bool shows_values(const Finding& f) { return f.note != "failed verification"; }

// The change of the figure itself, signed: "-62.0%" for a bandwidth that fell by 62 %, "+25.0%"
// for a latency that rose by a quarter (whether that is worse follows from the figure's direction
// and the verdict). "worse by (baseline/run - 1)" printed a 62 % drop as "162 % worse".
std::string signed_pct(double x) { return (x >= 0 ? "+" : "") + pct(x); }

// ...with the 95 % interval of the change where the repetitions gave one: "-12.0% [-15.1%, -9.0%]".
std::string change_text(const Finding& f) {
    if (f.note == "failed verification") return "failed verification";
    if (f.baseline == 0) return f.run == 0 ? "+0.0%" : "was 0";
    std::string out = signed_pct(f.run / f.baseline - 1);
    if (std::isfinite(f.ratio_low) && std::isfinite(f.ratio_high))
        out += " [" + signed_pct(f.ratio_low - 1) + ", " + signed_pct(f.ratio_high - 1) + "]";
    return out;
}

std::string p_text(const Finding& f) { return f.tested ? num(f.p) : "-"; }

// The point as the report names it: with its host where it is one rank of an MPI run.
std::string finding_label(const Finding& f) { return f.key.label() + (f.host.empty() ? "" : " on " + f.host); }

// Why a run shares no point with its baseline when they ran different numbers of processes.
std::string processes_differ(const ResultFile& base, const ResultFile& run) {
    const int b = base.mpi ? base.mpi->ranks : 1, r = run.mpi ? run.mpi->ranks : 1;
    if (b == r) return "";
    return "; the baseline is a run of " + base.processes_label() + " and the run of " + run.processes_label() +
           ": MPI ranks and aggregates meet only the same rank or the aggregate of a run of as many ranks";
}

std::string rule_text(const GateRule& r) {
    return "a change counts beyond " + pct(r.tolerance) + " when the repetitions tell the runs apart at p < " +
           num(r.alpha) + "; without repetitions, beyond " + pct(r.tolerance) + " plus the runs' spread";
}

std::string report_rule(const CheckReport& rep) { return rep.rule_text.empty() ? rule_text(rep.rule) : rep.rule_text; }

// The band of the runs' medians a finding was held against: "[12.1, 14.3] of 9 runs"; "-" without one.
std::string band_text(const Finding& f) {
    if (!std::isfinite(f.band_low)) return "-";
    return "[" + num(f.band_low) + ", " + num(f.band_high) + "] of " + std::to_string(f.band_runs) + " runs";
}

// The regressions, then the improvements, then the inconclusive figures; a column of the runs'
// band where any finding was held against one (history check).
TextTable findings_table(const CheckReport& rep, bool markdown, std::size_t max_rows = SIZE_MAX,
                         bool with_inconclusive = true) {
    bool banded = false;
    for (const auto& f : rep.findings) banded = banded || std::isfinite(f.band_low);
    TextTable t{{"", "point", "figure (median)", "baseline", "run", "change [95% interval]", "p", "allowed"},
                {},
                {false, false, false, true, true, true, true, true}};
    if (banded) {
        t.header.push_back("runs' band");
        t.right.push_back(true);
    }
    for (Verdict v : {Verdict::regressed, Verdict::improved, Verdict::inconclusive}) {
        if (v == Verdict::inconclusive && !with_inconclusive) break;
        for (const auto& f : rep.findings) {
            if (f.verdict != v || t.rows.size() >= max_rows) continue;
            const std::string label = markdown ? "`" + finding_label(f) + "`" : finding_label(f);
            t.rows.push_back({verdict_word(v), label, f.figure, shows_values(f) ? num(f.baseline) : "-",
                              shows_values(f) ? num(f.run) : "-", change_text(f), p_text(f),
                              shows_values(f) ? pct(f.allowed) : "-"});
            if (banded) t.rows.back().push_back(band_text(f));
        }
    }
    return t;
}

}  // namespace

std::size_t CheckReport::count(Verdict v) const {
    std::size_t n = 0;
    for (const auto& f : findings) n += f.verdict == v;
    return n;
}

Finding judge(const Measure& b, const Measure& r, const GateRule& rule) {
    Finding f;
    f.figure = b.name + " " + b.unit;
    f.direction = b.direction;
    f.baseline = b.median;
    f.run = r.median;
    // How many times worse the run is (above 1: worse), the same way for both directions.
    const bool lower_better = b.direction == Direction::lower_is_better;
    const double bad = lower_better ? r.median : b.median;
    const double good = lower_better ? b.median : r.median;
    double factor;
    if (good > 0)
        factor = bad / good;
    else
        factor = bad > 0 ? INFINITY : 1.0;  // 0 -> 0 is no change; 0 misses -> some is worse
    f.worse_by = factor - 1;
    // A count of a few events a repetition moves by whole events: no ratio of it means anything.
    if (std::isfinite(b.count_per_call) && std::isfinite(r.count_per_call) &&
        std::max(b.count_per_call, r.count_per_call) < rule.min_count) {
        f.allowed = rule.tolerance;
        f.note = "fewer than " + num(rule.min_count) + " events a repetition in both runs: not gated by ratio";
        return f;
    }
    // The minimum effect applies to the change as printed (the figure's own, signed), so that
    // "-9.3%" is never a regression at a tolerance of 10 %: for a rate a fall is worse, for a
    // time or a count a rise.
    double change;
    if (b.median > 0)
        change = r.median / b.median - 1;
    else
        change = r.median > 0 ? INFINITY : 0.0;
    const double worse_change = lower_better ? change : -change;  // above 0: worse
    const bool beyond_worse = worse_change > rule.tolerance, beyond_better = worse_change < -rule.tolerance;
    if (b.samples.size() >= 2 && r.samples.size() >= 2) {
        f.allowed = rule.tolerance;
        f.tested = true;
        const RankTest t = mann_whitney(r.samples, b.samples);
        // "run smaller" is worse for a rate, better for a time or a count.
        const double p_worse = lower_better ? t.p_x_larger : t.p_x_smaller,
                     p_better = lower_better ? t.p_x_smaller : t.p_x_larger;
        f.p = worse_change >= 0 ? p_worse : p_better;
        if (b.median > 0) {
            const Interval iv = median_ratio_interval(b.samples, r.samples);
            f.ratio_low = iv.low;
            f.ratio_high = iv.high;
        }
        if (!beyond_worse && !beyond_better) return f;
        if (f.p < rule.alpha) {
            f.verdict = beyond_worse ? Verdict::regressed : Verdict::improved;
        } else {
            f.verdict = Verdict::inconclusive;
            f.note = "a change beyond " + pct(rule.tolerance) +
                     " that the repetitions cannot tell from noise (Mann-Whitney p = " + num(f.p) + ", " +
                     std::to_string(b.samples.size()) + " against " + std::to_string(r.samples.size()) +
                     " repetitions; significant below " + num(rule.alpha) + ")";
        }
        return f;
    }
    f.allowed = rule.tolerance + std::sqrt(b.noise * b.noise + r.noise * r.noise);
    if (worse_change > f.allowed)
        f.verdict = Verdict::regressed;
    else if (worse_change < -f.allowed)
        f.verdict = Verdict::improved;
    return f;
}

CheckReport check_run(const ResultFile& base, const ResultFile& run, const GateRule& rule, bool force) {
    CheckReport rep;
    rep.baseline_path = base.path;
    rep.run_path = run.path;
    rep.rule = rule;
    std::map<PointKey, const LoadedPoint*> in_base, in_run;
    // An MPI run's ranks and aggregate are points of their own (a slow rank fails the gate even
    // where the aggregate hides it); the aggregate of one rank meets a plain run's point.
    for (const auto& p : base.points) in_base[matching_key(p.key)] = &p;
    for (const auto& p : run.points) in_run[matching_key(p.key)] = &p;
    // A gate compares one configuration over time: another machine or another build or setting
    // makes every point a different experiment, so that is refused unless asked for.
    std::string refused;
    for (const auto& [field, values] : context_differences({&base, &run})) {
        const std::string said = field + " '" + values[0] + "' -> '" + values[1] + "'";
        if (context_field_kind(field) == FieldKind::informational) {
            rep.notes.push_back("the context differs from the baseline's: " + said +
                                "; differences may come from that");
            continue;
        }
        refused += (refused.empty() ? "" : ", ") + said;
        if (force) rep.notes.push_back("the context differs from the baseline's (compared anyway, --force): " + said);
    }
    if (!refused.empty() && !force)
        throw InputError("the run is not comparable with the baseline " + base.path + ": " + refused +
                         "; gate against a baseline of the same machine and build, or pass --force to compare anyway");
    for (const auto& p : base.points)
        if (!in_run.count(matching_key(p.key))) rep.missing_from_run.push_back(p.key);
    for (const auto& p : run.points) {
        auto it = in_base.find(matching_key(p.key));
        if (it == in_base.end()) {
            rep.not_in_baseline.push_back(p.key);
            continue;
        }
        const LoadedPoint& b = *it->second;
        ++rep.points_compared;
        if (!b.verified) {
            rep.notes.push_back(p.key.label() + ": the baseline failed verification there; not gated");
            continue;
        }
        if (!p.verified) {
            Finding f;
            f.key = p.key;
            f.host = p.mpi.host;
            f.figure = "verification";
            f.verdict = Verdict::regressed;
            f.note = "failed verification";
            rep.findings.push_back(f);
            continue;
        }
        bool any = false;
        for (const auto& bm : b.measures)
            for (const auto& rm : p.measures)
                if (bm.name == rm.name && bm.unit == rm.unit) {
                    Finding f = judge(bm, rm, rule);
                    f.key = p.key;
                    f.host = p.mpi.host;
                    // callgrind's counts are exact: no noise can make them inconclusive.
                    const bool timed = bm.name.rfind("callgrind", 0) != 0;
                    if (timed && (b.unstable || p.unstable)) {
                        f.verdict = Verdict::inconclusive;
                        f.note = std::string(b.unstable ? "unstable in the baseline: " + b.unstable_why : "") +
                                 (b.unstable && p.unstable ? "; " : "") +
                                 (p.unstable ? "unstable in the run: " + p.unstable_why : "");
                    }
                    rep.findings.push_back(f);
                    any = true;
                }
        if (!any)
            rep.notes.push_back(p.key.label() +
                                ": no figure in both files (e.g. one was measured under callgrind); not gated");
    }
    if (rep.points_compared == 0)
        throw InputError("none of the " + std::to_string(run.points.size()) + " point(s) of " + run.path +
                         " is in the baseline " + base.path +
                         " (points are matched by kernel, variant, pattern, size, threads, pinning, placement, kernel "
                         "parameters and MPI rank); "
                         "run the baseline's configuration" +
                         processes_differ(base, run));
    if (rep.findings.empty())
        throw InputError(run.path + " and the baseline " + base.path +
                         " have points in common but no figure to compare in any of them");
    return rep;
}

std::string render_check_text(const CheckReport& rep) {
    std::string out =
        "suite check: " + rep.run_path + " against the baseline " + rep.baseline_path + " (" + report_rule(rep) + ")\n";
    for (const auto& n : rep.notes) out += "note: " + n + "\n";
    TextTable t = findings_table(rep, false);
    if (!t.rows.empty()) out += t.render_text();
    std::set<PointKey> said;  // a point's reasons once, however many of its figures were inconclusive
    for (const auto& f : rep.findings)
        if (f.verdict == Verdict::inconclusive && said.insert(f.key).second)
            out += "inconclusive: " + finding_label(f) + ": " + f.note + "\n";
    out += std::to_string(rep.points_compared) + " point(s) compared, " + std::to_string(rep.findings.size()) +
           " figure(s): " + std::to_string(rep.count(Verdict::regressed)) + " regressed, " +
           std::to_string(rep.count(Verdict::improved)) + " improved, " +
           std::to_string(rep.count(Verdict::unchanged)) + " within the threshold, " +
           std::to_string(rep.count(Verdict::inconclusive)) +
           " inconclusive (unstable points, or changes the repetitions cannot tell from noise; not gated).\n";
    if (!rep.missing_from_run.empty()) {
        out += std::to_string(rep.missing_from_run.size()) + " point(s) of the baseline are missing from the run:";
        for (const auto& k : rep.missing_from_run) out += " [" + k.label() + "]";
        out += "\n";
    }
    if (!rep.not_in_baseline.empty())
        out +=
            std::to_string(rep.not_in_baseline.size()) + " point(s) of the run are not in the baseline (not gated).\n";
    return out;
}

std::string render_check_markdown(const CheckReport& rep) {
    const std::size_t bad = rep.count(Verdict::regressed), good = rep.count(Verdict::improved);
    const std::size_t unsure = rep.count(Verdict::inconclusive);
    std::string out =
        "### suite check: " + std::string(bad ? "**" + std::to_string(bad) + " regression(s)**" : "no regression") +
        (good ? ", " + std::to_string(good) + " improvement(s)" : "") +
        (unsure ? ", " + std::to_string(unsure) + " inconclusive" : "") + "\n\n";
    out += "Run `" + rep.run_path + "` against the baseline `" + rep.baseline_path +
           "`: " + std::to_string(rep.points_compared) + " point(s), " + std::to_string(rep.findings.size()) +
           " figure(s) compared; " + report_rule(rep) + ".\n\n";
    TextTable t = findings_table(rep, true);
    if (!t.rows.empty()) out += t.render_markdown() + "\n";
    for (const auto& n : rep.notes) out += "- " + n + "\n";
    if (!rep.missing_from_run.empty())
        out +=
            "- " + std::to_string(rep.missing_from_run.size()) + " point(s) of the baseline are missing from the run\n";
    if (!rep.not_in_baseline.empty())
        out += "- " + std::to_string(rep.not_in_baseline.size()) +
               " point(s) of the run are not in the baseline (not gated)\n";
    return out;
}

std::string render_check_summary_markdown(const CheckReport& rep, const std::vector<std::string>& steps) {
    constexpr std::size_t max_rows = 10, max_steps = 5;
    const std::size_t bad = rep.count(Verdict::regressed), good = rep.count(Verdict::improved);
    std::string out = "### suite history check: " +
                      std::string(bad ? "**" + std::to_string(bad) + " regression(s)**" : "no regression") +
                      (good ? ", " + std::to_string(good) + " improvement(s)" : "") + "\n\n";
    out += "`" + rep.run_path + "` against " + rep.baseline_path + ": " + report_rule(rep) + ".\n\n";
    const TextTable t = findings_table(rep, true, max_rows, false);
    if (!t.rows.empty()) {
        out += t.render_markdown();
        if (bad + good > max_rows)
            out += "\n" + std::to_string(bad + good - max_rows) + " more changed figure(s): see the job's log.\n";
        out += "\n";
    }
    out += "- " + std::to_string(rep.points_compared) + " point(s), " + std::to_string(rep.findings.size()) +
           " figure(s): " + std::to_string(rep.count(Verdict::unchanged)) + " unchanged, " +
           std::to_string(rep.count(Verdict::inconclusive)) +
           " inconclusive (unstable points, or changes the repetitions cannot tell from noise; not gated)\n";
    if (!rep.notes.empty())
        out += "- " + std::to_string(rep.notes.size()) + " note(s) in the job's log; the first: " + rep.notes.front() +
               "\n";
    if (!rep.missing_from_run.empty() || !rep.not_in_baseline.empty())
        out += "- " + std::to_string(rep.missing_from_run.size()) + " point(s) of the history missing from the run, " +
               std::to_string(rep.not_in_baseline.size()) + " point(s) of the run without history (not gated)\n";
    out +=
        "- " + std::to_string(steps.size()) + " step(s) in this machine's history" + (steps.empty() ? "" : ":") + "\n";
    for (std::size_t i = 0; i < steps.size() && i < max_steps; ++i) out += "  - " + steps[i] + "\n";
    if (steps.size() > max_steps)
        out += "  - and " + std::to_string(steps.size() - max_steps) + " more (./suite history steps)\n";
    return out;
}

namespace {

// The whole of `text` as a finite number, or NAN.
double whole_number_text(const std::string& text) {
    std::size_t used = 0;
    double v = NAN;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        return NAN;
    }
    return used == text.size() && std::isfinite(v) ? v : NAN;
}

}  // namespace

double parse_alpha(const std::string& text) {
    const double v = whole_number_text(text);
    if (!(v > 0 && v <= 0.5))
        throw UsageError("--alpha='" + text +
                         "': give the test's significance level, a probability in (0, 0.5], e.g. --alpha=0.01");
    return v;
}

double parse_tolerance(const std::string& text) {
    std::string t = text;
    if (!t.empty() && t.back() == '%') t.pop_back();
    const double v = whole_number_text(t);
    if (!(v >= 0 && v <= 1000))
        throw UsageError("--tolerance='" + text +
                         "': give a percentage from 0 to 1000, e.g. --tolerance=10% or --tolerance=2.5");
    return v / 100;
}

}  // namespace suite
