#!/usr/bin/python3
"""fem-spmv's storages side by side, against the read ceiling measured in the same session.

Each round runs, one after another:
  suite --kernel=load --sizes=SIZE --threads=T            the read ceiling (s += b[i], DRAM-sized)
  suite --kernel=fem-spmv --mesh=M --ordering=O --strategy=csr,symmetric,sell --threads=T   per ordering
and the table gives, per ordering and thread count, the median over the rounds of each point's
median time: CSR's GB/s (STREAM convention) as a fraction of load's, the other storages' speed-ups
over CSR (time ratios, the same nonzeros), the best storage's GB/s counted from the bytes CSR moves
(its own savings a credit, SELL's padding a cost) as a fraction of load's, and the storages' facts
(far entries, bytes a nonzero, SELL's padding).
With --solvers, fem-cg and fem-eigen run once each way on --solver-mesh as well.

  /usr/bin/python3 bench/spmv_strategies.py                       # thesis mesh refine=4, 3 rounds
  /usr/bin/python3 bench/spmv_strategies.py --rounds=5 --json=results/bench/spmv_strategies.json
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def run_suite(suite, args, out):
    cmd = [suite] + args + ["--quiet", "--out=" + out]
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit("spmv_strategies: " + " ".join(cmd) + " failed (" + str(done.returncode) + "): " + done.stderr.strip())
    with open(out) as f:
        return json.load(f)["results"]


def facts(r):
    return {k: v["value"] for k, v in r.get("facts", {}).items()}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--suite", default=os.path.join(HERE, "..", "build", "suite"))
    p.add_argument("--mesh", default="file:../shared/meshes/unit_circle_fine.txt:refine=4")
    p.add_argument("--orderings", default="natural,morton,hilbert,rcm")
    p.add_argument("--threads", default="1,2")
    p.add_argument("--load-size", default="1GiB")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--strategies", default="csr,symmetric,sell", help="fem-spmv's --strategy list; csr first (the ratios' base)")
    p.add_argument("--reps", type=int, default=10)
    p.add_argument("--solvers", action="store_true", help="also fem-cg and fem-eigen, once, on --solver-mesh")
    p.add_argument("--solver-mesh", default="file:../shared/meshes/unit_circle_fine.txt:refine=1")
    p.add_argument("--json", help="write the table's figures here")
    o = p.parse_args()
    if o.rounds < 1:
        sys.exit("spmv_strategies: --rounds must be at least 1")
    orderings = o.orderings.split(",")
    times = {}  # (kernel-variant, ordering or "", threads) -> [median time of each round]
    rates = {}  # load: GB/s medians
    fact = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "r.json")
        for rnd in range(o.rounds):
            print(f"round {rnd + 1} of {o.rounds}", file=sys.stderr, flush=True)
            for r in run_suite(o.suite, ["--kernel=load", "--sizes=" + o.load_size, "--threads=" + o.threads, f"--reps={o.reps}"], out):
                rates.setdefault(r["threads"], []).append(r["bandwidth_gbps"]["stream"]["median"])
            for ordering in orderings:
                args = ["--kernel=fem-spmv", "--mesh=" + o.mesh, "--ordering=" + ordering, "--strategy=" + o.strategies, "--threads=" + o.threads,
                        f"--reps={o.reps}"]
                for r in run_suite(o.suite, args, out):
                    key = (r["variant"] or "csr", ordering, r["threads"])  # csr is the plain kernel, variant ""
                    times.setdefault(key, []).append(r["time_s"]["median"])
                    fact[key] = (facts(r), r["work_per_repetition"])
        solver_rows = []
        if o.solvers:
            for kernel in ("fem-cg", "fem-eigen"):
                args = ["--kernel=" + kernel, "--mesh=" + o.solver_mesh, "--ordering=hilbert,rcm", "--strategy=" + o.strategies,
                        "--threads=" + o.threads, "--reps=3"]
                for r in run_suite(o.suite, args, out):
                    solver_rows.append({"kernel": kernel, "strategy": r["variant"], "ordering": r["ordering"], "threads": r["threads"],
                                        "median_s": r["time_s"]["median"], "cg_iterations_per_s": r["work_per_repetition"]["units"] / r["time_s"]["median"]})
    med = {k: statistics.median(v) for k, v in times.items()}
    load = {t: statistics.median(v) for t, v in rates.items()}
    rows = []
    print(f"mesh {o.mesh}, {o.rounds} round(s), medians of the rounds' medians; load at {o.load_size}: " +
          ", ".join(f"{t} t {g:.1f} GB/s" for t, g in sorted(load.items())))
    others = [x for x in o.strategies.split(",") if x != "csr"]
    print("| ordering | threads | CSR ms | CSR GB/s | of load | " + " | ".join(f"{x} ms | speed-up" for x in others) +
          " | best | best's GB/s (CSR bytes) | of load | far entries | B/nnz CSR | B/nnz sym | SELL padding |")
    print("|" + " --- |" * (12 + 2 * len(others)))
    for ordering in orderings:
        for t in sorted(load):
            c = med.get(("csr", ordering, t))
            if c is None or any(med.get((x, ordering, t)) is None for x in others):
                continue
            f = {}
            for x in others:
                f.update(fact[(x, ordering, t)][0])
            csr_bytes = fact[("csr", ordering, t)][1]["stream_bytes"]
            gbs = csr_bytes / c / 1e9
            best = min(["csr"] + others, key=lambda x: med[(x, ordering, t)])
            best_gbs = csr_bytes / med[(best, ordering, t)] / 1e9
            row = {"ordering": ordering, "threads": t, "csr_ms": c * 1e3, "csr_gbps": gbs, "csr_of_load": gbs / load[t],
                   "best": best, "best_gbps_csr_bytes": best_gbs, "best_of_load": best_gbs / load[t],
                   "far_entries": f.get("far-entries"), "csr_bytes_per_nnz": f.get("csr-bytes-per-nnz"),
                   "symmetric_bytes_per_nnz": f.get("symmetric-bytes-per-nnz"), "sell_padding": f.get("padding"),
                   "rounds_csr_ms": [x * 1e3 for x in times[("csr", ordering, t)]]}
            for x in others:
                row[f"{x}_ms"] = med[(x, ordering, t)] * 1e3
                row[f"{x}_speedup"] = c / med[(x, ordering, t)]
                row[f"rounds_{x}_ms"] = [y * 1e3 for y in times[(x, ordering, t)]]
            rows.append(row)
            num = lambda v, fmt: "-" if v is None else format(v, fmt)  # noqa: E731
            print(f"| {ordering} | {t} | {row['csr_ms']:.2f} | {gbs:.1f} | {row['csr_of_load']:.2f} | " +
                  " | ".join(f"{row[x + '_ms']:.2f} | {row[x + '_speedup']:.2f}" for x in others) +
                  f" | {best} | {best_gbs:.1f} | {row['best_of_load']:.2f} | {num(row['far_entries'], '.4f')} | "
                  f"{num(row['csr_bytes_per_nnz'], '.2f')} | {num(row['symmetric_bytes_per_nnz'], '.2f')} | {num(row['sell_padding'], '.4f')} |")
    for s in solver_rows:
        print(f"{s['kernel']} {s['strategy']} {s['ordering']} {s['threads']} t: {s['median_s']:.3f} s, {s['cg_iterations_per_s']:.0f} CG iterations/s")
    if o.json:
        with open(o.json, "w") as f:
            json.dump({"mesh": o.mesh, "rounds": o.rounds, "load_gbps": load, "spmv": rows, "solvers": solver_rows}, f, indent=1)


if __name__ == "__main__":
    main()
