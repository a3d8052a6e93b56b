#!/usr/bin/python3
"""The timing gate's false alarms and reach on unchanged reruns of the CI recipe (an A/A test).

Runs `scripts/ci-gate.sh timing` N times (or takes the result files given with --from), stores
each run in a fresh history under a commit of its own, and measures on the same runs:
  - the gate against the history (`suite history noise`, leave one out: every run gated against
    the others, at --tolerance=auto with the band, alone and confirmed by the next run, and by the
    old rule, the pooled window alone, at 10 % and 25 %);
  - the gate against one baseline file (`suite check`, every pair of runs, at 10 % and 25 %);
  - its reach: each run and the next (its confirming rerun) slowed 1.25x (every repetition's time)
    and gated by `suite history check --tolerance=auto --confirm` against a history of the others;
    a point counts as steady when its band is narrower than the slowdown, and should regress.
Nothing changes between the runs, so every regression found before the slowdown is a false alarm.

Usage: bench/gate_noise.py [--runs 10] [--gap 20] [--from RUN.json ...] [--out results/bench] [--suite ./suite]
Writes OUT/gate_noise.{json,md}, and the reruns to OUT/gate_noise_runs/. --quick: 12 scaled copies of a committed fixture run, a check that it all runs.
"""
import argparse
import datetime
import json
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
p.add_argument("--runs", type=int, default=10, help="reruns of the CI recipe (default 10; at least 6)")
p.add_argument("--gap", type=float, default=20, help="seconds between reruns (default 20)")
p.add_argument("--from", dest="given", nargs="+", default=[], help="result files of earlier reruns, instead of running")
p.add_argument("--slowdown", type=float, default=1.25, help="the slowdown the gate must catch (default 1.25)")
p.add_argument("--quick", action="store_true", help="12 scaled copies of a committed fixture run: a check that it all runs")
a = p.parse_args()
if not a.given and not a.quick and a.runs < 6:
    print(f"gate_noise: --runs must be at least 6 (a band needs 5 other runs; got {a.runs})", file=sys.stderr)
    sys.exit(2)
if not (a.slowdown > 1):
    print(f"gate_noise: --slowdown must be above 1 (got {a.slowdown})", file=sys.stderr)
    sys.exit(2)


def run(argv, ok=(0,)):
    return gate_runs.run(argv, "gate_noise", ok)


slowed = gate_runs.slowed


