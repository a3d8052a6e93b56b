#pragma once
// `suite history html --out DIR`: a static, self-contained page of the history's trends (one
// chart per series with its repetitions' spread, its steps marked and the runs' band that
// `history check` gates the next run against, filterable by machine and kernel), that opens
// from file:// with no network. The chart library is Debian's libjs-chart.js, copied into DIR
// beside the page.
#include <cstddef>
#include <string>
#include <vector>

#include "harness/results/history_series.hpp"

namespace suite {

struct DashboardOptions {
    std::string title = "suite history";
    // Where Chart.js is read from (Debian's libjs-chart.js); a test may point it elsewhere.
    std::string chart_js = "/usr/share/javascript/chart.js/chart.min.js";
    // The runs' band each chart shows is `history check`'s (history_band.hpp): fitted from the
    // medians of the last `window` stable runs, at the gate's one-sided `alpha` (--window, --alpha).
    std::size_t window = 10;
    double alpha = 0.01;
};

// Writes DIR/index.html and DIR/chart.min.js (through the suite's one safe writer, so a failed
// write leaves any previous page whole). Returns the page's path. Throws UsageError when the
// chart library is missing (naming the package to install) or DIR cannot be written.
std::string write_dashboard(const std::vector<Series>& series, const std::string& out_dir,
                            const DashboardOptions& options = {});

}  // namespace suite
