#!/usr/bin/python3
"""The history gate's reach and false alarms with six runs of history (issue 53's table).

Runs `suite --kernel=triad,copy --sizes=64KiB,64MiB --threads=1 --reps=5` N times (default 37,
--gap seconds apart; or takes the files given with --from). Each of the N - 1 consecutive pairs
(run i, rerun i + 1) is a trial: a fresh history holds the six runs before the pair (wrapping
around), each under a commit of its own, and the pair is gated as the workflow gates a run,
`suite history check RUN --confirm RERUN --tolerance=auto`:
  - unchanged (an A/A test: every regression is a false alarm);
  - both slowed 1.25x, 1.5x and 2x: every repetition's time of the real run multiplied by the
    factor, its rates divided by it (what a slower build would have measured, noise included).
For each point: its runs' spread (the standard deviation of the log medians over the N runs, and
their Qn), its repetitions' typical spread, how many runs flagged it unstable, and in how many
trials each slowdown was caught (REGRESSED) or called inconclusive.

Usage: bench/gate_reach.py [--runs 37] [--gap 2] [--fresh-arrays] [--from RUN.json ...] [--out results/bench] [--suite ./suite]
Writes OUT/gate_reach.{json,md}, and the runs to OUT/gate_reach_runs/. --quick: 10 scaled copies
of a committed fixture run, a check that it all runs.
"""
import argparse
import datetime
import json
import math
import os
import re
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plots"))
from safe_output import write_text  # noqa: E402  (the suite's one output policy)

import gate_runs  # noqa: E402  (beside this file: what the gate benches share)

here = os.path.dirname(os.path.abspath(__file__))
top = os.path.dirname(here)
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(top, "suite"))
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--runs", type=int, default=37, help="runs of the recipe (default 37: 36 pairs; at least 8)")
p.add_argument("--gap", type=float, default=2, help="seconds between runs (default 2)")
p.add_argument("--history", type=int, default=6, help="runs of history each pair is gated against (default 6)")
p.add_argument("--fresh-arrays", action="store_true",
               help="the recipe with --fresh-arrays: each repetition on arrays allocated anew (docs/noise.md)")
p.add_argument("--from", dest="given", nargs="+", default=[], help="result files of earlier runs, instead of running")
p.add_argument("--quick", action="store_true", help="10 scaled copies of a committed fixture run: a check that it all runs")
a = p.parse_args()
if not a.given and not a.quick and a.runs < a.history + 2:
    print(f"gate_reach: --runs must be at least {a.history + 2} (a pair and {a.history} runs of history; got {a.runs})",
          file=sys.stderr)
    sys.exit(2)
if a.history < 1:
    print(f"gate_reach: --history must be at least 1 (got {a.history})", file=sys.stderr)
    sys.exit(2)
RECIPE = ["--kernel=triad,copy", "--sizes=64KiB,64MiB", "--threads=1", "--reps=5"] + (["--fresh-arrays"] if a.fresh_arrays else [])
SLOWDOWNS = (1.25, 1.5, 2.0)


def run(argv, ok=(0,)):
    return gate_runs.run(argv, "gate_reach", ok)


slowed = gate_runs.slowed


def label_of(r):
    """"triad 64KiB t=1": the kernel, its requested size and threads, as the point is named below."""
    b = r["size"]["requested"] if isinstance(r.get("size"), dict) else r["size_bytes"]
    size = f"{b}B"
    for unit, shift in (("GiB", 30), ("MiB", 20), ("KiB", 10)):
        if b >= 1 << shift:
            size = f"{b / (1 << shift):g}{unit}"
            break
    return f"{r['kernel']} {size} t={r['threads']}"


