#!/usr/bin/python3
"""The suite side by side with the references, on this machine, in one session: likwid-bench's
hand-written assembly for copy, STREAM triad, load and store (plain, AVX-512 and non-temporal),
and plain C loops (bench/ref_random) for the suite's random kernels. Interleaved repetitions;
prints the ratios suite/reference of the medians and writes results/bench/vs_likwid.{json,md}.

Usage: bench/vs_likwid.py [--quick] [--reps N] [--out DIR] [--suite ./suite] [--ref build/ref_random]
       bench/vs_likwid.py --merge A.json B.json ... [--out DIR]   (pools the repetitions of several runs)

Like with like:
  * sizes: likwid-bench's -W S0:SIZE:T is the size of all streams together, split over the T
    threads; the suite's --size is the footprint of all arrays together, split the same way. The
    same number of bytes is given to both (in bytes: likwid's kB/MB are powers of 1000).
  * bytes: likwid-bench's MByte/s counts 8 B per element of every stream (1 MB = 1e6 B), as
    STREAM does and the suite does (1 GB = 1e9 B); both are converted to GB/s.
  * ratio: the median over the repetitions of each repetition's suite/reference, whose two
    figures were taken seconds apart (the memory bandwidth of a shared machine drifts between
    states over minutes); the ratio of the two sides' medians is in the JSON too.
  * statistic: on a machine shared with other jobs a long run's average is mostly a measure of
    how often another process took a CPU (one lost time slice stalls a whole parallel region),
    so both sides are timed in windows of about the same length and medians of windows are
    compared: the suite's samples (each at least 1 ms of back-to-back calls; its median sample
    per run) and likwid-bench runs of about --window seconds (at least 10 iterations), each side
    the median over the interleaved repetitions. The non-temporal kernels get likwid-bench runs
    of --window-nt seconds: a run starts with the memory system's write queues empty, and its
    first tens of kilobytes of streaming stores are absorbed at core speed, which in a 2 ms
    window doubled the figure now and then; the suite's samples are in the steady state. The JSON also holds best against best (the
    suite's best sample, likwid-bench's best run) and the suite's mean. The random kernels and
    their plain loops both take the median of samples timed the same way.
  * threads: likwid-bench pins its threads to the first hardware threads of socket 0; the suite
    pins --pin=compact (the first core, then the next); the script checks that they are the same
    CPUs. The reference loops get OMP_PROC_BIND=close OMP_PLACES=cores.
  * the suite runs with --counters=none --energy=none (no instrument reads between repetitions).
Pairs: copy ~ copy_avx512, copy-nt ~ copy_mem_avx512, triad ~ stream_avx512 (likwid's "stream" is
STREAM triad a = b + s*c; its "triad" is a = b*c + d, four streams), triad-nt ~ stream_mem_avx512,
load ~ load_avx512, store ~ store_avx512, store-nt ~ store_mem_avx512 (the _avx ones on a machine
without AVX-512).
"""
import argparse
import datetime
import json
import math
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
p.add_argument("--ref", default=os.path.join(top, "build", "ref_random"))
p.add_argument("--likwid", default=shutil.which("likwid-bench") or "/usr/bin/likwid-bench")
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--reps", type=int, default=3, help="interleaved repetitions of every point (default 3)")
p.add_argument("--seconds", type=float, default=0.2, help="the suite's --min-time per point (default 0.2)")
p.add_argument("--window", type=float, default=0.002, help="seconds of one likwid-bench run (default 0.002, about one suite sample; at least 10 iterations)")
p.add_argument("--window-nt", type=float, default=0.05, help="seconds of one likwid-bench run of a non-temporal kernel (default 0.05)")
p.add_argument("--hugepages", default="system", help="the suite's --hugepages (default system: as likwid-bench, no advice)")
p.add_argument("--thp-from", default="256MiB", help="at this size and above the suite also runs with --hugepages=thp, a second "
               "column (default 256MiB, so the 1 GiB points; 0 leaves it out)")
p.add_argument("--merge", nargs="+", metavar="JSON", help="measure nothing: pool the repetitions of earlier runs' vs_likwid.json")
p.add_argument("--quick", action="store_true", help="two small sizes, one thread, one repetition: a check that it all runs (seconds)")
a = p.parse_args()

