#!/usr/bin/python3
"""The finite element kernels by mesh ordering: SpMV against the triad bound, and what an ordering buys.

Three parts, each from `suite` runs on this machine (nothing is timed here):
  roofline  R rounds of: triad at --triad-size, then fem-spmv on --mesh, both at every thread
            count. Per round the ratio SpMV GB/s / triad GB/s (best of each point, both counting the
            minimal traffic); the median over the rounds is the figure. Rounds interleave the two,
            so a machine that changes speed between minutes moves both.
  speedup   R rounds of fem-assembly (serial), fem-spmv and fem-eigen on one thread, every ordering
            in one run: per round each ordering's median time against natural's; the median of those
            ratios over the rounds. (The thesis's figures were -10 % assembly and -33 % inverse
            iteration time with Morton on one core.)
  misses    `suite deterministic` (valgrind's callgrind: one thread, simulated D1 32 KiB and LL
            8 MiB) on the same kernels and orderings on --det-mesh: instructions and simulated misses
            per call, the explanation that a machine without hardware counters can still give.

Usage: bench/fem_orderings.py [--rounds 3] [--out results/bench] [--quick]
Writes OUT/fem_orderings.{json,md}; --quick: small meshes, one round, a check in a minute that it all
runs.
"""
import argparse
import datetime
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plots"))
from safe_output import write_text  # noqa: E402  (the suite's one output policy)

here = os.path.dirname(os.path.abspath(__file__))
top = os.path.dirname(here)
thesis = "file:" + os.path.join(top, "..", "shared", "meshes", "unit_circle_fine.txt")
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(top, "suite"))
p.add_argument("--twin", default=os.path.join(top, "build", "suite-x86-64-v3"), help="the valgrind twin, for the misses part")
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--mesh", default=thesis + ":refine=3", help="SpMV and assembly mesh (default: the thesis's 1.54 M triangles)")
p.add_argument("--eigen-mesh", default=thesis + ":refine=1", help="fem-eigen mesh (default 385 k triangles: a CSR of 16 MB)")
p.add_argument("--det-mesh", default=thesis + ":refine=1", help="mesh of the callgrind part")
p.add_argument("--triad-size", default="1GiB")
p.add_argument("--threads", default="1,2")
p.add_argument("--orderings", default="natural,morton,hilbert,rcm")
p.add_argument("--parts", default="roofline,speedup,misses")
p.add_argument("--quick", action="store_true")
a = p.parse_args()
if a.quick:
    a.rounds, a.mesh, a.eigen_mesh, a.det_mesh, a.triad_size = 1, "disk:refine=5", "disk:refine=4", "disk:refine=4", "16MiB"
parts = a.parts.split(",")
orderings = a.orderings.split(",")
tmp = tempfile.mkdtemp(prefix="fem-orderings-")


def suite(args, binary=None):
    out = os.path.join(tmp, "r.json")
    argv = [binary or a.suite] + args + ["--out", out, "--quiet"]
    print("  " + " ".join(argv[:1] + args), file=sys.stderr, flush=True)
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"fem_orderings: {' '.join(argv)} failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with open(out) as f:
        return json.load(f)


def gbps(rec):
    return rec["bandwidth_gbps"]["stream"]["best"]


report = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "command": sys.argv, "rounds": a.rounds}
lines = [f"# fem kernels by ordering ({report['date']}, {a.rounds} round(s))", ""]

