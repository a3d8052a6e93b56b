#pragma once
// The spread of a few run medians, robustly and as efficiently as a few numbers allow. The
// estimator is Qn (Rousseeuw and Croux 1993): the k-th smallest of the |x_i - x_j|, i < j, with
// k = h (h - 1) / 2 and h = n / 2 + 1. It ignores up to half the values (one stray run of this VM
// moves it little) and wastes less than the median absolute deviation: of six normal values it
// knows the spread about as well as a standard deviation of 3.2 degrees of freedom, where the
// MAD's is worth 2.5 and the standard deviation's own 5 (bench/qn_constants.py).
//
// A t interval needs the estimate to behave like a standard deviation of some degrees of freedom
// d (s^2 ~ sigma^2 chi^2_d / d). Qn is matched to that in its log moments, as limma matches
// variances: d from Var(log Qn^2) = trigamma(d / 2), and a factor c with E[log (c Qn)^2] =
// digamma(d / 2) - log(d / 2). Both were simulated (bench/qn_constants.py, 200000 normal samples
// a size, fixed seed) for n = 2..40; beyond, the last row of the same parity, with d growing as
// 0.73 (n - 1) (its ratio at n = 40; the asymptotic 0.82 is reached only slowly).
#include <cmath>
#include <vector>

namespace suite {

struct ScaleEstimate {
    double sigma = NAN;  // in the values' units (log units for log medians)
    double df = 0;       // the degrees of freedom of a standard deviation that knows sigma as well
};

// Qn of `x`, scaled as above; sigma NAN and df 0 for fewer than 2 values.
ScaleEstimate qn_scale(const std::vector<double>& x);

}  // namespace suite