KiB, MiB, GiB = 1 << 10, 1 << 20, 1 << 30
thp_from = int(a.thp_from.removesuffix("MiB")) * MiB if a.thp_from.endswith("MiB") else int(a.thp_from)
threads_all = len(os.sched_getaffinity(0))
if a.quick:
    sizes, thread_counts, reps = [32 * KiB, 1 * MiB], [1], 1
    random_sizes, random_kernels = [32 * KiB, 1 * MiB], ["add", "latency"]
else:
    sizes, thread_counts, reps = [32 * KiB, 1 * MiB, 16 * MiB, 1 * GiB], sorted({1, threads_all}), a.reps
    random_sizes, random_kernels = [32 * KiB, 1 * MiB, 16 * MiB], ["add", "triad", "sin-add", "load", "store", "latency"]


def run(argv, env=None):
    r = subprocess.run(argv, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"vs_likwid: {' '.join(argv)} failed with status {r.returncode}:\n{r.stderr[-2000:]}")
    return r.stdout


def loadavg():
    return [round(x, 2) for x in os.getloadavg()]


info = json.loads(run([a.suite, "info", "--json"]))
avx512 = info["instruction_set"]["avx512f"]
w = "avx512" if avx512 else "avx"
pairs = [("copy", "", f"copy_{w}"), ("copy", "nt", f"copy_mem_{w}"), ("triad", "", f"stream_{w}"), ("triad", "nt", f"stream_mem_{w}"),
         ("load", "", f"load_{w}"), ("store", "", f"store_{w}"), ("store", "nt", f"store_mem_{w}")]
if a.quick:
    pairs = [pairs[0], pairs[4]]
have_likwid = os.access(a.likwid, os.X_OK)
if not have_likwid:
    print(f"vs_likwid: {a.likwid} not found (Debian package likwid; make bench-vs installs it): the likwid-bench comparison is left out")


def suite_points(size, threads, variant, kernels, tmp, pattern="sequential", hugepages=None):
    """One suite run over `kernels`; {(kernel, variant): record}."""
    out = os.path.join(tmp, "suite.json")
    argv = [a.suite, "--kernel=" + ",".join(kernels), f"--pattern={pattern}", f"--size={size}", f"--threads={threads}", "--pin=compact",
            f"--min-time={a.seconds}", f"--hugepages={hugepages or a.hugepages}", "--counters=none", "--energy=none"] + (["--stores=" + variant] if variant else []) + ["--quiet", f"--out={out}"]
    run(argv)
    recs = {}
    for r in json.load(open(out))["results"]:
        if not r["verification"]["passed"]:
            sys.exit(f"vs_likwid: the suite's {r['name']} failed verification: {r['verification']['detail']}")
        recs[(r["kernel"], r["variant"])] = r
    return recs, argv


def likwid_point(test, size, threads, seconds_per_call):
    # likwid-bench has no warm-up: below DRAM sizes, at least 50 iterations, so that a first pass
    # over data that other processes evicted while it slept is a small part of the run.
    window = a.window_nt if "_mem" in test else a.window
    iters = max(10 if size >= 256 * MiB else 50, math.ceil(window / max(seconds_per_call, 1e-9)))
    argv = [a.likwid, "-t", test, "-W", f"S0:{size}B:{threads}", "-i", str(iters)]
    text = run(argv)
    mbs = float(re.search(r"^MByte/s:\s+([0-9.]+)", text, re.M).group(1))
    volume = float(re.search(r"^Data volume \(Byte\):\s+([0-9.]+)", text, re.M).group(1))
    secs = float(re.search(r"^Time:\s+([0-9.e+-]+)", text, re.M).group(1))
    cpus = sorted(int(c) for c in re.findall(r"Global Thread \d+ running on (?:hwthread|core) (\d+)", text))
    # MByte/s is the data volume over the time, in 1e6 B/s: check that it counts what we think.
    if abs(volume / secs / 1e6 - mbs) > 0.02 * mbs:
        sys.exit(f"vs_likwid: likwid-bench's MByte/s ({mbs}) is not its data volume over its time ({volume / secs / 1e6:.0f})")
    return mbs / 1e3, cpus, argv


