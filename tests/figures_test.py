#!/usr/bin/python3
"""ctest: every figure a record reports, tied to its definition. One small point of every kernel
the registry has (`suite list --json`; a kernel this test has no point for fails it) is run three
times, writing JSON, CSV and Google Benchmark's JSON, each time with the console table of the
same run on stdout. Then, on every record:
  - the time statistics are those of the record's own samples (min, median, max, mean, cv);
  - every rate is its declared work over the best or the median time: STREAM and hardware GB/s
    (best and median), ns per load, GFLOP/s, units per second; a figure the metric has not is
    absent, never 0;
  - the declared work per unit is the kernel's reference formula, counted by hand here (not read
    from the code): the stream kernels at every pattern and store kind (write-allocate, whole
    64 B lines, the index array), the pointer chase, SpMV, CG and the assembly on a mesh whose
    vertex count Euler's formula gives, and the particle kernels' constant bytes per particle;
  - the formats agree to their printed precision: the table with the JSON, CSV and gbench of
    its own run, `suite compare --format=markdown` with the JSON it reads, and `suite check
    --markdown` with a run made 1.5 times slower (every point regressed, by -33.3 % or +50 %).
Usage: figures_test.py SUITE_BINARY"""
import csv
import io
import json
import re
import statistics
import subprocess
import sys
import tempfile

suite = sys.argv[1]
failures = []
COMMON = ["--counters=none", "--energy=none", "--seed=7"]
# One group a run: the kernels that share a size (a footprint, or a mesh).
STREAM = ["add", "copy", "load", "scale", "sin-add", "store", "triad"]
NT = ["add", "copy", "scale", "store", "triad"]
GROUPS = {
    "stream": ["--kernel=" + ",".join(STREAM), "--pattern=sequential,random,strided:2,strided:16", "--size=192KiB", "--threads=1,2"],
    "latency": ["--kernel=latency", "--pattern=random,sequential", "--size=192KiB", "--threads=1,2"],
    "nt": ["--kernel=" + ",".join(NT), "--stores=nt", "--size=192KiB", "--threads=1"],
    "fem": ["--kernel=fem-spmv,fem-cg,fem-eigen,fem-assembly,fem-pattern,fem-spmv-dist,fem-cg-dist,fem-eigen-dist",
            "--mesh=disk:refine=3", "--ordering=natural,hilbert", "--threads=1,2"],
    "sfc": ["--kernel=sfc-build", "--mesh=disk:refine=3", "--ordering=morton,hilbert", "--threads=1,2"],
    "mpm": ["--kernel=mpm-p2g,mpm-g2p,mpm-step,mpm-implicit-assembly,mpm-implicit-solve,mpm-implicit-step",
            "--mesh=box:6,6,6", "--threads=1", "--warm-steps=2"],
    "compute": ["--kernel=peak-flops", "--size=4096", "--threads=1,2"],
}
LINE = 64  # bytes of a cache line: the hardware estimate's granule for scattered accesses


def check(cond, message):
    if not cond:
        failures.append(message)
    return cond


def close(a, b, rel=1e-12):
    return a is not None and b is not None and abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


