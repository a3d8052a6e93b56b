#!/usr/bin/python3
"""peak-flops against likwid-bench's peakflops kernels, interleaved on this machine.

Each round runs, for 1 thread and for all threads, likwid-bench -t peakflops_<isa> (one run, its
MFlops/s) and ./suite --kernel=peak-flops --isa=<isa> (the best and the median repetition), one
after the other, so that both see the same machine state. Prints the medians over the rounds
and the ratio suite/likwid, for the suite's best and its median repetition (likwid reports one
long run, which sits between the two).

Usage: bench/peakflops_vs_likwid.py [--suite ./suite] [--rounds 5] [--isa avx512]
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

LIKWID = {"avx512": "peakflops_avx512_fma", "avx": "peakflops_avx_fma", "sse": "peakflops_sse", "scalar": "peakflops"}


def likwid(test, threads):
    # The working set stays in L1: 16 kB a thread, as likwid's own examples use for peakflops.
    out = subprocess.run(["likwid-bench", "-t", test, "-w", f"S0:{16 * threads}kB:{threads}"], capture_output=True, text=True, check=True).stdout
    return float(re.search(r"MFlops/s:\s+([0-9.]+)", out).group(1)) / 1e3


def suite(binary, isa, threads, tmp):
    path = os.path.join(tmp, "p.json")
    subprocess.run([binary, "--kernel=peak-flops", f"--isa={isa}", f"--threads={threads}", "--quiet", "--out=" + path], check=True,
                   capture_output=True)
    r = json.load(open(path))["results"][0]
    w, t = r["work_per_repetition"], r["time_s"]
    return w["flops"] / t["min"] / 1e9, w["flops"] / t["median"] / 1e9


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", default="./suite")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--isa", default="avx512", choices=sorted(LIKWID))
    a = ap.parse_args()
    all_threads = os.cpu_count()
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.rounds):
            for t in sorted({1, all_threads}):
                lw = likwid(LIKWID[a.isa], t)
                best, med = suite(a.suite, a.isa, t, tmp)
                rows.setdefault(t, []).append((lw, best, med))
                print(f"round {k + 1} t={t}: likwid {lw:.1f}  suite best {best:.1f} median {med:.1f} GFLOP/s", flush=True)
    print(f"\n{'threads':>7} {'likwid':>8} {'suite best':>11} {'suite median':>13} {'best/likwid':>12} {'median/likwid':>14}")
    for t, r in sorted(rows.items()):
        lw, best, med = (statistics.median(x[i] for x in r) for i in range(3))
        print(f"{t:>7} {lw:>8.1f} {best:>11.1f} {med:>13.1f} {best / lw:>12.3f} {med / lw:>14.3f}")


main()