def ref_points(kernels, size, threads):
    env = dict(os.environ, OMP_PROC_BIND="close", OMP_PLACES="cores")
    argv = [a.ref, ",".join(kernels), str(size), str(threads)]
    out = {}
    for line in run(argv, env).splitlines():
        r = json.loads(line)
        if not r["verified"]:
            sys.exit(f"vs_likwid: ref_random's {r['kernel']} failed its check")
        out[r["kernel"]] = r
    return out, argv


def label(size):
    for unit, n in (("GiB", GiB), ("MiB", MiB), ("KiB", KiB)):
        if size % n == 0:
            return f"{size // n}{unit}"
    return f"{size}B"


def suite_rate_mean(rec):
    return rec["work_per_repetition"]["stream_bytes"] / rec["time_s"]["mean"] / 1e9


started = time.time()
load_before = loadavg()
lk = {}   # (kernel, variant, size, threads) -> {"suite": [...], "likwid": [...], ...}
per_call = {}  # (kernel, variant, size, threads) -> the suite's latest mean seconds per call
rnd = {}  # (kernel, size, threads) -> {"suite": [...], "ref": [...]}
commands = []
pin_mismatch = []
runs = 1
if a.merge:
    # Every repetition of every run, as if they had been one run; nothing is measured.
    docs = [json.load(open(f)) for f in a.merge]
    runs, reps = len(docs), 0
    load_before = [d["load_average_before"] for d in docs]
    load_after_runs = [d["load_average_after"] for d in docs]
    commands = docs[0]["commands"]
    for d in docs:
        for r in d["likwid"]:
            kernel, _, variant = r["suite"].partition("-")
            e = lk.setdefault((kernel, variant, r["size_bytes"], r["threads"]),
                              {"suite": [], "suite_best": [], "suite_mean": [], "likwid": [], "likwid_test": r["likwid"]})
            for key, src in (("suite", "suite_gbps"), ("suite_best", "suite_best_gbps"), ("suite_mean", "suite_mean_gbps"), ("likwid", "likwid_gbps"),
                             ("suite_thp", "suite_thp_gbps"), ("suite_thp_huge_bytes", "suite_thp_huge_bytes")):
                if src in r:
                    e.setdefault(key, [])
                    e[key] += r[src]
            e["suite_cpus"], e["likwid_cpus"] = r["suite_cpus"], r["likwid_cpus"]
        for r in d["random"]:
            e = rnd.setdefault((r["kernel"], r["size_bytes"], r["threads"]), {"suite": [], "ref": []})
            e["suite"] += r["suite"]
            e["ref"] += r["ref"]
        pin_mismatch += [tuple(m) for m in d["pinning_mismatches"]]
    sizes = sorted({k[2] for k in lk})
    thread_counts = sorted({k[3] for k in lk} | {k[2] for k in rnd})
    random_sizes = sorted({k[1] for k in rnd})
    random_kernels = [k for k in ["add", "triad", "sin-add", "load", "store", "latency"] if any(key[0] == k for key in rnd)]
