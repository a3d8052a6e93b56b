#!/usr/bin/python3
"""Does measuring disturb the measurement? triad at 1 GiB with counters and energy on, then off,
interleaved run by run, and the ratio of the medians.

Usage: bench/instrument_overhead.py [--suite ./suite] [--runs 7] [--size 1GiB] [--threads 1,2]
                                    [--sysfs-root DIR]

With no RAPL on the machine, --sysfs-root points the energy meter at a captured tree
(tests/fixtures/sysfs/intel-2socket by default) so that the per-repetition reads of energy_uj files
still happen and are part of the cost (the energy figures themselves are then unavailable).
Prints one line per thread count: median GB/s off and on (medians over runs of each run's median
repetition, and of each run's best), and on/off.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(here, "..", "suite"))
p.add_argument("--runs", type=int, default=7)
p.add_argument("--size", default="1GiB")
p.add_argument("--threads", default="1,2")
p.add_argument("--reps", type=int, default=10)
p.add_argument("--sysfs-root", default=os.path.join(here, "..", "tests", "fixtures", "sysfs", "intel-2socket"))
a = p.parse_args()


def run(on, threads, out):
    env = dict(os.environ)
    args = [a.suite, "--kernel=triad", f"--size={a.size}", f"--threads={threads}", f"--reps={a.reps}", "--quiet", f"--out={out}"]
    if on:
        env["SUITE_SYSFS_ROOT"] = a.sysfs_root
        args += ["--counters=default", "--energy=sysfs"]
    else:
        args += ["--counters=none", "--energy=none"]
    subprocess.run(args, check=True, env=env)
    rec = json.load(open(out))["results"][0]
    bw = rec["bandwidth_gbps"]["stream"]
    return bw["median"], bw["best"]


with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "r.json")
    for t in a.threads.split(","):
        res = {False: [], True: []}
        for i in range(a.runs):
            for on in ((False, True) if i % 2 == 0 else (True, False)):  # alternate who goes first
                res[on].append(run(on, t, out))
        off_med = statistics.median(m for m, _ in res[False])
        on_med = statistics.median(m for m, _ in res[True])
        off_best = statistics.median(b for _, b in res[False])
        on_best = statistics.median(b for _, b in res[True])
        print(f"threads={t}: median-of-medians off {off_med:.2f} GB/s, on {on_med:.2f} GB/s, on/off {on_med / off_med:.4f}; "
              f"median-of-bests off {off_best:.2f}, on {on_best:.2f}, on/off {on_best / off_best:.4f}  ({a.runs} runs each)")
        sys.stdout.flush()
