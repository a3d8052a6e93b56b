#!/usr/bin/python3
"""Every sequential stream kernel of the suite against the best peer of its kind, interleaved on
this machine: likwid-bench's assembly, STREAM's loops built as stream.c's users build them
(gcc -O3 -march=native -fopenmp), and glibc's memcpy and memset per thread block (build/ref_stream).

Usage: bench/vs_peers.py [--rounds N] [--out DIR] [--suite ./suite] [--ref build/ref_stream] [--quick]
                         [--kinds copy,load]

Sizes: 32 KiB, 1 MiB, half the last level the cache probe measures (all instances), and 1 GiB
(DRAM), each the footprint of all arrays together; 1 thread and all threads, pinned compact
(likwid-bench pins to the same first CPUs). Each round measures, point by point and kind by kind,
the suite's variants of the kind and then its peers (or the peers first: the order alternates
between rounds), so that both sides of a ratio are seconds apart; the figure of a side is the
median over the rounds of its median sample (the suite's, ref_stream's: samples of at least 1 ms)
or of one likwid-bench run of about 2 ms (50 ms for its non-temporal kernels, whose first tens of
kilobytes of streaming stores are absorbed at core speed). GB/s by the STREAM convention.

Kinds and their peers:
  copy   copy_avx512, copy_mem_avx512 (likwid), stream-copy (STREAM's loop: GCC makes it a memcpy
         call), memcpy
  scale  stream-scale;  add  stream-add  (likwid-bench has neither)
  triad  stream_avx512, stream_mem_avx512 (likwid's STREAM triad), stream-triad
  load   load_avx512
  store  store_avx512, store_mem_avx512, memset
The suite's figure for a kind is its best variant at that point (plain, -nt, or -rep for copy and
store, the string instructions rep movsb / rep stosq: a user picks the one that suits the size);
all are in the JSON. Two ratios: of the sides' medians, and the median over the rounds of each
round's ratio (best variant over best peer). Writes DIR/vs_peers.{json,md}; with --kinds, only
those kinds, to DIR/vs_peers_KIND-KIND.{json,md} (a focused re-run leaves the whole table alone).
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plots"))
from safe_output import write_text  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
top = os.path.dirname(here)
ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--suite", default=os.path.join(top, "suite"))
ap.add_argument("--ref", default=os.path.join(top, "build", "ref_stream"))
ap.add_argument("--likwid", default=shutil.which("likwid-bench") or "/usr/bin/likwid-bench")
ap.add_argument("--out", default=os.path.join(top, "results", "bench"))
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--quick", action="store_true", help="32 KiB and 1 MiB, one thread, one round: a check that it all runs")
KINDS = {
    "copy": (["copy", "copy-nt", "copy-rep"], ["likwid:copy", "likwid:copy_mem", "ref:stream-copy", "ref:memcpy"]),
    "scale": (["scale", "scale-nt"], ["ref:stream-scale"]),
    "add": (["add", "add-nt"], ["ref:stream-add"]),
    "triad": (["triad", "triad-nt"], ["likwid:stream", "likwid:stream_mem", "ref:stream-triad"]),
    "load": (["load"], ["likwid:load"]),
    "store": (["store", "store-nt", "store-rep"], ["likwid:store", "likwid:store_mem", "ref:memset"]),
}
ap.add_argument("--kinds", help=f"a comma-separated subset of {', '.join(KINDS)} (default all)")
a = ap.parse_args()

KiB, MiB, GiB = 1 << 10, 1 << 20, 1 << 30
if a.kinds is not None:
    chosen = [k for k in a.kinds.split(",") if k]
    unknown = [k for k in chosen if k not in KINDS]
    if unknown or not chosen:
        print(f"vs_peers: --kinds={a.kinds}: {'unknown kind ' + unknown[0] if unknown else 'no kind given'}; "
              f"accepted: a comma-separated subset of {', '.join(KINDS)}", file=sys.stderr)
        sys.exit(2)
    KINDS = {k: v for k, v in KINDS.items() if k in chosen}


def run(argv):
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"vs_peers: {' '.join(argv)} failed with status {r.returncode}: {r.stderr.strip()[-500:]}")
    return r.stdout


info = json.loads(run([a.suite, "info", "--probe", "--json"]))
width = "avx512" if info["instruction_set"]["avx512f"] else "avx"
llc = info.get("caches_measured", {}).get("last_level_total_bytes") or 8 * MiB
threads_all = len(os.sched_getaffinity(0))
sizes = [32 * KiB, 1 * MiB] + ([] if a.quick else [llc // 2 // 4096 * 4096, 1 * GiB])
thread_counts = [1] if a.quick else sorted({1, threads_all})
rounds = 1 if a.quick else a.rounds
have_likwid = os.access(a.likwid, os.X_OK)
# Without likwid-bench its peers are left out, and a kind whose only peer it is (load) has no row:
# said once here and in both outputs, so that no table passes for a comparison it is not.
missing = ("" if have_likwid else
           f"likwid-bench not found at {a.likwid}: its peers are left out"
           + (" and the load kind has no row" if "load" in KINDS else "") + " (`make bench-deps` installs it)")
if missing:
    print(f"vs_peers: {missing}", file=sys.stderr, flush=True)


STORES = {"": "default", "nt": "nt", "rep": "rep"}


def suite_side(kind, size, threads, tmp):
    """{name: median GB/s} of the suite's variants of one kind at this point (a run per --stores)."""
    out, figures = os.path.join(tmp, "s.json"), {}
    for name in KINDS[kind][0]:
        variant = name.split("-", 1)[1] if "-" in name else ""
        run([a.suite, f"--kernel={kind}", f"--stores={STORES[variant]}", f"--size={size}", f"--threads={threads}", "--pin=compact",
             "--counters=none", "--energy=none", "--quiet", f"--out={out}"])
        for r in json.load(open(out))["results"]:
            if not r["verification"]["passed"]:
                sys.exit(f"vs_peers: the suite's {r['name']} failed verification")
            figures[r["name"]] = r["bandwidth_gbps"]["stream"]["median"]
    return figures


