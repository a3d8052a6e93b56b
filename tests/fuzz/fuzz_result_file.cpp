// libFuzzer target: the reader of result files behind `suite compare` and `suite check`.
// Any input must either load or be refused with InputError (a UsageError: one line, exit 2);
// another exception, a crash or a sanitizer report is a bug. Loaded points must keep the
// reader's promises: finite figures, a headline, a known direction.
// SOURCES: harness/results/result_file.cpp harness/results/result_file_mpi.cpp harness/results/context_fields.cpp harness/common/units.cpp harness/common/text.cpp harness/common/did_you_mean.cpp harness/common/stats.cpp harness/common/input_file.cpp harness/common/sysfs_file.cpp harness/kernel/registry.cpp harness/kernel/store_variants.cpp
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "harness/results/result_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const suite::ResultFile f = suite::parse_result_text(text, "fuzz.json");
        for (const auto& p : f.points) {
            if (p.measures.empty()) std::abort();
            for (const auto& m : p.measures)
                if (!std::isfinite(m.median) || !std::isfinite(m.best) || !std::isfinite(m.noise) || m.noise < 0)
                    std::abort();
            (void)p.key.label();
        }
        (void)f.machine_label();
    } catch (const suite::UsageError&) {
    }
    return 0;
}
