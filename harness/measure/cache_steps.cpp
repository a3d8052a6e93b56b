#include "harness/measure/cache_steps.hpp"

#include <algorithm>
#include <cmath>

namespace suite {

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    const double upper = v[mid];
    if (v.size() % 2) return upper;
    return (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)) + upper) / 2;
}

struct Segment {
    std::size_t first, last;
    std::vector<double> values;
    double low, high;  // the band its values lie in
    double median_value() const { return median(values); }
};

// The footprint where the curve, between points i and i + 1, crosses `threshold`: linear in the
// value against the logarithm of the size (the sweep's sizes are geometric).
std::uint64_t crossing_size(const std::vector<CurvePoint>& c, std::size_t i, double threshold) {
    if (i + 1 >= c.size() || !(c[i + 1].value > c[i].value)) return c[i].size_bytes;
    const double t = std::clamp((threshold - c[i].value) / (c[i + 1].value - c[i].value), 0.0, 1.0);
    const double lo = std::log(static_cast<double>(c[i].size_bytes)),
                 hi = std::log(static_cast<double>(c[i + 1].size_bytes));
    return static_cast<std::uint64_t>(std::llround(std::exp(lo + t * (hi - lo))));
}

}  // namespace

Steps find_steps(std::vector<CurvePoint> points, const StepOptions& o) {
    Steps s;
    // Only positive, finite costs have a place on a ratio scale.
    points.erase(std::remove_if(points.begin(), points.end(),
                                [](const CurvePoint& p) { return !(p.value > 0) || !std::isfinite(p.value); }),
                 points.end());
    std::stable_sort(points.begin(), points.end(),
                     [](const CurvePoint& a, const CurvePoint& b) { return a.size_bytes < b.size_bytes; });
    // A running median of three takes out a single disturbed point (a spike from another
    // process, or a lucky dip) and keeps a real step as sharp as it was.
    s.curve = points;
    for (std::size_t i = 1; i + 1 < points.size(); ++i)
        s.curve[i].value = median({points[i - 1].value, points[i].value, points[i + 1].value});
    const auto& c = s.curve;
    if (c.size() < o.min_points) return s;

    const std::size_t n = c.size(), w = o.rise_span;
    const double half_jump = std::sqrt(o.jump);
    auto rising = [&](std::size_t i) {
        return i >= w && i + w < n && c[i].value / c[i - w].value > half_jump &&
               c[i + w].value / c[i].value > half_jump;
    };
    // Where the tail begins (n: no tail).
    std::size_t tail = n;
    if (o.tail_from_size)
        for (std::size_t i = 0; i < n && tail == n; ++i)
            if (c[i].size_bytes >= *o.tail_from_size) tail = i;
    if (o.ceiling)
        for (std::size_t i = 0; i < n && tail == n; ++i) {
            if (c[i].value < *o.ceiling) continue;
            std::size_t above = 0;
            for (std::size_t k = i; k < n; ++k) above += c[k].value >= *o.ceiling;
            if (above >= 0.8 * static_cast<double>(n - i)) tail = i;
        }

    // Segments: a point joins the current one while all of its values stay within a band of
    // width `jump`, so that a slow rise (a gradual transition) cannot drift along as one flat
    // run; a point in the middle of a rise is passed over.
    std::vector<Segment> segments(1, Segment{0, 0, {}, 0, 0});
    for (std::size_t i = 0; i < tail; ++i) {
        Segment& cur = segments.back();
        const double v = c[i].value;
        if (rising(i)) continue;
        if (cur.values.empty()) {
            cur = {i, i, {v}, v, v};
        } else if (std::max(cur.high, v) / std::min(cur.low, v) <= o.jump) {
            cur.last = i;
            cur.values.push_back(v);
            cur.low = std::min(cur.low, v);
            cur.high = std::max(cur.high, v);
        } else {
            segments.push_back({i, i, {v}, v, v});
        }
    }
    // Long segments are levels; the short ones between them are the rises.
    std::vector<Segment> kept;
    for (auto& seg : segments)
        if (seg.values.size() >= o.min_points) kept.push_back(std::move(seg));
    // Neighbours less than `min_step` apart (or going down) are one level: merge the closest
    // pair first, until every step is a real one.
    while (kept.size() > 1) {
        std::size_t best = 0;
        double best_ratio = 0;
        for (std::size_t k = 0; k + 1 < kept.size(); ++k) {
            const double r = kept[k + 1].median_value() / kept[k].median_value();
            if (k == 0 || r < best_ratio) {
                best_ratio = r;
                best = k;
            }
        }
        if (best_ratio >= o.min_step) break;
        Segment& a = kept[best];
        const Segment& b = kept[best + 1];
        a.last = b.last;
        a.values.insert(a.values.end(), b.values.begin(), b.values.end());
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(best) + 1);
    }
    for (const auto& seg : kept) s.plateaus.push_back({seg.first, seg.last, seg.median_value()});
    if (n - tail >= o.min_points) {
        std::vector<double> values;
        for (std::size_t i = tail; i < n; ++i) values.push_back(c[i].value);
        double value = median(values);
        // A plateau before the tail that is not clearly below it was the tail's beginning.
        while (!s.plateaus.empty() && value / s.plateaus.back().value < o.min_step) {
            tail = s.plateaus.back().first;
            s.plateaus.pop_back();
            values.clear();
            for (std::size_t i = tail; i < n; ++i) values.push_back(c[i].value);
            value = median(values);
        }
        s.plateaus.push_back({tail, n - 1, value});
        s.tail = true;
    }

    // Each capacity: the last time, before the next plateau begins, that the curve is still
    // below the crossing threshold (looking backwards, so that noise inside the plateau does not
    // end it early), interpolated to the threshold.
    for (std::size_t k = 0; k + 1 < s.plateaus.size(); ++k) {
        const Plateau& here = s.plateaus[k];
        const Plateau& next = s.plateaus[k + 1];
        auto cross = [&](double threshold) {
            std::size_t i = next.first;
            while (i > here.first && c[i].value > threshold) --i;
            return c[i].value > threshold ? c[i].size_bytes : crossing_size(c, i, threshold);
        };
        s.capacities.push_back(cross(here.value * std::pow(next.value / here.value, o.crossing)));
        s.reaches.push_back(cross(here.value + o.crossing * (next.value - here.value)));
    }
    return s;
}