with tempfile.TemporaryDirectory() as tmp:
    for rep in range(reps):
        points = [(s, t) for s in sizes for t in thread_counts]
        if rep % 2:
            points.reverse()
        for size, threads in points:
            if not have_likwid:
                break
            recs = {}

            def suite_side():
                for variant in ("", "nt"):
                    ks = [k for k, v, _ in pairs if v == variant]
                    if ks:
                        recs[variant], argv = suite_points(size, threads, variant, ks, tmp)
                        if rep == 0:
                            commands.append(" ".join(argv[:-2] + ["--quiet", "--out=FILE"]))
                    # The same points with transparent huge pages asked for, at DRAM sizes, where
                    # fewer TLB misses can show; likwid-bench gets whatever the system gives.
                    if ks and thp_from and size >= thp_from:
                        recs["thp:" + variant], argv = suite_points(size, threads, variant, ks, tmp, hugepages="thp")
                        if rep == 0:
                            commands.append(" ".join(argv[:-2] + ["--quiet", "--out=FILE"]))
                for kernel, variant, _ in pairs:
                    per_call[(kernel, variant, size, threads)] = recs[variant][(kernel, variant)]["time_s"]["median"]

            def likwid_side():
                for kernel, variant, test in pairs:
                    key = (kernel, variant, size, threads)
                    gbps, cpus, argv = likwid_point(test, size, threads, per_call[key])
                    e = lk.setdefault(key, {"suite": [], "suite_best": [], "suite_mean": [], "likwid": [], "likwid_test": test})
                    e["likwid"].append(gbps)
                    e["likwid_cpus"] = cpus
                    if rep == 0:
                        commands.append(" ".join(argv))

            # Who goes first alternates with the repetition (the first always starts with the
            # suite, whose time per call sets likwid-bench's iteration count).
            for side in ((suite_side, likwid_side) if rep % 2 == 0 else (likwid_side, suite_side)):
                side()
            for kernel, variant, _ in pairs:
                e = lk[(kernel, variant, size, threads)]
                rec = recs[variant][(kernel, variant)]
                e["suite"].append(rec["bandwidth_gbps"]["stream"]["median"])
                e["suite_best"].append(rec["bandwidth_gbps"]["stream"]["best"])
                e["suite_mean"].append(suite_rate_mean(rec))
                e["suite_cpus"] = sorted(t["cpu"] for t in rec["pin"]["threads"])
                if "thp:" + variant in recs:
                    thp = recs["thp:" + variant][(kernel, variant)]
                    e.setdefault("suite_thp", []).append(thp["bandwidth_gbps"]["stream"]["median"])
                    e.setdefault("suite_thp_huge_bytes", []).append(sum(arr.get("anon_huge_bytes", 0) for arr in thp["placement"]["arrays"]))
                if e["suite_cpus"] != e["likwid_cpus"]:
                    pin_mismatch.append((kernel, variant, size, threads, e["suite_cpus"], e["likwid_cpus"]))
            print(f"rep {rep + 1}/{reps} vs likwid-bench, {label(size)} x{threads}: " + ", ".join(
                f"{k}{'-' + v if v else ''} {lk[(k, v, size, threads)]['suite'][-1] / lk[(k, v, size, threads)]['likwid'][-1]:.2f}"
                for k, v, _ in pairs) + ("; with thp: " + ", ".join(
                f"{k}{'-' + v if v else ''} {lk[(k, v, size, threads)]['suite_thp'][-1] / lk[(k, v, size, threads)]['likwid'][-1]:.2f}"
                for k, v, _ in pairs) if any(r.startswith("thp:") for r in recs) else ""), flush=True)
        rpoints = [(s, t) for s in random_sizes for t in thread_counts]
        if rep % 2:
            rpoints.reverse()
        for size, threads in rpoints:
            order = ["suite", "ref"] if rep % 2 == 0 else ["ref", "suite"]
            for who in order:
                if who == "suite":
                    recs, argv = suite_points(size, threads, "", random_kernels, tmp, pattern="random")
                    for k in random_kernels:
                        r = recs[(k, "")]
                        e = rnd.setdefault((k, size, threads), {"suite": [], "ref": []})
                        e["suite"].append(r["latency_ns"]["median"] if k == "latency" else r["bandwidth_gbps"]["stream"]["median"])
                else:
                    refs, argv = ref_points(random_kernels, size, threads)
                    for k in random_kernels:
                        r = refs[k]
                        e = rnd.setdefault((k, size, threads), {"suite": [], "ref": []})
                        e["ref"].append(r["ns_median"] if k == "latency" else r["gbps_median"])
                if rep == 0:
                    commands.append(" ".join(argv[:-2] + ["--quiet", "--out=FILE"]) if who == "suite" else " ".join(argv))
            print(f"rep {rep + 1}/{reps} random vs plain loops, {label(size)} x{threads}: " + ", ".join(
                f"{k} {(rnd[(k, size, threads)]['ref'][-1] / rnd[(k, size, threads)]['suite'][-1]) if k == 'latency' else (rnd[(k, size, threads)]['suite'][-1] / rnd[(k, size, threads)]['ref'][-1]):.2f}"
                for k in random_kernels), flush=True)

load_after = load_after_runs if a.merge else loadavg()
elapsed = sum(d["elapsed_s"] for d in docs) if a.merge else time.time() - started
total_reps = sum(d["repetitions"] for d in docs) if a.merge else reps


