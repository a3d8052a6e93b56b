#!/usr/bin/python3
"""Distributed SpMV against the threaded one on the same cores: what the halo exchange costs, and
the curve's partition beside METIS's (issue 16).

Per round, on one mesh and ordering: fem-spmv threaded on 1 and 2 threads (suite), then
fem-spmv-dist with both partitions on 1 rank and on 2 ranks of one thread each (suite-mpi under
mpirun). The 2-rank job and the 2-thread run use the same two cores and the same matrix; the
difference is the halo exchange and the ranks' synchronisation. Figures are the median over the
rounds of each configuration's median time per product (the aggregate record for the MPI runs),
and each one's ratio to the threaded run on as many cores, taken within a round.

Usage: bench/fem_dist.py [--mesh SPEC] [--ordering hilbert] [--rounds 3] [--reps 30] [--out results/bench]
Writes OUT/fem_dist.{json,md}.
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
p.add_argument("--suite", default=os.path.join(top, "build", "suite"))
p.add_argument("--suite-mpi", default=os.path.join(top, "build", "suite-mpi"))
p.add_argument("--mesh", default="file:" + os.path.join(top, "..", "shared", "meshes", "unit_circle_fine.txt") + ":refine=2")
p.add_argument("--ordering", default="hilbert")
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--reps", type=int, default=30)
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
a = p.parse_args()
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
tmp = tempfile.mkdtemp(prefix="fem-dist-")
common = ["--ordering=" + a.ordering, "--mesh=" + a.mesh, "--reps=%d" % a.reps, "--quiet"]


def records(argv):
    out = os.path.join(tmp, "r.json")
    if os.path.exists(out):
        os.remove(out)
    print("  " + " ".join(argv), file=sys.stderr, flush=True)
    subprocess.run(argv + ["--out=" + out], env=env, check=True)
    return json.load(open(out))["results"]


def facts(rec, name):
    return rec.get("facts", {}).get(name, {}).get("value")


rows = {}  # configuration -> list per round of {"median": s, "best": s, ...}
for rnd in range(a.rounds):
    print("round %d of %d" % (rnd + 1, a.rounds), file=sys.stderr, flush=True)
    for rec in records([a.suite, "--kernel=fem-spmv", "--threads=1,2"] + common):
        rows.setdefault("threaded, %d thread(s)" % rec["threads"], []).append(
            {"cores": rec["threads"], "median": rec["time_s"]["median"], "best": rec["time_s"]["min"]})
    for np in (1, 2):
        recs = records(["mpirun", "-np", str(np), a.suite_mpi, "--kernel=fem-spmv-dist", "--strategy=curve,metis", "--threads=1"] + common)
        for rec in recs:
            if rec["mpi"]["scope"] != "aggregate":
                continue
            ranks = [r for r in recs if r["mpi"]["scope"] == "rank" and r["name"] == rec["name"]]
            rows.setdefault("%s, %d rank(s)" % (rec["variant"], np), []).append(
                {"cores": np, "median": rec["time_s"]["median"], "best": rec["time_s"]["min"],
                 "halo": sum(facts(r, "halo") or 0 for r in ranks), "edge_cut": facts(rec, "edge-cut"),
                 "imbalance_nnz": facts(rec, "imbalance-nnz"), "spread": rec["mpi"]["spread"]})

summary = []
for name, runs in rows.items():
    threaded = rows["threaded, %d thread(s)" % runs[0]["cores"]]
    ratios = [r["median"] / t["median"] for r, t in zip(runs, threaded)]
    summary.append({"configuration": name, "cores": runs[0]["cores"],
                    "median_ms": 1e3 * statistics.median(r["median"] for r in runs),
                    "best_ms": 1e3 * min(r["best"] for r in runs),
                    "vs_threaded_same_cores": statistics.median(ratios),
                    "halo_values": runs[0].get("halo"), "edge_cut": runs[0].get("edge_cut"),
                    "imbalance_nnz": runs[0].get("imbalance_nnz")})

md = ["# Distributed SpMV against threaded, %s, %s order" % (a.mesh.split("/")[-1], a.ordering), "",
      "%s; %d rounds of %d repetitions; medians over rounds of each median time per product." %
      (datetime.date.today().isoformat(), a.rounds, a.reps), "",
      "| configuration | cores | median ms | best ms | time / threaded on as many cores | halo values (all ranks) | edge cut | nnz imbalance |",
      "|---|---|---|---|---|---|---|---|"]
for s in summary:
    md.append("| %s | %d | %.3f | %.3f | %.2fx | %s | %s | %s |" % (
        s["configuration"], s["cores"], s["median_ms"], s["best_ms"], s["vs_threaded_same_cores"],
        "" if s["halo_values"] is None else "%d" % s["halo_values"], "" if s["edge_cut"] is None else "%d" % s["edge_cut"],
        "" if s["imbalance_nnz"] is None else "%.3f" % s["imbalance_nnz"]))
os.makedirs(a.out, exist_ok=True)
write_text(os.path.join(a.out, "fem_dist.json"), json.dumps({"mesh": a.mesh, "ordering": a.ordering, "rounds": a.rounds,
                                                               "reps": a.reps, "summary": summary, "runs": rows}, indent=1) + "\n")
write_text(os.path.join(a.out, "fem_dist.md"), "\n".join(md) + "\n")
print("\n".join(md))
