#pragma once
// Reading a roofline file (what `suite roofline` measured, harness/measure/roofline.hpp) and
// placing the points of a result file on it: each point's arithmetic intensity from the flops
// and bytes its kernel declared (STREAM convention and the hardware estimate both), the level
// its footprint lives in, the ceiling that bounds it there, and the fraction of that ceiling it
// reached. Only a result measured on the same machine (machine_fingerprint) is placed.
//
// The level: the first whose capacity for the point's threads (level_bytes) is at least half
// the footprint. A footprint up to twice a level's capacity still keeps part of its data there
// (replacement is not strict LRU), so it is held against that level's ceiling, the higher one:
// a ceiling is an upper bound, and a point between two levels shows as a low fraction of the
// faster, not as a fraction above 1 of the slower. Where a level has no ceiling at that thread
// count (its footprint fitted in the levels above), the nearest faster level's is used.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/measure/roofline.hpp"
#include "harness/results/result_file.hpp"

namespace suite {

constexpr int roofline_schema_version = 1;
constexpr const char* roofline_kind = "suite-roofline";
constexpr const char* placement_kind = "suite-roofline-placement";

struct RooflineFile {
    std::string path;
    nlohmann::json context;
    std::string fingerprint;
    Roofline roofline;
};

// Reads and checks a roofline file: InputError (exit 2) naming the file and the field when it is
// missing, not JSON, not a roofline (kind), of another schema_version, or lacks a field.
RooflineFile load_roofline_file(const std::string& path);
RooflineFile parse_roofline_text(const std::string& text, const std::string& path);

struct PlacedPoint {
    std::string label;  // "triad sequential 64MiB t=1 compact/local"
    std::string name, kernel, group, level;
    int threads = 1;
    std::uint64_t footprint_bytes = 0;
    bool verified = true;
    std::optional<double> gflops;                         // none: the kernel declares no flops
    double gbps = 0, hardware_gbps = 0;                   // best repetition
    std::optional<double> intensity, hardware_intensity;  // flop per byte
    std::optional<double> ceiling_gflops;                 // min(peak, intensity x level bandwidth)
    double ceiling_gbps = 0, ceiling_hardware_gbps = 0;
    std::string bound;                        // "bandwidth" or "compute"
    double fraction = 0;                      // of the ceiling, STREAM convention
    std::optional<double> hardware_fraction;  // of the ceiling, hardware estimate
};

struct Placement {
    std::vector<PlacedPoint> points;
    std::vector<std::pair<std::string, std::string>> not_placed;  // label, why
};

// The placement of every record of a result file on `roof`: `file` as parse_result_text read
// it, `result` the same document as JSON (for the work and footprint of each record). Throws
// InputError when the result comes from another machine or has no records.
Placement place_points(const RooflineFile& roof, const ResultFile& file, const nlohmann::json& result);

nlohmann::json to_json(const Placement& placement, const std::string& roofline_path, const std::string& result_path);
// The placement as a console table, one line a point, then the points not placed and why.
std::string render_placement(const Placement& placement);
// The ceilings as a console table: peak per width, bandwidth per level, per thread count.
std::string render_roofline(const Roofline& roof);

}  // namespace suite
