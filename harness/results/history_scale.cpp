#include "harness/results/history_scale.hpp"

#include <algorithm>
#include <cstddef>

namespace suite {

namespace {

struct QnRow {
    double factor, df;
};

// bench/qn_constants.py's output, n = 2..40.
constexpr QnRow qn_rows[] = {
    {0.7060, 0.997},   // n = 2
    {1.7698, 0.928},   // n = 3
    {1.0078, 1.967},   // n = 4
    {1.6569, 1.968},   // n = 5
    {1.2573, 3.158},   // n = 6
    {1.7647, 3.188},   // n = 7
    {1.4069, 4.469},   // n = 8
    {1.8385, 4.598},   // n = 9
    {1.5312, 5.801},   // n = 10
    {1.8919, 5.943},   // n = 11
    {1.6253, 7.210},   // n = 12
    {1.9370, 7.366},   // n = 13
    {1.6927, 8.595},   // n = 14
    {1.9666, 8.829},   // n = 15
    {1.7469, 10.091},  // n = 16
    {1.9946, 10.283},  // n = 17
    {1.7932, 11.524},  // n = 18
    {2.0162, 11.663},  // n = 19
    {1.8324, 13.021},  // n = 20
    {2.0365, 13.314},  // n = 21
    {1.8608, 14.575},  // n = 22
    {2.0491, 14.744},  // n = 23
    {1.8889, 16.070},  // n = 24
    {2.0611, 16.401},  // n = 25
    {1.9116, 17.610},  // n = 26
    {2.0721, 17.928},  // n = 27
    {1.9319, 19.180},  // n = 28
    {2.0802, 19.422},  // n = 29
    {1.9493, 20.704},  // n = 30
    {2.0906, 21.093},  // n = 31
    {1.9641, 22.301},  // n = 32
    {2.0961, 22.756},  // n = 33
    {1.9784, 23.741},  // n = 34
    {2.1027, 24.110},  // n = 35
    {1.9917, 25.358},  // n = 36
    {2.1093, 25.794},  // n = 37
    {2.0017, 26.973},  // n = 38
    {2.1151, 27.244},  // n = 39
    {2.0132, 28.530},  // n = 40
};
constexpr std::size_t qn_first = 2, qn_last = qn_first + sizeof qn_rows / sizeof qn_rows[0] - 1;

}  // namespace

ScaleEstimate qn_scale(const std::vector<double>& x) {
    ScaleEstimate out;
    const std::size_t n = x.size();
    if (n < 2) return out;
    std::vector<double> d;
    d.reserve(n * (n - 1) / 2);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) d.push_back(std::fabs(x[i] - x[j]));
    const std::size_t h = n / 2 + 1, k = h * (h - 1) / 2;
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k - 1), d.end());
    const QnRow& row = qn_rows[std::min(n, n % 2 == qn_last % 2 ? qn_last : qn_last - 1) - qn_first];
    out.sigma = row.factor * d[k - 1];
    out.df = n <= qn_last ? row.df : 0.73 * static_cast<double>(n - 1);
    return out;
}

}  // namespace suite
