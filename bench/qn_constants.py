#!/usr/bin/python3
"""The constants of the history gate's scale estimator (harness/results/history_scale.cpp), by simulation.

For n normal draws, Qn (Rousseeuw and Croux: the k-th smallest of the |x_i - x_j|, i < j, with
k = h (h - 1) / 2, h = n // 2 + 1) is matched to a scaled chi-square in its log moments, as the
variances of a t interval are: the degrees of freedom d with Var(log Qn^2) = trigamma(d / 2), and
the factor c with E[log (c Qn)^2] = digamma(d / 2) - log(d / 2) for unit sigma. Prints the C++
table for n = 2..40 (fixed seed; 200000 samples each). Usage: bench/qn_constants.py
"""
import numpy as np
from scipy.optimize import brentq
from scipy.special import polygamma, digamma

rng = np.random.default_rng(53)


def qn_raw(x):
    n = x.shape[1]
    h = n // 2 + 1
    k = h * (h - 1) // 2
    i, j = np.triu_indices(n, 1)
    d = np.abs(x[:, i] - x[:, j])
    return np.partition(d, k - 1, axis=1)[:, k - 1]


rows = []
for n in range(2, 41):
    logs = np.concatenate([np.log(qn_raw(rng.standard_normal((20000, n))) ** 2) for _ in range(10)])
    d = brentq(lambda d: polygamma(1, d / 2) - logs.var(), 0.01, 1e6)
    c = np.exp((digamma(d / 2) - np.log(d / 2) - logs.mean()) / 2)
    rows.append(f"    {{{c:.4f}, {d:.3f}}},  // n = {n}")
print("\n".join(rows))