def qn(x):
    """Qn's raw order statistic (harness/results/history_scale.hpp applies the factor): reported raw x 2.2219."""
    n = len(x)
    h = n // 2 + 1
    d = sorted(abs(x[i] - x[j]) for i in range(n) for j in range(i + 1, n))
    return 2.2219 * d[h * (h - 1) // 2 - 1]


def robust_rel(s):
    s = sorted(s)
    med = s[len(s) // 2] if len(s) % 2 else (s[len(s) // 2 - 1] + s[len(s) // 2]) / 2
    dev = sorted(abs(x - med) for x in s)
    mad = dev[len(dev) // 2] if len(dev) % 2 else (dev[len(dev) // 2 - 1] + dev[len(dev) // 2]) / 2
    return 1.4826 * mad / med


started = time.time()
with tempfile.TemporaryDirectory() as tmp:
    files = list(a.given)
    if a.quick:
        files += gate_runs.quick_runs(top, tmp, 10, lambda i: 1 + 0.01 * ((i * 7) % 10 - 5))
    elif not files:
        kept = os.path.join(a.out, "gate_reach_runs")
        os.makedirs(kept, exist_ok=True)
        for i in range(a.runs):
            if i:
                time.sleep(a.gap)
            files.append(os.path.join(kept, f"run{i:02d}.json"))
            run([a.suite] + RECIPE + [f"--out={files[-1]}", "--quiet"])
        print(f"{len(files)} runs done ({time.time() - started:.0f} s)", flush=True)
    if len(files) < a.history + 2:
        sys.exit(f"gate_reach: {len(files)} runs given; a trial needs {a.history + 2}")
    docs = [json.load(open(f)) for f in files]
    # Each point's figures over all runs: the medians' spread between runs, the repetitions' within.
    points = {}
    for d in docs:
        for r in d["results"]:
            pt = points.setdefault(label_of(r), {"medians": [], "rep_spread": [], "unstable": 0})
            pt["medians"].append(r["bandwidth_gbps"]["stream"]["median"])
            bytes_ = r["work_per_repetition"]["stream_bytes"]
            pt["rep_spread"].append(robust_rel([bytes_ / t for t in r["time_s"]["samples"]]))
            pt["unstable"] += bool((r.get("stability") or {}).get("unstable"))
    for pt in points.values():
        logs = [math.log(m) for m in pt["medians"]]
        mean = sum(logs) / len(logs)
        pt["sd"] = math.sqrt(sum((x - mean) ** 2 for x in logs) / (len(logs) - 1))
        pt["qn"] = qn(logs)
        pt["rep_spread"] = sorted(pt["rep_spread"])[len(pt["rep_spread"]) // 2]
    n = len(files)
    trials = []
    for i in range(n - 1):
        j = i + 1
        hist = [(i - k) % n for k in range(1, n) if (i - k) % n not in (i, j)][: a.history]
        db = os.path.join(tmp, f"trial{i}.sqlite")
        for k in hist:
            run([a.suite, "history", "add", files[k], "--db", db, "--commit", f"{k + 1:07x}aa00000", "--branch", "main"])
        trial = {"pair": [i, j], "history": hist}
        for f in (1.0,) + SLOWDOWNS:
            x, y = os.path.join(tmp, "x.json"), os.path.join(tmp, "y.json")
            json.dump(slowed(docs[i], f), open(x, "w"))
            json.dump(slowed(docs[j], f), open(y, "w"))
            out = run([a.suite, "history", "check", x, "--db", db, "--commit", "ffffff0", "--tolerance=auto", "--confirm", y],
                      ok=(0, 1)).stdout
            verdicts = {}
            for line in out.splitlines():
                m = re.match(r"(REGRESSED|improved|inconclusive)\s+(\S+) \S+ (\d+(?:\.\d+)?) ?(KiB|MiB|GiB|B) t=(\d+)\s.*bandwidth GB/s",
                             line)
                if m:
                    verdicts[f"{m.group(2)} {float(m.group(3)):g}{m.group(4)} t={m.group(5)}"] = m.group(1)
            trial[str(f)] = verdicts
            if f == 1.0:
                trial["aa_exit"] = "regressed" if "REGRESSED" in out else "passed"
            if i == 0 and f == 1.5:
                trial["example_output"] = out
        trials.append(trial)

rows = []
for name, pt in sorted(points.items()):
    row = {"point": name, "runs_sd": pt["sd"], "runs_qn": pt["qn"], "repetitions_spread": pt["rep_spread"],
           "unstable_runs": pt["unstable"], "runs": len(pt["medians"])}
    for f in SLOWDOWNS:
        row[f"caught_{f}"] = sum(t[str(f)].get(name) == "REGRESSED" for t in trials)
        row[f"inconclusive_{f}"] = sum(t[str(f)].get(name) == "inconclusive" for t in trials)
    row["aa_regressed"] = sum(t["1.0"].get(name) == "REGRESSED" for t in trials)
    rows.append(row)
aa = sum(t["aa_exit"] == "regressed" for t in trials)
doc = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "runs": len(files),
       "history": a.history, "trials": len(trials), "recipe": RECIPE, "elapsed_s": round(time.time() - started, 1),
       "aa_pairs_with_a_false_alarm": aa, "points": rows, "trials_detail": trials}
os.makedirs(a.out, exist_ok=True)
name = "gate_reach_quick" if a.quick else "gate_reach"
write_text(os.path.join(a.out, name + ".json"), json.dumps(doc, indent=1))
pc = lambda x: f"{100 * x:.1f} %"  # noqa: E731
lines = [f"# The history gate with {a.history} runs of history, {len(trials)} pairs ({doc['date']})", "",
         f"`suite {' '.join(RECIPE)}`, {len(files)} runs; each pair gated with `history check --tolerance=auto --confirm`.", "",
         "| point | runs' spread (sd, Qn) | repetitions' spread | runs flagged unstable | 1.25x caught (inconclusive) | 1.5x | 2x |",
         "|---|---|---|---|---|---|---|"]
for r in rows:
    cells = [f"{r[f'caught_{f}']}/{len(trials)} ({r[f'inconclusive_{f}']})" for f in SLOWDOWNS]
    lines.append(f"| {r['point']} | {pc(r['runs_sd'])}, {pc(r['runs_qn'])} | {pc(r['repetitions_spread'])} | "
                 f"{r['unstable_runs']}/{r['runs']} | " + " | ".join(cells) + " |")
lines += ["", f"A/A (both runs unchanged): {aa} of {len(trials)} pairs failed the gate."]
write_text(os.path.join(a.out, name + ".md"), "\n".join(lines) + "\n")
print("\n".join(lines))