likwid_rows = []
for (kernel, variant, size, threads), e in sorted(lk.items(), key=lambda kv: (kv[0][2], kv[0][3], kv[0][0], kv[0][1])):
    sm, lm = statistics.median(e["suite"]), statistics.median(e["likwid"])
    # The headline is the median of the repetitions' own ratios: the two figures of a repetition
    # were taken seconds apart, while the machine's memory bandwidth drifts between states over
    # minutes (on the development VM, 40 or 70-90 GB/s with two threads at 1 GiB).
    paired = statistics.median(s / l for s, l in zip(e["suite"], e["likwid"]))
    likwid_rows.append({"suite": kernel + ("-" + variant if variant else ""), "likwid": e["likwid_test"], "size_bytes": size, "threads": threads,
                        "suite_gbps": e["suite"], "suite_best_gbps": e["suite_best"], "suite_mean_gbps": e["suite_mean"],
                        "likwid_gbps": e["likwid"], "suite_median_gbps": sm,
                        "likwid_median_gbps": lm, "ratio": paired, "ratio_of_medians": sm / lm,
                        "ratio_best": max(e["suite_best"]) / max(e["likwid"]),
                        "suite_cpus": e["suite_cpus"], "likwid_cpus": e.get("likwid_cpus")})
    if e.get("suite_thp"):
        likwid_rows[-1].update({"suite_thp_gbps": e["suite_thp"], "suite_thp_huge_bytes": e["suite_thp_huge_bytes"],
                                "suite_thp_median_gbps": statistics.median(e["suite_thp"]),
                                "ratio_thp": statistics.median(s / l for s, l in zip(e["suite_thp"], e["likwid"]))})
random_rows = []
for (kernel, size, threads), e in sorted(rnd.items(), key=lambda kv: (kv[0][1], kv[0][2], kv[0][0])):
    sm, rm = statistics.median(e["suite"]), statistics.median(e["ref"])
    latency = kernel == "latency"
    paired = statistics.median((r / s) if latency else (s / r) for s, r in zip(e["suite"], e["ref"]))
    random_rows.append({"kernel": kernel, "size_bytes": size, "threads": threads, "metric": "ns_per_load" if latency else "gbps",
                        "suite": e["suite"], "ref": e["ref"], "suite_median": sm, "ref_median": rm, "ratio": paired,
                        "ratio_of_medians": rm / sm if latency else sm / rm})


def goal(rows, pred, need, key="ratio"):
    sel = [r for r in rows if pred(r) and key in r]
    worst = min(sel, key=lambda r: r[key]) if sel else None
    return {"need": need, "points": len(sel), "met": all(r[key] >= need for r in sel) if sel else None,
            "below": sum(r[key] < need for r in sel),
            "worst": None if worst is None else {k: v for k, v in worst.items()
                                                 if k in ("suite", "likwid", "kernel", "size_bytes", "threads", key) and not isinstance(v, list)}}


goals = {
    "dram_1GiB_vs_likwid_>=1.00": goal(likwid_rows, lambda r: r["size_bytes"] >= GiB, 1.00),
    "dram_1GiB_thp_vs_likwid_>=1.00": goal(likwid_rows, lambda r: r["size_bytes"] >= GiB, 1.00, key="ratio_thp"),
    "in_cache_vs_likwid_>=0.90": goal(likwid_rows, lambda r: r["size_bytes"] <= MiB, 0.90),
    "random_vs_plain_loop_>=0.98": goal(random_rows, lambda r: True, 0.98),
}
doc = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "quick": a.quick, "repetitions": total_reps,
       "runs": runs, "merged_from": [os.path.basename(os.path.dirname(os.path.abspath(f))) + "/" + os.path.basename(f) for f in a.merge or []],
       "seconds_per_point": a.seconds, "elapsed_s": round(elapsed, 1), "load_average_before": load_before, "load_average_after": load_after,
       "cpu_model": info.get("cpu_model", ""), "pus": info["pus"], "instruction_set": info["instruction_set"],
       "transparent_hugepages": info["transparent_hugepages"]["value"], "likwid_available": have_likwid,
       "pinning_mismatches": [list(m) for m in pin_mismatch], "commands": commands, "goals": goals,
       "likwid": likwid_rows, "random": random_rows,
       "conventions": "GB/s = 1e9 B/s, STREAM bytes (8 B per array element read or written); likwid-bench's MByte/s converted; suite "
                      "vs likwid: the suite's median sample (>= 1 ms each) against likwid-bench's average over a short run "
                      "(window_s; window_nt_s for the non-temporal kernels); random kernels: medians of samples on both sides; "
                      "ratio = the median over the repetitions of each repetition's suite/reference (for latency reference ns / "
                      "suite ns); ratio_of_medians beside it",
       "window_s": a.window, "window_nt_s": a.window_nt, "suite_hugepages": a.hugepages, "suite_thp_from_bytes": thp_from}

