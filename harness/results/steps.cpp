#include "harness/results/steps.hpp"

#include <algorithm>
#include <cmath>

#include "harness/common/stats.hpp"

namespace suite {

namespace {

struct StepSplit {
    std::size_t at = 0;  // the first position of the new level
    double p = 1, change = 0;
};

// The stable entries of a series: their values and commits, and where each sits in the series.
struct StableEntries {
    std::vector<double> values;
    std::vector<const std::string*> commits;
    std::vector<std::size_t> index;
};

// The most significant step in positions [lo, hi), if any.
bool best_split(const StableEntries& s, std::size_t lo, std::size_t hi, const StepRule& o, StepSplit& best) {
    if (hi - lo < 2 * o.min_side) return false;
    std::vector<std::size_t> candidates;
    for (std::size_t at = lo + o.min_side; at + o.min_side <= hi; ++at)
        if (*s.commits[at] != *s.commits[at - 1]) candidates.push_back(at);  // never inside one commit's runs
    bool found = false;
    for (std::size_t at : candidates) {
        const std::vector<double> before(s.values.begin() + lo, s.values.begin() + at),
            after(s.values.begin() + at, s.values.begin() + hi);
        const double level = median_of(before);
        if (!(level > 0)) continue;
        const double change = median_of(after) / level - 1;
        const RankTest t = mann_whitney(before, after);
        const double p =
            std::min(1.0, 2 * std::min(t.p_x_smaller, t.p_x_larger) * static_cast<double>(candidates.size()));
        if (p > o.alpha || std::fabs(change) < o.min_effect) continue;
        const bool better = !found || p < best.p || (p == best.p && std::fabs(change) > std::fabs(best.change));
        if (better) best = {at, p, change};
        found = true;
    }
    return found;
}

// The most significant bump in [lo, hi): entries [a, b), starting and ending at commit boundaries,
// that differ from the entries on both sides of them together (a regression later fixed, which
// moves neither side's median enough for one split to see it). Pairs are ranked by the rank sum
// of the inside (O(1) a pair from prefix sums, so a long history stays cheap); the best pair is
// then tested with the Mann–Whitney test, Bonferroni over every pair scanned.
bool best_bump(const StableEntries& s, std::size_t lo, std::size_t hi, const StepRule& o, StepSplit& first,
               StepSplit& second) {
    const std::size_t n = hi - lo;
    if (n < 3 * o.min_side) return false;
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return s.values[lo + a] < s.values[lo + b]; });
    std::vector<double> rank(n);
    for (std::size_t i = 0; i < n;) {  // ties share their average rank
        std::size_t j = i;
        while (j < n && s.values[lo + order[j]] == s.values[lo + order[i]]) ++j;
        for (std::size_t q = i; q < j; ++q) rank[order[q]] = 0.5 * static_cast<double>(i + 1 + j);
        i = j;
    }
    std::vector<double> prefix(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + rank[i];
    auto boundary = [&](std::size_t at) { return *s.commits[at] != *s.commits[at - 1]; };
    double best_z = 0;
    std::size_t best_a = 0, best_b = 0, pairs = 0;
    const double nd = static_cast<double>(n);
    for (std::size_t a = lo + o.min_side; a + 2 * o.min_side <= hi; ++a) {
        if (!boundary(a)) continue;
        for (std::size_t b = a + o.min_side; b + o.min_side <= hi; ++b) {
            if (!boundary(b)) continue;
            ++pairs;
            const double k = static_cast<double>(b - a);
            const double z =
                (prefix[b - lo] - prefix[a - lo] - k * (nd + 1) / 2) / std::sqrt(k * (nd - k) * (nd + 1) / 12);
            if (std::fabs(z) > best_z) best_z = std::fabs(z), best_a = a, best_b = b;
        }
    }
    if (pairs == 0 || best_z == 0) return false;
    const std::vector<double> inside(s.values.begin() + best_a, s.values.begin() + best_b);
    std::vector<double> outside(s.values.begin() + lo, s.values.begin() + best_a);
    outside.insert(outside.end(), s.values.begin() + best_b, s.values.begin() + hi);
    const double level = median_of(outside);
    if (!(level > 0)) return false;
    const double change = median_of(inside) / level - 1;
    const RankTest t = mann_whitney(outside, inside);
    const double p = std::min(1.0, 2 * std::min(t.p_x_smaller, t.p_x_larger) * static_cast<double>(pairs));
    if (p > o.alpha || std::fabs(change) < o.min_effect) return false;
    first = {best_a, p, change};
    second = {best_b, p, -change};
    return true;
}

void split_segment(const StableEntries& s, std::size_t lo, std::size_t hi, const StepRule& o,
                   std::vector<StepSplit>& found) {
    StepSplit split, back;
    if (best_split(s, lo, hi, o, split)) {
        found.push_back(split);
        split_segment(s, lo, split.at, o, found);
        split_segment(s, split.at, hi, o, found);
    } else if (best_bump(s, lo, hi, o, split, back)) {
        found.push_back(split);
        found.push_back(back);
        split_segment(s, lo, split.at, o, found);
        split_segment(s, split.at, back.at, o, found);
        split_segment(s, back.at, hi, o, found);
    }
}

}  // namespace

std::vector<Step> detect_steps(const Series& series, const StepRule& options) {
    StableEntries s;
    for (std::size_t i = 0; i < series.entries.size(); ++i) {
        const SeriesEntry& e = series.entries[i];
        if (e.unstable || !std::isfinite(e.median)) continue;
        s.values.push_back(e.median);
        s.commits.push_back(&e.commit);
        s.index.push_back(i);
    }
    std::vector<StepSplit> splits;
    split_segment(s, 0, s.values.size(), options, splits);
    std::sort(splits.begin(), splits.end(), [](const StepSplit& a, const StepSplit& b) { return a.at < b.at; });
    // Each step's levels are those of the final segments either side of it.
    std::vector<Step> steps;
    for (std::size_t k = 0; k < splits.size(); ++k) {
        const std::size_t lo = k == 0 ? 0 : splits[k - 1].at, at = splits[k].at;
        const std::size_t hi = k + 1 < splits.size() ? splits[k + 1].at : s.values.size();
        Step step;
        step.index = s.index[at];
        step.commit = series.entries[step.index].commit;
        step.before = median_of(std::vector<double>(s.values.begin() + lo, s.values.begin() + at));
        step.after = median_of(std::vector<double>(s.values.begin() + at, s.values.begin() + hi));
        step.change = step.before > 0 ? step.after / step.before - 1 : 0;
        step.p = splits[k].p;
        step.worse = series.direction == Direction::higher_is_better ? step.change < 0 : step.change > 0;
        steps.push_back(step);
    }
    return steps;
}

}  // namespace suite