def ref_side(kernels, size, threads):
    env = dict(os.environ, OMP_PROC_BIND="close", OMP_PLACES="cores")
    r = subprocess.run([a.ref, ",".join(kernels), str(size), str(threads)], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"vs_peers: ref_stream failed: {r.stderr.strip()}")
    figures = {}
    for line in r.stdout.splitlines():
        x = json.loads(line)
        if not x["verified"]:
            sys.exit(f"vs_peers: ref_stream's {x['kernel']} failed its check")
        figures["ref:" + x["kernel"]] = x["gbps_median"]
    return figures


def likwid_side(names, size, threads, guess):
    figures = {}
    if not have_likwid:
        return figures
    for name in names:
        test = f"{name.replace('_mem', '')}_mem_{width}" if name.endswith("_mem") else f"{name}_{width}"
        seconds = 0.05 if name.endswith("_mem") else 0.002
        per_call = size / max(guess, 1.0) / 1e9
        iters = max(10, int(seconds / max(per_call, 1e-9)))
        text = run([a.likwid, "-t", test, "-W", f"S0:{size}B:{threads}", "-i", str(iters)])
        figures["likwid:" + name] = float(re.search(r"^MByte/s:\s+([0-9.]+)", text, re.M).group(1)) / 1e3
    return figures


def peer_side(kind, size, threads, guess):
    peers = KINDS[kind][1]
    ref = [p.split(":", 1)[1] for p in peers if p.startswith("ref:")]
    lik = [p.split(":", 1)[1] for p in peers if p.startswith("likwid:")]
    return {**(ref_side(ref, size, threads) if ref else {}), **likwid_side(lik, size, threads, guess)}


# Each kind's suite variants and its peers run back to back, so that the two sides of a ratio
# are seconds apart (this VM's bandwidth changes state from one minute to the next); which side
# goes first alternates from round to round, so that a drift within the pair cancels.
samples, guesses = {}, {}
with tempfile.TemporaryDirectory() as tmp:
    for k in range(rounds):
        for threads in thread_counts:
            for size in sizes:
                for kind in KINDS:
                    # likwid-bench's iteration count comes from the last figure at this point
                    # (about 2 ms runs, 50 ms for its non-temporal kernels).
                    guess = guesses.get((threads, size), 200.0 if size < 64 * MiB else 30.0)
                    sides = [lambda: suite_side(kind, size, threads, tmp), lambda: peer_side(kind, size, threads, guess)]
                    fig = {}
                    for side in (sides if k % 2 == 0 else sides[::-1]):
                        fig.update(side())
                    if kind == "copy" and "copy" in fig:
                        guesses[(threads, size)] = fig["copy"]
                    for name, v in fig.items():
                        samples.setdefault((threads, size, name), []).append(v)
                print(f"round {k + 1}/{rounds}: {threads} thread(s), {size} B", file=sys.stderr, flush=True)

med = {key: statistics.median(v) for key, v in samples.items()}
rows, worst = [], []
for threads in thread_counts:
    for size in sizes:
        for kind, (ours, peers) in KINDS.items():
            mine = {n: med[(threads, size, n)] for n in ours if (threads, size, n) in med}
            theirs = {n: med[(threads, size, n)] for n in peers if (threads, size, n) in med}
            if not mine or not theirs:
                continue
            best_mine, best_peer = max(mine, key=mine.get), max(theirs, key=theirs.get)
            ratio = mine[best_mine] / theirs[best_peer]
            # Round by round, the suite's best variant over the best peer: the two sides of a
            # round's ratio were seconds apart, so a change of the machine's state between rounds
            # cancels in it.
            per_round = [max(samples[(threads, size, n)][r] for n in mine) / max(samples[(threads, size, n)][r] for n in theirs)
                         for r in range(rounds)]
            rows.append({"threads": threads, "size_bytes": size, "kind": kind, "suite": mine, "peers": theirs, "suite_best": best_mine,
                         "peer_best": best_peer, "ratio": ratio, "round_ratios": per_round, "paired_ratio": statistics.median(per_round)})


def size_text(n):
    for unit, scale in (("GiB", GiB), ("MiB", MiB), ("KiB", KiB)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n} B"


md = ["| threads | size | kind | suite (its best) GB/s | best peer GB/s | suite / peer | median of the rounds' ratios |",
      "| --- | --- | --- | --- | --- | --- | --- |"]
for r in rows:
    md.append(f"| {r['threads']} | {size_text(r['size_bytes'])} | {r['kind']} | {r['suite'][r['suite_best']]:.1f} ({r['suite_best']}) | "
              f"{r['peers'][r['peer_best']]:.1f} ({r['peer_best']}) | {r['ratio']:.3f} | {r['paired_ratio']:.3f} |")
if missing:
    md += ["", f"Not a comparison with every peer: {missing}."]
text = "\n".join(md) + "\n"
print(text)
os.makedirs(a.out, exist_ok=True)
suffix = ("_quick" if a.quick else "") + ("_" + "-".join(KINDS) if a.kinds is not None else "")
write_text(os.path.join(a.out, f"vs_peers{suffix}.json"), json.dumps({"rounds": rounds, "rows": rows, "cpu": info.get("cpu_model"),
                                                                          "peers_left_out": missing or None}, indent=1) + "\n")
write_text(os.path.join(a.out, f"vs_peers{suffix}.md"), text)