os.makedirs(a.out, exist_ok=True)
name = "vs_likwid_quick" if a.quick else "vs_likwid"
write_text(os.path.join(a.out, name + ".json"), json.dumps(doc, indent=1))
lines = [f"# suite vs likwid-bench and plain loops ({doc['date']}, {doc['cpu_model']}, {doc['pus']} PUs)", ""]
if a.merge:
    lines += [f"{runs} runs, {total_reps} interleaved repetitions in all, pooled: medians over all of them; 1-minute load "
              f"average before/after each run: " + ", ".join(f"{b[0]}/{e[0]}" for b, e in zip(load_before, load_after)) +
              f"; {elapsed:.0f} s in all.", ""]
else:
    lines += [f"{reps} interleaved repetitions, medians; load average {load_before[0]} before, {load_after[0]} after; {elapsed:.0f} s.", ""]


def likwid_table(rows, header, ratio, gbps):
    """Markdown rows: one line per size and thread count, a cell per pair: ratio (suite/likwid GB/s)."""
    out = ["| size | threads | " + " | ".join(header(k, v, t) for k, v, t in pairs) + " |", "|---|---|" + "---|" * len(pairs)]
    for size in sorted({r["size_bytes"] for r in rows}):
        for t in thread_counts:
            cells = []
            for k, v, _ in pairs:
                r = next((r for r in rows if r["suite"] == k + ("-" + v if v else "") and r["size_bytes"] == size and r["threads"] == t), None)
                cells.append(f"{r[ratio]:.2f} ({r[gbps]:.0f}/{r['likwid_median_gbps']:.0f})" if r else "-")
            out.append(f"| {label(size)} | {t} | " + " | ".join(cells) + " |")
    return out + [""]


if likwid_rows:
    lines += likwid_table(likwid_rows, lambda k, v, t: f"{k}{'-' + v if v else ''} / {t}", "ratio", "suite_median_gbps")
    thp_rows = [r for r in likwid_rows if "ratio_thp" in r]
    if thp_rows:
        lines += ["With `--hugepages=thp` (the suite's arrays on transparent huge pages; likwid-bench as the system gives it):", ""]
        lines += likwid_table(thp_rows, lambda k, v, t: f"{k}{'-' + v if v else ''}", "ratio_thp", "suite_thp_median_gbps")
lines += ["| size | threads | " + " | ".join(f"{k} random" for k in random_kernels) + " |", "|---|---|" + "---|" * len(random_kernels)]
for size in random_sizes:
    for t in thread_counts:
        cells = []
        for k in random_kernels:
            r = next((r for r in random_rows if r["kernel"] == k and r["size_bytes"] == size and r["threads"] == t), None)
            cells.append(f"{r['ratio']:.2f}" if r else "-")
        lines.append(f"| {label(size)} | {t} | " + " | ".join(cells) + " |")
lines += ["", "Cells: the median over the repetitions of suite/reference (in brackets the medians of suite GB/s and likwid-bench "
          "GB/s); random: suite/plain loop (latency: plain ns / suite ns).", ""]
for g, v in goals.items():
    verdict = "not measured" if v["met"] is None else "met" if v["met"] else "NOT met"
    lines.append(f"- {g}: {verdict} over {v['points']} points ({v['below']} below); worst {v['worst']}")
write_text(os.path.join(a.out, name + ".md"), "\n".join(lines) + "\n")
print("\n".join(lines))
print(f"wrote {os.path.join(a.out, name + '.json')} and .md")
if pin_mismatch:
    print(f"vs_likwid: warning: the suite and likwid-bench ran on different CPUs at {len(pin_mismatch)} point(s): {pin_mismatch[:3]}")