def run(args, reps=3):
    p = subprocess.run([suite, *args, *COMMON, f"--reps={reps}"], capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit(f"FAIL: suite {' '.join(args)} exited {p.returncode}: {p.stderr.strip()[-500:]}")
    return p.stdout


def table_rows(stdout):
    """The console table's rows: best, median, hw-est (None for '-'), cv %, reps, check."""
    rows = []
    for line in stdout.splitlines():
        t = line.split()
        if not t or "/" not in t[0] or not t[0].split("/")[0].isdigit():
            continue
        i = 6
        best = None if t[i] == "-" else float(t[i])
        i += 1 if best is None else 2
        num = [None if x == "-" else float(x) for x in t[i:i + 3]]
        rows.append({"name": t[1], "access": t[2], "threads": int(t[4]), "best": best, "median": num[0], "hw": num[1],
                     "cv": num[2], "reps": int(t[i + 3]), "check": t[i + 4]})
    return rows


def printed(value, shown, decimals):
    """shown is value printed with `decimals` decimals (half a unit of the last place)."""
    if value is None or shown is None:
        return value is None and shown is None
    return abs(value - shown) <= 0.5 * 10 ** -decimals + 1e-9 * abs(value)


def places(text):
    """The decimals of a figure as printed, in units of 10^-places: '8.19' -> 2, '8.199e-03' -> 6
    (a very slow point of a busy machine is printed in scientific notation)."""
    mantissa, _, exponent = text.lower().partition("e")
    digits = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return digits - (int(exponent) if exponent else 0)


# --- the definitions, on the JSON record -------------------------------------------------------------------

def check_rates(r, where):
    t, w = r["time_s"], r["work_per_repetition"]
    s = t["samples"]
    check(len(s) == r["repetitions"]["counted"], f"{where}: {len(s)} samples for {r['repetitions']['counted']} repetitions")
    mean = sum(s) / len(s)
    cv = statistics.stdev(s) / mean if len(s) > 1 else 0.0
    for key, want in (("min", min(s)), ("max", max(s)), ("median", statistics.median(s)), ("mean", mean), ("cv", cv)):
        check(close(t[key], want, 1e-9), f"{where}: time_s.{key} = {t[key]}, the samples give {want}")
    best, med = t["min"], t["median"]
    bw, lat = r["bandwidth_gbps"], r["latency_ns"]
    if r["metric"] == "bandwidth":
        check(lat is None, f"{where}: a bandwidth record has latency_ns {lat}")
        for kind, num in (("stream", w["stream_bytes"]), ("hardware_estimate", w["hardware_bytes_estimate"])):
            if num == 0:  # moves no bytes (peak-flops): no bandwidth, null with the reason, never 0
                check(bw[kind]["best"] is None and bw[kind]["median"] is None and bw.get("reason"),
                      f"{where}: {kind} of a kernel that moves no bytes is {bw[kind]}, reason {bw.get('reason')!r}")
                continue
            check(close(bw[kind]["best"], num / best / 1e9), f"{where}: {kind} best {bw[kind]['best']} != {num} B / {best} s")
            check(close(bw[kind]["median"], num / med / 1e9), f"{where}: {kind} median {bw[kind]['median']} != {num} B / {med} s")
    else:
        check(bw is None, f"{where}: a latency record has bandwidth_gbps {bw}")
        loads = w["units"] / r["threads"]  # each thread chases its share, one load after another
        check(close(lat["best"], best / loads * 1e9), f"{where}: ns per load best {lat['best']} != {best} s / {loads}")
        check(close(lat["median"], med / loads * 1e9), f"{where}: ns per load median {lat['median']} != {med} s / {loads}")
    if w["flops"] > 0:
        check(close(r["gflops_best"], w["flops"] / best / 1e9), f"{where}: gflops_best {r['gflops_best']} != {w['flops']} / {best} s")
    else:
        check(r["gflops_best"] is None, f"{where}: no flops declared, gflops_best is {r['gflops_best']} (not measured is not 0)")
    check(close(r["units_per_second_best"], w["units"] / best), f"{where}: units/s {r['units_per_second_best']} != {w['units']} / {best} s")
    check(r["verification"]["passed"], f"{where}: not verified: {r['verification']['detail']}")


def stream_reference(r):
    """Bytes, hardware bytes and flops per element of a stream kernel, counted from its formula."""
    k, access = r["kernel"], r["pattern"]
    reads = {"copy": 1, "scale": 1, "add": 2, "triad": 2, "sin-add": 2, "load": 1, "store": 0}[k]
    writes = 0 if k == "load" else 1
    flops = {"copy": 0, "scale": 1, "add": 1, "triad": 2, "sin-add": 1, "load": 1, "store": 0}[k]  # sin() not counted
    granule = 8 if access == "sequential" else LINE if access == "random" else min(LINE, 8 * int(access.split(":")[1]))
    store = 1 if r["variant"] == "nt" else 2  # a store reads its line first (write-allocate) unless non-temporal
    index = 4 if access == "random" else 0     # the permutation, read in order
    return 8 * (reads + writes), granule * (reads + writes * store) + index, flops


def mesh_counts(spmv):
    """Vertices and nonzeros of the fem mesh from the SpMV record: nnz = n + 2E, and Euler's
    V - E + F = 1 on a disk, F the triangles: n = (nnz - 2F + 2) / 3."""
    nnz, f = spmv["work_per_repetition"]["units"], spmv["size"]["requested"]
    n = (nnz - 2 * f + 2) / 3
    check(n == int(n) and n > 0, f"Euler's formula gives {n} vertices from nnz {nnz}, {f} triangles")
    return n, nnz, f


def fem_reference(r, n, nnz, f):
    """Per repetition: stream bytes, hardware bytes, flops. CSR is 8 B a value, 4 a column, 4 a row
    pointer; a CG iteration moves the matrix, p and q (SpMV), x, p, r, q read and x, r written, r, p
    read and p written: 11 vectors; its flops 2 a nonzero and 10 a row."""
    csr = 12 * nnz + 4 * (n + 1)
    k = r["kernel"].removesuffix("-dist")
    if k == "fem-spmv":
        return csr + 16 * n, csr + 24 * n, 2 * nnz
    if k == "fem-cg":
        its = r["work_per_repetition"]["units"]
        stream = its * (csr + 88 * n) + csr + 16 * n  # and the first residual: one matrix pass
        return stream, stream + its * 32 * n, its * (2 * nnz + 10 * n)
    if k == "fem-assembly":  # triangles' corners 12 B, coordinates 16, the pattern, A and M zeroed then updated
        stream = 12 * f + 16 * n + 4 * (n + 1) + 4 * nnz + 48 * nnz
        return stream, stream + 16 * nnz + 3 * f * (64 + 48), None
    return None


def check_work(r, where, listed, spmv):
    w = r["work_per_repetition"]
    u = w["units"]
    got = (w["stream_bytes"], w["hardware_bytes_estimate"], w["flops"])
    want = None
    if r["kernel"] in STREAM:
        per = stream_reference(r)
        want = tuple(x * u for x in per)
    elif r["kernel"] == "latency":
        lines = r["size"]["footprint_bytes"] / LINE
        check(u == lines + r["threads"], f"{where}: {u} loads for {lines} lines and {r['threads']} thread(s): one cycle each, plus its return")
        want = (8 * u, LINE * u, 0)
    elif spmv is not None and r["kernel"].startswith("fem-") and fem_reference(r, *spmv):
        want = fem_reference(r, *spmv)
    elif r["kernel"] == "peak-flops":  # 12 accumulators of `lanes` doubles, size iterations a thread, 2 flops an update
        lanes = r["facts"]["lanes"]["value"]
        check(lanes == {"scalar": 1, "sse": 2, "avx": 4, "avx512": 8}[r["variant"]], f"{where}: {lanes} lanes for {r['variant']}")
        check(u == r["size"]["requested"] * 12 * lanes * r["threads"], f"{where}: {u} updates")
        want = (0, 0, 2 * u)
    elif r["kernel"] in ("mpm-p2g", "mpm-g2p", "mpm-step"):  # the particle arrays: a constant a particle (step)
        want = ((listed["read_bytes_per_unit"] + listed["write_bytes_per_unit"]) * u, None, listed["flops_per_unit"] * u)
        check(listed["read_bytes_per_unit"] + listed["write_bytes_per_unit"] > 0, f"{where}: suite list declares no bytes")
    if want is None:
        return False
    for name, g, e in zip(("stream bytes", "hardware bytes", "flops"), got, want):
        if e is not None:
            check(close(g, e, 1e-12), f"{where}: {name} {g}, the hand count gives {e}")
    # `suite list` declares the same per-unit figures where they are constant.
    if r["kernel"] in STREAM and r["pattern"] == "sequential" or r["kernel"] in ("latency", "mpm-p2g", "mpm-g2p", "mpm-step"):
        declared = listed["read_bytes_per_unit"] + listed["write_bytes_per_unit"]
        check(close(declared * u, w["stream_bytes"]), f"{where}: suite list says {declared} B a unit, the record {w['stream_bytes'] / u}")
        check(close(listed["flops_per_unit"] * u, w["flops"]), f"{where}: suite list says {listed['flops_per_unit']} flops a unit")
    return True


# --- the formats, against the table of their own run -------------------------------------------------------

def check_table(rows, records, where, best_of, median_of, hw_of, cv_of, reps_of, ok_of):
    if not check(len(rows) == len(records), f"{where}: {len(rows)} table rows for {len(records)} records"):
        return
    for row, r in zip(rows, records):
        at = f"{where} {row['name']} {row['access']} t={row['threads']}"
        check(row["name"] == name_of(r), f"{at}: the table's row is {row['name']}, the file's record {name_of(r)}")
        for label, got, want, dec in (("best", row["best"], best_of(r), 2), ("median", row["median"], median_of(r), 2),
                                      ("hw-est", row["hw"], hw_of(r), 2), ("cv%", row["cv"], cv_of(r), 1)):
            check(printed(want, got, dec), f"{at}: the table's {label} {got}, the file's {want}")
        check(row["reps"] == reps_of(r), f"{at}: the table's reps {row['reps']}, the file's {reps_of(r)}")
        check((row["check"] == "ok") == ok_of(r), f"{at}: the table says {row['check']}")


def name_of(r):
    return r["name"]


def flops_only(w):
    """A kernel that moves no bytes (peak-flops): the table shows its GFLOP/s."""
    return float(w["stream_bytes"]) == 0 and float(w["flops"]) > 0


def check_json_run(stdout, doc, where):
    recs = doc["results"]

    def bw(r, k, s):
        w, t = r["work_per_repetition"], r["time_s"]
        if flops_only(w):
            return None if k != "stream" else w["flops"] / (t["min"] if s == "best" else t["median"]) / 1e9
        return r["bandwidth_gbps"][k][s] if r["bandwidth_gbps"] else r["latency_ns"][s] if k == "stream" else None
    check_table(table_rows(stdout), recs, where + " JSON", lambda r: bw(r, "stream", "best"), lambda r: bw(r, "stream", "median"),
                lambda r: bw(r, "hardware_estimate", "best"), lambda r: r["time_s"]["cv"] * 100,
                lambda r: r["repetitions"]["counted"], lambda r: r["verification"]["passed"])


def check_csv_run(stdout, text, where):
    rows = list(csv.DictReader(io.StringIO(text)))
    num = lambda r, k: float(r[k]) if r[k] != "" else None
    for r in rows:
        at = f"{where} CSV {r['name']} {r['access']} t={r['threads']}"
        units, sb, hb, fl = (float(r[k]) for k in ("units", "stream_bytes", "hardware_bytes_estimate", "flops"))
        tmin, tmed = float(r["time_min_s"]), float(r["time_median_s"])  # 9 significant digits; the rates 6
        lat = r["ns_per_load_best"] != ""
        pairs = [("units_per_second_best", units / tmin), ("gflops_best", fl / tmin / 1e9 if fl > 0 else None)]
        if lat:
            loads = units / int(r["threads"])
            pairs += [("ns_per_load_best", tmin / loads * 1e9), ("ns_per_load_median", tmed / loads * 1e9),
                      ("stream_gbps_best", None), ("hardware_gbps_best", None)]
        else:
            # A kernel that moves no bytes (peak-flops) has no bandwidth: empty cells, never 0.
            rate = lambda b, t: b / t / 1e9 if b > 0 else None  # noqa: E731
            pairs += [("stream_gbps_best", rate(sb, tmin)), ("stream_gbps_median", rate(sb, tmed)),
                      ("hardware_gbps_best", rate(hb, tmin)), ("hardware_gbps_median", rate(hb, tmed)), ("ns_per_load_best", None)]
        for key, want in pairs:
            got = num(r, key)
            check((got is None and want is None) or close(got, want, 1e-5), f"{at}: {key} {got}, its own columns give {want}")
    gf = lambda r, t: float(r["flops"]) / float(r[t]) / 1e9
    check_table(table_rows(stdout), rows, where + " CSV",
                lambda r: gf(r, "time_min_s") if flops_only(r) else num(r, "ns_per_load_best") if r["ns_per_load_best"] else num(r, "stream_gbps_best"),
                lambda r: gf(r, "time_median_s") if flops_only(r) else num(r, "ns_per_load_median") if r["ns_per_load_best"] else num(r, "stream_gbps_median"),
                lambda r: None if flops_only(r) else num(r, "hardware_gbps_best"), lambda r: float(r["time_cv"]) * 100, lambda r: int(r["repetitions"]),
                lambda r: r["verified"] == "true")


def check_gbench_run(stdout, doc, where):
    per = {}
    for b in doc["benchmarks"]:
        per.setdefault(b["family_index"], []).append(b)
    recs = []
    for i in sorted(per):
        its = [b for b in per[i] if b["run_type"] == "iteration"]
        agg = {b["aggregate_name"]: b for b in per[i] if b["run_type"] == "aggregate"}
        name = its[0]["run_name"].split("/")[0]
        at = f"{where} gbench {its[0]['run_name']}"
        times = [b["real_time"] * 1e-9 for b in its]
        lat = "ns_per_load" in its[0]
        # Every repetition moves the same declared bytes: rate x time is one number.
        key = "ns_per_load" if lat else "bytes_per_second"
        work = [b["items_per_second"] * t for b, t in zip(its, times)]
        check(all(close(x, work[0], 1e-9) for x in work), f"{at}: items per second x time differs between repetitions: {work}")
        if not lat:
            sb = [b["bytes_per_second"] * t for b, t in zip(its, times)]
            check(all(close(x, sb[0], 1e-9) for x in sb), f"{at}: bytes per second x time differs between repetitions")
        check(close(agg["median"]["real_time"] * 1e-9, statistics.median(times), 1e-9), f"{at}: median aggregate is not the samples' median")
        check(close(agg["mean"]["real_time"] * 1e-9, sum(times) / len(times), 1e-9), f"{at}: mean aggregate is not the samples' mean")
        fast = min(its, key=lambda b: b["real_time"])
        if not lat and fast["bytes_per_second"] == 0 and fast.get("flops_per_second", 0) > 0:  # peak-flops: GFLOP/s
            recs.append({"name": name, "best": fast["flops_per_second"] * 1e-9, "median": agg["median"]["flops_per_second"] * 1e-9,
                         "hw": None, "cv": agg["cv"]["real_time"] * 100, "reps": len(its)})
            continue
        recs.append({"name": name, "best": fast[key] * (1 if lat else 1e-9), "median": agg["median"][key] * (1 if lat else 1e-9),
                     "hw": None if lat else fast["hardware_bytes_per_second"] * 1e-9, "cv": agg["cv"]["real_time"] * 100,
                     "reps": len(its)})
    check_table(table_rows(stdout), recs, where + " gbench", lambda r: r["best"], lambda r: r["median"], lambda r: r["hw"],
                lambda r: r["cv"], lambda r: r["reps"], lambda r: True)


def check_markdown(a_path, b_path, a, b, where):
    """`suite compare --format=markdown`: each point's best and median (to the digits shown) are
    the files', and "vs [1]" is performance from the medians: B/A for bandwidth, A/B for latency."""
    p = subprocess.run([suite, "compare", a_path, b_path, "--format=markdown"], capture_output=True, text=True, timeout=120)
    check(p.returncode == 0, f"{where}: suite compare exited {p.returncode}: {p.stderr.strip()}")
    rows = [c for c in ([x.strip() for x in l.split("|")[1:-1]] for l in p.stdout.splitlines() if l.startswith("| "))
            if len(c) == 7 and re.match(r"^\d+\.\d+x", c[6])]
    check(len(rows) == len(a["results"]), f"{where}: compare shows {len(rows)} points of {len(a['results'])}")
    for cells, ra, rb in zip(rows, a["results"], b["results"]):
        fig = lambda r, s: r["bandwidth_gbps"]["stream"][s] if r["bandwidth_gbps"] else r["latency_ns"][s]
        for shown, want in zip(cells[2:6], (fig(ra, "best"), fig(ra, "median"), fig(rb, "best"), fig(rb, "median"))):
            decimals = places(shown)
            check(printed(want, float(shown), decimals), f"{where} {cells[0]}: compare shows {shown}, the file {want}")
        ratio = fig(rb, "median") / fig(ra, "median") if ra["bandwidth_gbps"] else fig(ra, "median") / fig(rb, "median")
        got = float(cells[6].split("x")[0])
        check(abs(got - ratio) <= 0.0005 + 1e-9, f"{where} {cells[0]}: vs [1] {got}, the medians give {ratio:.4f}")
        # The 95 % bootstrap interval of that ratio holds it: each median resampled falls at or
        # below its sample's median with probability >= 1/2, so the ratio's 2.5 % and 97.5 %
        # points cannot both lie on one side of the ratio of the medians.
        low, high = (float(x) for x in re.search(r"\[([0-9.]+), ([0-9.]+)\]", cells[6]).groups())
        check(low <= got + 0.0005 and got <= high + 0.0005, f"{where} {cells[0]}: the interval [{low}, {high}] leaves out its ratio {got}")


def size_label(n):
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n % scale == 0:
            return f"{n // scale}{unit}"
    return f"{n}B"


def check_gate(a_path, a, where, tmp):
    """`suite check`'s markdown on a run made 1.5 times slower (every time of the baseline's
    records x 1.5, each rate over the new time): every point regresses, and its row shows the
    medians of both files and the change of the figure itself (-33.3 % GB/s, +50.0 % ns). The
    baseline has 7 repetitions (3 against 3 can never reach p < 0.01), and both files are marked
    stable: the gate would call a point of this busy VM inconclusive, and its figures not shown."""
    for r in a["results"]:
        r["stability"]["unstable"] = False
    a_path = a_path.removesuffix(".json") + ".stable.json"
    json.dump(a, open(a_path, "w"))
    slow = json.loads(json.dumps(a))
    for r in slow["results"]:
        t = r["time_s"]
        for k in ("min", "median", "max", "mean"):
            t[k] *= 1.5
        t["samples"] = [x * 1.5 for x in t["samples"]]
        for fig in (r["bandwidth_gbps"] or {}).values():
            fig["best"] /= 1.5
            fig["median"] /= 1.5
        if r["latency_ns"]:
            r["latency_ns"] = {k: v * 1.5 for k, v in r["latency_ns"].items()}
        r["units_per_second_best"] /= 1.5
        if r["gflops_best"]:
            r["gflops_best"] /= 1.5
    b_path, md = f"{tmp}/slow.json", f"{tmp}/gate.md"
    json.dump(slow, open(b_path, "w"))
    p = subprocess.run([suite, "check", "--baseline", a_path, b_path, "--markdown=" + md], capture_output=True, text=True, timeout=120)
    check(p.returncode == 1, f"{where}: suite check of a run 1.5x slower exited {p.returncode}, not 1 (regressed)")
    rows = {}
    for line in open(md).read().splitlines():
        c = [x.strip() for x in line.split("|")[1:-1]]
        if len(c) == 8 and c[1].startswith("`"):
            rows[c[1].strip("`")] = c
    for r in a["results"]:
        label = f"{r['name']} {r['pattern']} {size_label(r['size']['requested'])} t={r['threads']} {r['pin']['requested']}/{r['placement']['requested']}"
        c = rows.get(label)
        if not check(c is not None, f"{where}: the gate's markdown has no row {label!r}: {sorted(rows)[:3]}"):
            continue
        fig = r["bandwidth_gbps"]["stream"]["median"] if r["bandwidth_gbps"] else r["latency_ns"]["median"]
        slow_fig = fig / 1.5 if r["bandwidth_gbps"] else fig * 1.5
        for shown, want in ((c[3], fig), (c[4], slow_fig)):
            decimals = places(shown)
            check(printed(want, float(shown), decimals), f"{where} gate {label}: shows {shown}, the file's median {want}")
        change = float(c[5].split("%")[0])
        want = -33.3 if r["bandwidth_gbps"] else 50.0
        check(abs(change - want) <= 0.05 + 1e-9, f"{where} gate {label}: change {c[5]}, the medians give {want} %")
        check(c[0] in ("REGRESSED", "inconclusive"), f"{where} gate {label}: {c[0]} for a run 1.5x slower")


def main():
    listed = {k["name"]: k for k in json.loads(subprocess.run([suite, "list", "--json"], capture_output=True, text=True, check=True).stdout)}
    covered = {k for args in GROUPS.values() for k in args[0].removeprefix("--kernel=").split(",")}
    check(not set(listed) - covered, f"kernels with no point here: {sorted(set(listed) - covered)} (add one to GROUPS)")
    hand = set()
    with tempfile.TemporaryDirectory() as tmp:
        for group, args in GROUPS.items():
            j, c, g = (f"{tmp}/{group}.{x}" for x in ("json", "csv", "gb.json"))
            out = run([*args, "--out=" + j])
            doc = json.load(open(j))
            check_json_run(out, doc, group)
            spmv = next((mesh_counts(r) for r in doc["results"] if r["kernel"] == "fem-spmv"), None)
            for r in doc["results"]:
                where = f"{group}: {r['name']} {r.get('pattern', r.get('ordering'))} t={r['threads']}"
                check_rates(r, where)
                if check_work(r, where, listed[r["kernel"]], spmv):
                    hand.add(r["kernel"])
            check_csv_run(run([*args, "--out=" + c]), open(c).read(), group)
            check_gbench_run(run([*args, "--format=gbench", "--out=" + g]), json.load(open(g)), group)
            if group in ("stream", "latency"):  # a second run, to compare with the first
                b = f"{tmp}/{group}.b.json"
                run([*args, "--out=" + b])
                check_markdown(j, b, doc, json.load(open(b)), group)
                run([*args, "--out=" + b], reps=7)
                check_gate(b, json.load(open(b)), group, tmp)
    want = set(STREAM) | {"latency", "fem-spmv", "fem-cg", "fem-assembly", "fem-spmv-dist", "fem-cg-dist", "mpm-p2g", "mpm-g2p", "mpm-step"}
    check(want <= hand, f"no hand count was checked for {sorted(want - hand)}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(failures)} failure(s); hand counts checked for {len(hand)} kernels")
    sys.exit(1 if failures else 0)


main()
