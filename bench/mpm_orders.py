#!/usr/bin/python3
"""The MPM kernels by particle order and grid order: what sorting the particles buys, sort cost included.

Three parts, each from `suite` runs on this machine (nothing is timed here):
  sort      R rounds of mpm-step on one thread, --particles=unsorted,sorted,dynamic on every grid
            ordering in one run: per round each point's particle-steps/s against unsorted particles
            on the natural grid; the median over the rounds. One repetition is K = --sort-every
            steps and the sort (and the renumbering, for dynamic) that falls due after them, so the
            sort's cost is inside every timing.
  every     mpm-step, sorted particles on the Hilbert grid, at each K of --every: the K to choose.
  p2g       mpm-p2g's scatter strategies at every thread count and grid ordering, with the node
            updates each had to synchronise (the record's facts).

Usage: bench/mpm_orders.py [--rounds 3] [--mesh box:56,56,56] [--out results/bench] [--quick]
Writes OUT/mpm_orders.{json,md}; --quick: a small grid, one round, a check in a minute that it all runs.
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
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(top, "suite"))
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--mesh", default="box:56,56,56", help="the grid (default: 1.05 M tetrahedra, 0.54 M particles, 82 MB of particle arrays)")
p.add_argument("--orderings", default="natural,random,morton,hilbert")
p.add_argument("--every", default="1,5,20,50,100", help="the K of the 'every' part")
p.add_argument("--sort-every", default="5", help="K of the 'sort' part (5: the fastest of the 'every' part on the development VM)")
p.add_argument("--threads", default="1,2", help="thread counts of the 'p2g' part")
p.add_argument("--parts", default="sort,every,p2g")
p.add_argument("--quick", action="store_true")
a = p.parse_args()
if a.quick:
    a.rounds, a.mesh, a.every = 1, "box:12,12,12", "1,20"
parts = a.parts.split(",")
orderings = a.orderings.split(",")
tmp = tempfile.mkdtemp(prefix="mpm-orders-")


def suite(args):
    out = os.path.join(tmp, "r.json")
    argv = [a.suite] + args + ["--out", out, "--quiet"]
    print("  " + " ".join(argv[:1] + args), file=sys.stderr, flush=True)
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"mpm_orders: {' '.join(argv)} failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with open(out) as f:
        return json.load(f)


def rate(rec):
    return rec["units_per_second_best"]


def fact(rec, name):
    f = (rec.get("facts") or {}).get(name)
    return f["value"] if f else None


report = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "command": sys.argv, "rounds": a.rounds, "mesh": a.mesh}
lines = [f"# MPM by particle and grid order ({report['date']}, {a.rounds} round(s), {a.mesh})", ""]

if "sort" in parts:
    ratio, rates, facts = {}, {}, {}
    for r in range(a.rounds):
        res = suite(["--kernel=mpm-step", f"--mesh={a.mesh}", f"--ordering={a.orderings}", "--threads=1", f"--sort-every={a.sort_every}", "--reps=5"]
                    + (["--probe-caches"] if r == 0 else []))
        if r == 0:
            report["measured_llc_bytes"] = (res["context"].get("caches_measured") or {}).get("last_level_total_bytes")
        by = {(rec["ordering"], rec["variant"]): rec for rec in res["results"]}
        base = rate(by[("natural", "unsorted")])
        for key, rec in by.items():
            ratio.setdefault(key, []).append(rate(rec) / base)
            rates.setdefault(key, []).append(rate(rec))
            facts[key] = {"particles": fact(rec, "particles"), "active_nodes": fact(rec, "active-nodes"), "footprint_bytes": rec["size"]["footprint_bytes"]}
    report["sort"] = {f"{o}/{v}": {"speed_vs_unsorted_natural": statistics.median(ratio[(o, v)]), "per_round": ratio[(o, v)],
                                   "particle_steps_per_s": statistics.median(rates[(o, v)]), **facts[(o, v)]} for (o, v) in ratio}
    any_key = next(iter(facts))
    np_, fp = facts[any_key]["particles"], facts[any_key]["footprint_bytes"]
    llc = report.get("measured_llc_bytes")
    lines += ["## mpm-step, one thread: speed against unsorted particles on the natural grid", "",
              f"{np_:.0f} particles; all arrays {fp / 1e6:.0f} MB" + (f", {fp / llc:.0f}x the measured last level ({llc / 1e6:.1f} MB)" if llc else "")
              + f"; K = {a.sort_every}, sort cost included", "",
              "| grid | unsorted | sorted | dynamic | sorted: particle-steps/s | sorted: node-steps/s |", "|---|---|---|---|---|---|"]
    for o in orderings:
        cells = [f"{statistics.median(ratio[(o, v)]):.2f}x" for v in ("unsorted", "sorted", "dynamic")]
        r, f = statistics.median(rates[(o, 'sorted')]), facts[(o, 'sorted')]
        nodes = f"{r * f['active_nodes'] / f['particles'] / 1e6:.2f} M" if f["active_nodes"] else "n/a"
        lines.append(f"| {o} | " + " | ".join(cells) + f" | {r / 1e6:.2f} M | {nodes} |")
    lines.append("")

if "every" in parts:
    per_k = {}
    for r in range(a.rounds):
        for k in a.every.split(","):
            res = suite(["--kernel=mpm-step", f"--mesh={a.mesh}", "--ordering=hilbert", "--particles=sorted", "--threads=1", f"--sort-every={k}", "--reps=5"])
            per_k.setdefault(k, []).append(rate(res["results"][0]))
    report["every"] = {k: {"particle_steps_per_s_median": statistics.median(v), "per_round": v} for k, v in per_k.items()}
    lines += ["## Sorting every K steps (sorted particles, Hilbert grid, one thread, sort included)", "",
              "| K | particle-steps/s |", "|---|---|"]
    for k, v in per_k.items():
        lines.append(f"| {k} | {statistics.median(v) / 1e6:.2f} M |")
    lines.append("")

if "p2g" in parts:
    res = suite(["--kernel=mpm-p2g", f"--mesh={a.mesh}", f"--ordering={a.orderings}", f"--threads={a.threads}", "--reps=5"])
    rows = []
    for rec in res["results"]:
        rows.append({"ordering": rec["ordering"], "strategy": rec["variant"], "threads": rec["threads"], "particles_per_s": rate(rec),
                     "synchronised": fact(rec, "synchronised"), "colours": fact(rec, "colours"), "shared_nodes": fact(rec, "shared-nodes")})
    report["p2g"] = rows
    lines += ["## mpm-p2g by strategy (particles sorted along the curve)", "",
              "| grid | strategy | threads | particles/s | synchronised node updates | colours / shared nodes |", "|---|---|---|---|---|---|"]
    for r in rows:
        extra = r["colours"] if r["colours"] is not None else r["shared_nodes"] if r["shared_nodes"] is not None else ""
        lines.append(f"| {r['ordering']} | {r['strategy']} | {r['threads']} | {r['particles_per_s'] / 1e6:.2f} M | {r['synchronised']:.0f} | {extra} |")
    lines.append("")

os.makedirs(a.out, exist_ok=True)
stem = os.path.join(a.out, "mpm_orders" + ("_quick" if a.quick else ""))
write_text(stem + ".json", json.dumps(report, indent=1) + "\n")
write_text(stem + ".md", "\n".join(lines) + "\n")
print("\n".join(lines))