if "roofline" in parts:
    ratios = {}  # (ordering, threads) -> [ratio per round]
    triad_seen, csr_bytes, llc = [], None, None
    for r in range(a.rounds):
        tri = suite(["--kernel=triad", f"--size={a.triad_size}", f"--threads={a.threads}", "--reps=10"])
        bound = {rec["threads"]: gbps(rec) for rec in tri["results"]}
        triad_seen.append(bound)
        sp = suite(["--kernel=fem-spmv", f"--mesh={a.mesh}", f"--ordering={a.orderings}", f"--threads={a.threads}", "--reps=15", "--probe-caches" if r == 0 else "--min-time=0.2"])
        if r == 0:
            llc = (sp["context"].get("caches_measured") or {}).get("last_level_total_bytes")
        for rec in sp["results"]:
            csr_bytes = rec["work_per_repetition"]["stream_bytes"]
            ratios.setdefault((rec["ordering"], rec["threads"]), []).append(gbps(rec) / bound[rec["threads"]])
    report["roofline"] = {
        "spmv_bytes": csr_bytes, "measured_llc_bytes": llc, "triad_gbps_per_round": triad_seen,
        "ratio_median": {f"{o}/{t}": statistics.median(v) for (o, t), v in ratios.items()},
        "ratio_per_round": {f"{o}/{t}": v for (o, t), v in ratios.items()},
    }
    lines += ["## SpMV against the triad bound", "",
              f"SpMV traffic {csr_bytes / 1e6:.1f} MB a product; measured last level {llc / 1e6:.2f} MB" if llc else f"SpMV traffic {csr_bytes / 1e6:.1f} MB a product",
              f"({csr_bytes / llc:.0f}x)" if llc else "", "",
              "| ordering | threads | SpMV / triad (median of rounds) | per round |", "|---|---|---|---|"]
    for (o, t), v in ratios.items():
        lines.append(f"| {o} | {t} | {statistics.median(v):.2f} | {' '.join(f'{x:.2f}' for x in v)} |")
    lines.append("")

if "speedup" in parts:
    runs = [("fem-assembly", a.mesh, ["--strategy=serial"]), ("fem-spmv", a.mesh, []), ("fem-eigen", a.eigen_mesh, ["--reps=2"])]
    speed = {}
    for r in range(a.rounds):
        for kernel, mesh, extra in runs:
            res = suite([f"--kernel={kernel}", f"--mesh={mesh}", f"--ordering={a.orderings}", "--threads=1"] + extra)
            t = {rec["ordering"]: rec["time_s"]["median"] for rec in res["results"]}
            for o in orderings:
                speed.setdefault((kernel, o), []).append(t[o] / t["natural"])
    report["speedup"] = {f"{k}/{o}": {"time_ratio_median": statistics.median(v), "per_round": v} for (k, o), v in speed.items()}
    lines += ["## Time against the file's natural order, one thread", "",
              "| kernel | " + " | ".join(orderings) + " |", "|---|" + "---|" * len(orderings)]
    for kernel, _, _ in runs:
        lines.append(f"| {kernel} | " + " | ".join(f"{100 * (statistics.median(speed[(kernel, o)]) - 1):+.0f} %" for o in orderings) + " |")
    lines.append("")

if "misses" in parts:
    if not os.path.exists(a.twin):
        lines += ["## Simulated misses", "", f"not measured: {a.twin} is absent (it is built when valgrind is installed)", ""]
    else:
        det = {}
        for kernel, extra in [("fem-assembly", ["--strategy=serial"]), ("fem-spmv", [])]:
            res = suite(["deterministic", f"--kernel={kernel}", f"--mesh={a.det_mesh}", f"--ordering={a.orderings}"] + extra, binary=a.twin)
            for rec in res["results"]:
                cg = rec["callgrind"]
                det[f"{kernel}/{rec['ordering']}"] = cg
        report["misses"] = det
        keys = ["Ir", "D1mr", "D1mw", "DLmr", "DLmw"]
        lines += ["## Simulated misses per call (callgrind: D1 32 KiB, LL 8 MiB)", "", f"mesh {a.det_mesh}", "",
                  "| kernel/ordering | " + " | ".join(keys) + " |", "|---|" + "---|" * len(keys)]
        for name, cg in det.items():
            per = cg.get("per_call", cg)
            lines.append(f"| {name} | " + " | ".join(f"{per.get(k, float('nan')):.3g}" for k in keys) + " |")
        lines.append("")

os.makedirs(a.out, exist_ok=True)
stem = os.path.join(a.out, "fem_orderings" + ("_quick" if a.quick else ""))
write_text(stem + ".json", json.dumps(report, indent=1) + "\n")
write_text(stem + ".md", "\n".join(lines) + "\n")
print("\n".join(lines))
print(f"wrote {stem}.json and {stem}.md")