started = time.time()
with tempfile.TemporaryDirectory() as tmp:
    files = list(a.given)
    if a.quick:
        files += gate_runs.quick_runs(top, tmp, 12, lambda i: 1 + 0.002 * ((i * 5) % 12 - 6))
    elif not files:
        # The reruns are kept, so that the rules can be measured on them again (--from).
        kept = os.path.join(a.out, "gate_noise_runs")
        os.makedirs(kept, exist_ok=True)
        for i in range(a.runs):
            if i:
                time.sleep(a.gap)
            files.append(os.path.join(kept, f"run{i:02d}.json"))
            run(["scripts/ci-gate.sh", "timing", files[-1]])
            print(f"rerun {i + 1}/{a.runs} done ({time.time() - started:.0f} s)", flush=True)
    db = os.path.join(tmp, "history.sqlite")
    commits = []
    for i, f in enumerate(files):
        commits.append(f"{i + 1:07x}aa00000")
        run([a.suite, "history", "add", f, "--db", db, "--commit", commits[-1], "--branch", "main"])

    def noise(*extra):
        out = run([a.suite, "history", "noise", "--db", db] + list(extra)).stdout
        m = re.search(r"(\d+) of (\d+) run\(s\) called regressed", out)
        return {"alarmed": int(m.group(1)), "tried": int(m.group(2))}

    history = {"auto, confirmed by a rerun": noise("--tolerance=auto", "--confirm"), "auto": noise("--tolerance=auto"),
               "band 10%": noise("--tolerance=10%"),
               "window 10%": noise("--tolerance=10%", "--without-band"), "window 25%": noise("--tolerance=25%", "--without-band")}
    pairs = {}
    for tol in ("10%", "25%"):
        alarmed, tried = 0, 0
        for i in range(len(files)):
            for j in range(i + 1, len(files)):
                r = run([a.suite, "check", "--baseline", files[i], files[j], f"--tolerance={tol}"], ok=(0, 1))
                alarmed += r.returncode == 1
                tried += 1
        pairs[tol] = {"alarmed": alarmed, "tried": tried}
    # The steady headline points: those whose band (of the latest window) is narrower than the
    # slowdown, where a gate could catch it at all.
    steady, headline = set(), set()
    for line in run([a.suite, "history", "noise", "--db", db, "--tolerance=auto"]).stdout.splitlines():
        m = re.match(r"(\S.*?)\s{2,}(bandwidth GB/s|latency ns/load)\s.*\[(\S+), (\S+)\]", line)
        if m:
            headline.add(m.group(1))
        if m and float(m.group(4)) / float(m.group(3)) < a.slowdown ** 2 * 0.99:
            steady.add(m.group(1))
    reach = []
    for i, f in enumerate(files):
        # Runs i and its confirming rerun j both slowed, gated against a history of the others.
        j = (i + 1) % len(files)
        trial_db = os.path.join(tmp, f"trial{i}.sqlite")
        for k, g in enumerate(files):
            if k not in (i, j):
                run([a.suite, "history", "add", g, "--db", trial_db, "--commit", commits[k], "--branch", "main"])
        slow, slow2 = os.path.join(tmp, "slow.json"), os.path.join(tmp, "slow2.json")
        json.dump(slowed(json.load(open(f)), a.slowdown), open(slow, "w"))
        json.dump(slowed(json.load(open(files[j])), a.slowdown), open(slow2, "w"))
        out = run([a.suite, "history", "check", slow, "--db", trial_db, "--commit", "ffffff0", "--tolerance=auto", "--confirm", slow2],
                  ok=(0, 1)).stdout
        caught = set()
        for line in out.splitlines():
            m = re.match(r"REGRESSED\s+(\S.*?)\s{2,}(bandwidth GB/s|latency ns/load)\s", line)
            if m:
                caught.add(m.group(1))
        reach.append({"run": i, "confirming_run": j, "steady_points": len(steady), "steady_caught": len(steady & caught), "caught": len(caught),
                      "missed": sorted(steady - caught), "exit": "regressed" if "REGRESSED" in out else "passed"})

doc = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "runs": len(files), "slowdown": a.slowdown,
       "elapsed_s": round(time.time() - started, 1), "history_leave_one_out": history, "pairs_suite_check": pairs, "reach": reach,
       "steady_points": sorted(steady), "headline_points": sorted(headline),
       "statistic": "runs with at least one regressed figure (history: each run left out in turn; pairs: every pair of runs)"}
os.makedirs(a.out, exist_ok=True)
name = "gate_noise_quick" if a.quick else "gate_noise"
write_text(os.path.join(a.out, name + ".json"), json.dumps(doc, indent=1))
lines = [f"# The timing gate on {len(files)} unchanged reruns ({doc['date']})", "",
         "| gate | rule | runs or pairs with a false alarm |", "|---|---|---|"]
for k, v in history.items():
    lines.append(f"| history check, leave one out | {k} | {v['alarmed']} of {v['tried']} |")
for k, v in pairs.items():
    lines.append(f"| check, every pair | {k} | {v['alarmed']} of {v['tried']} |")
exits = sum(r["exit"] == "regressed" for r in reach)
lines += ["", f"Each run and its confirming rerun (the next) slowed {a.slowdown}x and gated at --tolerance=auto --confirm against the others: "
          f"{exits} of {len(reach)} failed the gate. "
          f"Steady headline points (band narrower than the slowdown): {len(steady)} of {len(headline)}; caught in each run: " +
          ", ".join(f"{r['steady_caught']}/{r['steady_points']}" for r in reach) + "."]
write_text(os.path.join(a.out, name + ".md"), "\n".join(lines) + "\n")
print("\n".join(lines))