StepOptions latency_step_options() {
    StepOptions o;
    o.ceiling = memory_latency_floor_ns;
    return o;
}

Hierarchy read_hierarchy(const Steps& steps, double memory_ns) {
    Hierarchy h;
    const auto& p = steps.plateaus;
    std::size_t memory = p.size();
    for (std::size_t k = 0; k < p.size(); ++k)
        if (p[k].value >= memory_ns || (steps.tail && k + 1 == p.size())) {
            memory = k;
            break;
        }
    for (std::size_t k = 0; k < memory; ++k) {
        MeasuredLevel level;
        level.level = static_cast<int>(k) + 1;
        level.latency_ns = p[k].value;
        if (k < steps.capacities.size()) level.capacity_bytes = steps.capacities[k];
        h.levels.push_back(level);
    }
    // A partial level between the last plateau and memory.
    if (memory < p.size() && memory > 0 && memory - 1 < steps.reaches.size()) {
        const std::uint64_t end = steps.capacities[memory - 1], reach = steps.reaches[memory - 1];
        if (static_cast<double>(reach) >= std::sqrt(2.0) * static_cast<double>(end)) {
            std::vector<double> between;
            for (const auto& point : steps.curve)
                if (point.size_bytes > end && point.size_bytes <= reach) between.push_back(point.value);
            if (!between.empty()) {
                MeasuredLevel level;
                level.level = static_cast<int>(memory) + 1;
                level.capacity_bytes = reach;
                level.latency_ns = median(between);
                level.partial = true;
                h.levels.push_back(level);
            }
        }
    }
    if (memory < p.size()) {
        // Memory is everything from its plateau on: one figure, however the noise split it.
        std::vector<double> values;
        for (std::size_t i = p[memory].first; i < steps.curve.size(); ++i) values.push_back(steps.curve[i].value);
        h.memory_latency_ns = median(values);
        h.memory_from = steps.curve[p[memory].first].size_bytes;
    }
    return h;
}

}  // namespace suite
