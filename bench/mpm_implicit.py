#!/usr/bin/python3
"""Implicit MPM by grid order: the time of a step split into assembly, solve and the rest.

From `suite` runs on this machine (nothing is timed here), one thread, the elastic dam collapse at
--dt-multiple times the explicit stable step, R rounds, each round every grid ordering:
  mpm-implicit-step      seconds per step (particles seeded, and dynamic: sorted with the grid's
                         active elements renumbered every --sort-every steps), Newton and CG
                         iterations per step (the record's facts)
  mpm-implicit-assembly  seconds per assembly (serial, particles sorted)
  mpm-implicit-solve     seconds per CG iteration, and CHOLMOD's analyse, factorise and solve
                         seconds for the same system (verify's reference, facts)
A step's split: assembly = (Newton + 1) assemblies, solve = CG iterations x seconds per
iteration, rest = the step less both (projection, update, locate, the pattern, the reordering).
The assembly is timed with the particles sorted along the curve (the kernel's order), so for the
seeded rows the difference their order makes to the assembly lands in "rest".
Medians over the rounds; each order against the natural grid with seeded particles of the same
round, the median of those ratios.

Usage: bench/mpm_implicit.py [--rounds 3] [--mesh box:32,32,32] [--out results/bench] [--quick]
Writes OUT/mpm_implicit.{json,md}.
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
p.add_argument("--mesh", default="box:32,32,32", help="the grid (default: 197 k tetrahedra, 100 k particles, 20 MB of particle arrays)")
p.add_argument("--orderings", default="natural,morton,hilbert")
p.add_argument("--dt-multiple", default="10")
p.add_argument("--quick", action="store_true")
a = p.parse_args()
if a.quick:
    a.rounds, a.mesh = 1, "box:10,10,10"
orderings = a.orderings.split(",")
tmp = tempfile.mkdtemp(prefix="mpm-implicit-")


def suite(args):
    out = os.path.join(tmp, "r.json")
    argv = [a.suite] + args + ["--mesh", a.mesh, "--dt-multiple", a.dt_multiple, "--threads", "1", "--reps", "5", "--out", out, "--quiet"]
    print("  " + " ".join(argv), file=sys.stderr, flush=True)
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"mpm_implicit: {' '.join(argv)} failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with open(out) as f:
        return json.load(f)["results"]


def fact(rec, name):
    f = (rec.get("facts") or {}).get(name)
    return f["value"] if f else None


def key(rec):
    return rec["ordering"], rec["variant"]


def median_rate(rec):
    """Units per second at the median repetition time."""
    return rec["work_per_repetition"]["units"] / rec["time_s"]["median"]


rows = {}  # (ordering, particles) -> per round dicts
for r in range(a.rounds):
    step = suite(["--kernel=mpm-implicit-step", "--ordering=" + a.orderings, "--particles=seeded,dynamic"])
    asm = {rec["ordering"]: rec for rec in suite(["--kernel=mpm-implicit-assembly", "--ordering=" + a.orderings, "--strategy=serial"])}
    sol = {key(rec): rec for rec in suite(["--kernel=mpm-implicit-solve", "--ordering=" + a.orderings, "--particles=seeded,dynamic"])}
    for rec in step:
        o, v = key(rec)
        np_ = fact(rec, "particles")
        step_s = np_ / median_rate(rec)
        newton, cg = fact(rec, "newton-per-step"), fact(rec, "cg-per-newton") * fact(rec, "newton-per-step")
        assemble_s = (newton + 1) * np_ / median_rate(asm[o])
        s = sol[(o, v)]
        solve_s = cg / median_rate(s)
        rows.setdefault((o, v), []).append({"step": step_s, "assembly": assemble_s, "solve": solve_s, "rest": step_s - assemble_s - solve_s,
                                            "newton": newton, "cg": cg, "cholmod_analyse": fact(s, "cholmod-analyse-seconds"), "cholmod": fact(s, "cholmod-factor-seconds"),
                                            "cholmod_solve": fact(s, "cholmod-solve-seconds"), "rows": fact(s, "rows"),
                                            "cg_per_solve": fact(s, "cg-iterations"), "particles": np_})

med = {k: {f: None if v[0][f] is None else statistics.median(d[f] for d in v) for f in v[0]} for k, v in rows.items()}
# Against the natural grid with seeded particles of the same round (the VM's state moves between
# rounds by more than the orders differ), then the median over the rounds.
parts = ("step", "assembly", "solve", "rest")
base_rounds = rows[("natural", "seeded")]
ratio = {k: {f: statistics.median(v[r][f] / base_rounds[r][f] for r in range(a.rounds)) for f in parts} for k, v in rows.items()}
report = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "command": sys.argv, "rounds": a.rounds, "mesh": a.mesh,
          "dt_multiple": a.dt_multiple, "points": {f"{o}/{v}": {**m, "vs_natural_seeded": ratio[(o, v)]} for (o, v), m in med.items()},
          "per_round": {f"{o}/{v}": r for (o, v), r in rows.items()}}
base = med[("natural", "seeded")]
lines = [f"# Implicit MPM by grid order ({report['date']}, {a.rounds} round(s), {a.mesh}, {a.dt_multiple}x the explicit step, 1 thread)", "",
         f"{int(base['particles'])} particles, {int(base['rows'])} rows. Seconds per step, medians over the rounds; in brackets the median over the rounds of "
         "each round's ratio to the natural grid with seeded particles.", "",
         "| grid / particles | step | assembly | solve (CG) | rest | Newton/step | CG/step | CHOLMOD factor |", "|---|---|---|---|---|---|---|---|"]
for (o, v), m in sorted(med.items(), key=lambda kv: (orderings.index(kv[0][0]), kv[0][1] != "seeded")):
    def cell(f):
        return f"{m[f]:.3f} ({ratio[(o, v)][f] - 1:+.1%})"
    cholmod = "not built" if m["cholmod"] is None else f"{m['cholmod']:.3f} s"
    lines.append(f"| {o} / {v} | {cell('step')} | {cell('assembly')} | {cell('solve')} | {cell('rest')} | {m['newton']:.2f} | {m['cg']:.0f} | {cholmod} |")
os.makedirs(a.out, exist_ok=True)
write_text(os.path.join(a.out, "mpm_implicit.json"), json.dumps(report, indent=1) + "\n")
write_text(os.path.join(a.out, "mpm_implicit.md"), "\n".join(lines) + "\n")
print("\n".join(lines))
