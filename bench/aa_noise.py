#!/usr/bin/python3
"""The noise floor of `make bench-vs` at DRAM size: each program against itself (an A/A test).

For every likwid-bench kernel of vs_likwid.py at one size (default 1 GiB), one thread and all
threads, and for the matching suite kernels, the same command is run twice back to back per
repetition, and the ratio first/second is formed as vs_likwid.py forms suite/likwid-bench: the
median over the repetitions of each repetition's ratio. Nothing differs between the two runs but
time, so the spread of these medians around 1.00 is how far a ratio of vs_likwid.py can stray
from the truth on this machine with this many repetitions, and the share of points below 1.00 is
what a program exactly as fast as likwid-bench would show against "at least 1.00 at every point".

Usage: bench/aa_noise.py [--reps 9] [--size 1GiB] [--out results/bench] [--suite ./suite] [--quick]
Writes OUT/aa_noise.{json,md} (aa_noise_quick.* with --quick: 16 MiB, one thread, one repetition,
a check in seconds that it all runs). Without likwid-bench the suite's half runs alone.
"""
import argparse
import datetime
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plots"))
from safe_output import write_text  # noqa: E402  (the suite's one output policy)

here = os.path.dirname(os.path.abspath(__file__))
top = os.path.dirname(here)
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(top, "suite"))
p.add_argument("--likwid", default=shutil.which("likwid-bench") or "/usr/bin/likwid-bench")
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--reps", type=int, default=9, help="repetitions of every point (default 9, as three pooled runs of vs_likwid.py)")
p.add_argument("--size", default="1GiB", help="footprint, as the suite's --size (default 1GiB)")
p.add_argument("--quick", action="store_true", help="16 MiB, one thread, one repetition: a check that it all runs")
a = p.parse_args()
if a.quick:
    a.size, a.reps = "16MiB", 1
if a.reps < 1:
    print(f"aa_noise: --reps must be at least 1 (got {a.reps})", file=sys.stderr)
    sys.exit(2)
have_likwid = os.access(a.likwid, os.X_OK)
if not have_likwid:
    print(f"aa_noise: {a.likwid} not found (Debian package likwid; make bench-deps installs it): only the suite against itself")


def run(argv):
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"aa_noise: {' '.join(argv)} failed with status {r.returncode}:\n{r.stderr[-2000:]}")
    return r.stdout


info = json.loads(run([a.suite, "info", "--json"]))
w = "avx512" if info["instruction_set"]["avx512f"] else "avx"
pairs = [("copy", "", f"copy_{w}"), ("copy", "nt", f"copy_mem_{w}"), ("triad", "", f"stream_{w}"), ("triad", "nt", f"stream_mem_{w}"),
         ("load", "", f"load_{w}"), ("store", "", f"store_{w}"), ("store", "nt", f"store_mem_{w}")]
threads_all = len(os.sched_getaffinity(0))
thread_counts = [1] if a.quick else sorted({1, threads_all})
size_bytes = None


def suite_once(threads, variant, tmp):
    """The suite's median sample (GB/s) of every kernel of `variant`, as vs_likwid.py takes it."""
    global size_bytes
    out = os.path.join(tmp, "aa.json")
    ks = [k for k, v, _ in pairs if v == variant]
    run([a.suite, "--kernel=" + ",".join(ks), f"--size={a.size}", f"--threads={threads}", "--pin=compact", "--min-time=0.2",
         "--counters=none", "--energy=none", "--quiet", f"--out={out}"] + (["--stores=" + variant] if variant else []))
    got = {}
    for r in json.load(open(out))["results"]:
        if not r["verification"]["passed"]:
            sys.exit(f"aa_noise: the suite's {r['name']} failed verification")
        got[(r["kernel"], r["variant"])] = r["bandwidth_gbps"]["stream"]["median"]
        size_bytes = r["size"]["requested"]
    return got


def likwid_once(test, threads):
    # As vs_likwid.py at DRAM sizes: 10 iterations (a run of 0.3 s or more at 1 GiB).
    text = run([a.likwid, "-t", test, "-W", f"S0:{size_bytes}B:{threads}", "-i", "10"])
    return float(re.search(r"^MByte/s:\s+([0-9.]+)", text, re.M).group(1)) / 1e3


started, load_before = time.time(), [round(x, 2) for x in os.getloadavg()]
series = {}  # (program, name, threads) -> [(first, second), ...]
with tempfile.TemporaryDirectory() as tmp:
    for rep in range(a.reps):
        for threads in (thread_counts if rep % 2 == 0 else list(reversed(thread_counts))):
            for variant in ("", "nt"):
                first, second = suite_once(threads, variant, tmp), suite_once(threads, variant, tmp)
                for key in first:
                    series.setdefault(("suite", key[0] + ("-" + key[1] if key[1] else ""), threads), []).append((first[key], second[key]))
            for _, _, test in (pairs if have_likwid else []):
                series.setdefault(("likwid-bench", test, threads), []).append((likwid_once(test, threads), likwid_once(test, threads)))
        print(f"rep {rep + 1}/{a.reps} done ({time.time() - started:.0f} s)", flush=True)

rows = []
for (program, name, threads), pts in sorted(series.items()):
    ratios = [x / y for x, y in pts]
    rows.append({"program": program, "kernel": name, "threads": threads, "gbps_pairs": pts, "ratio": statistics.median(ratios),
                 "ratio_min": min(ratios), "ratio_max": max(ratios)})
summary = {}
for program in ("suite", "likwid-bench"):
    med = [r["ratio"] for r in rows if r["program"] == program]
    if not med:
        continue
    summary[program] = {"points": len(med), "below_1.00": sum(m < 1.0 for m in med), "lowest": min(med), "highest": max(med),
                        "median_abs_deviation_from_1": statistics.median(abs(m - 1) for m in med)}
doc = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "size_bytes": size_bytes, "repetitions": a.reps,
       "load_average_before": load_before, "load_average_after": [round(x, 2) for x in os.getloadavg()],
       "elapsed_s": round(time.time() - started, 1), "cpu_model": info.get("cpu_model", ""), "pus": info["pus"],
       "statistic": "per point: the median over the repetitions of first/second, two identical runs back to back",
       "summary": summary, "points": rows}
os.makedirs(a.out, exist_ok=True)
name = "aa_noise_quick" if a.quick else "aa_noise"
write_text(os.path.join(a.out, name + ".json"), json.dumps(doc, indent=1))
lines = [f"# A/A: each program against itself at {a.size} ({doc['date']}, {doc['cpu_model']}, {doc['pus']} PUs)", "",
         f"{a.reps} repetitions; load average {load_before[0]} before, {doc['load_average_after'][0]} after; {doc['elapsed_s']:.0f} s.", "",
         "| program | kernel | threads | median first/second | lowest | highest |", "|---|---|---|---|---|---|"]
for r in rows:
    lines.append(f"| {r['program']} | {r['kernel']} | {r['threads']} | {r['ratio']:.2f} | {r['ratio_min']:.2f} | {r['ratio_max']:.2f} |")
lines.append("")
for program, s in summary.items():
    lines.append(f"- {program} against itself: {s['below_1.00']} of {s['points']} medians below 1.00, from {s['lowest']:.2f} to "
                 f"{s['highest']:.2f} (median distance from 1: {s['median_abs_deviation_from_1']:.3f})")
write_text(os.path.join(a.out, name + ".md"), "\n".join(lines) + "\n")
print("\n".join(lines))
