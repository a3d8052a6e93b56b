#!/usr/bin/python3
"""ctest: plots/roofline.py draws the roofline of ceilings files (made here as dicts, and the
committed tests/fixtures/roofline/) into a real PNG (signature, IHDR) of plausible size, with and
without a placement; it refuses bad input (missing, unreadable, not JSON, another kind, another
schema_version, no ceilings, malformed values, an output it may not write) with exit status 2 and
one line on stderr, creating no file and leaving an existing one as it was. Then, on the matplotlib
figure its make_figure builds: log axes, a panel per thread count, one diagonal per level with a
measured bandwidth (y = x * GB/s up to the ridge, labelled "L1 210 GB/s"), the peak line at
peak_gflops labelled with its ISA, fainter lines at the narrower ISAs, the ridge points, the placed
points where the placement says (numbered, marker by group, colour by level, unverified hollow),
kernels without flops in a second panel, records not placed listed, the machine and date in the
title. Usage: roofline_plot_test.py SOURCE_DIR"""
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

src = sys.argv[1]
script = os.path.join(src, "plots", "roofline.py")
fixtures = os.path.join(src, "tests", "fixtures", "roofline")
failures = []


def check(cond, message):
    if not cond:
        failures.append(message)


def run(*args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True, timeout=120)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def side(kernel, gbps, hardware):
    return {"kernel": kernel, "gbps": gbps, "hardware_gbps": hardware}


def machine():
    """The ceilings of a small machine, as `suite roofline` writes them: 1 thread with four ISAs
    and two of its four levels measured, 2 threads with a peak only."""
    return {
        "kind": "suite-roofline", "schema_version": 1, "complete": True,
        "context": {"host": "vm", "cpu_model": "  AMD   EPYC ", "cores": 2, "pus": 2, "date": "2026-11-27T10:00:00Z"},
        "fingerprint": "0123456789abcdef", "seconds": 41.2,
        "levels": [{"name": "L1", "capacity_bytes": 47308, "source": "measured"},
                   {"name": "L2", "capacity_bytes": 797000, "source": "measured"},
                   {"name": "L3", "capacity_bytes": 7100000, "source": "measured"},
                   {"name": "DRAM", "capacity_bytes": None, "source": "memory"}],
        "ceilings": [
            {"threads": 1, "peak_gflops": 106.1,
             "peak": [{"isa": "scalar", "kernel": "peak-flops-scalar", "gflops": 7.0},
                      {"isa": "sse", "kernel": "peak-flops-sse", "gflops": 14.1},
                      {"isa": "avx", "kernel": "peak-flops-avx", "gflops": 53.4},
                      {"isa": "avx512", "kernel": "peak-flops-avx512", "gflops": 106.1}],
             "bandwidth": [
                 {"level": "L1", "footprint_bytes": 24576, "gbps": 210.0, "hardware_gbps": 230.0, "kernel": "load",
                  "read_only": side("load", 210.0, 210.0), "read_write": side("copy", 150.0, 230.0)},
                 {"level": "DRAM", "footprint_bytes": 2147483648, "gbps": 16.0, "hardware_gbps": 20.0, "kernel": "copy-nt",
                  "read_only": None, "reason": "read_only: not measured (--quick)",
                  "read_write": side("copy-nt", 16.0, 16.0)}]},
            {"threads": 2, "peak_gflops": 212.0, "peak": [], "bandwidth": []}]}


def point(label, group, threads, level, gflops, gbps, intensity, verified=True, fraction=0.5):
    return {"label": label, "name": label.split()[0], "kernel": label.split()[0], "group": group, "threads": threads,
            "footprint_bytes": 67108864, "level": level, "verified": verified, "gflops": gflops, "gbps": gbps,
            "hardware_gbps": gbps, "intensity": None if intensity is None else {"stream": intensity, "hardware": intensity},
            "ceiling": {"gflops": None, "gbps": 16.0, "bound": "bandwidth"}, "fraction": fraction, "hardware_fraction": fraction}


def placement():
    """Points of a run on those ceilings: flops and none, verified and not, and a thread count the
    ceilings lack. Its ceilings_file names another path than the one given: that is fine."""
    return {
        "kind": "suite-roofline-placement", "schema_version": 1,
        "ceilings_file": "results/roofline.json", "result_file": "results/latest.json",
        "points": [point("triad sequential 64MiB t=1 compact/local", "stream", 1, "DRAM", 0.9, 14.2, 0.0833, fraction=0.95),
                   point("triad sequential 16KiB t=1 compact/local", "stream", 1, "L1", 12.0, 150.0, 0.0833),
                   point("fem-spmv hilbert 16MiB t=1 compact/local", "fem", 1, "DRAM", 1.1, 11.0, 0.1, verified=False),
                   point("copy sequential 64MiB t=1 compact/local", "stream", 1, "DRAM", None, 13.0, None),
                   point("sfc-build hilbert 8MiB t=1 compact/local", "sfc", 1, "L1", None, 90.0, None, verified=False),
                   point("triad sequential 64MiB t=2 compact/local", "stream", 2, "DRAM", 1.5, 18.0, 0.0833),
                   point("triad sequential 64MiB t=4 compact/local", "stream", 4, "DRAM", 1.9, 23.0, 0.0833)],
        "not_placed": [{"label": "latency random 1MiB t=1 compact/local",
                        "reason": "a latency kernel has no bandwidth or flops to place"}]}


def write(directory, name, doc):
    path = os.path.join(directory, name)
    with open(path, "w") as f:
        f.write(doc if isinstance(doc, str) else json.dumps(doc))
    return path


def leftovers(directory):
    return [n for n in os.listdir(directory) if ".tmp." in n]


# Figures: a real PNG of plausible size, its path on stdout, no temporary file left.
with tempfile.TemporaryDirectory() as tmp:
    ceilings = write(tmp, "ceilings.json", machine())
    placed = write(tmp, "placed.json", placement())
    cases = [("ceilings only", [ceilings]), ("with --place", [ceilings, "--place", placed]),
             ("committed fixture", [os.path.join(fixtures, "ceilings.json")]),
             ("committed fixtures with --place", [os.path.join(fixtures, "ceilings.json"), "--place",
                                                  os.path.join(fixtures, "placed.json")])]
    for i, (what, args) in enumerate(cases):
        out = os.path.join(tmp, f"figure{i}.png")
        r = run(*args, "--out", out)
        check(r.returncode == 0, f"{what}: exit {r.returncode}\n{r.stderr}")
        check(r.stdout.strip() == out, f"{what}: expected the figure's path on stdout, got {r.stdout!r}")
        if not os.path.exists(out):
            check(False, f"{what}: {out} was not written")
            continue
        size, dims = os.path.getsize(out), png_size(out)
        check(dims is not None, f"{what}: the figure is not a PNG")
        check(20_000 < size < 5_000_000, f"{what}: the figure has an implausible size: {size} bytes")
        check(dims is None or (dims[0] >= 700 and dims[1] >= 500), f"{what}: the figure is only {dims} pixels")
    # The format follows the extension; an existing figure is replaced.
    svg = os.path.join(tmp, "figure.svg")
    r = run(ceilings, "--place", placed, "--out", svg)
    check(r.returncode == 0 and open(svg, encoding="utf-8").read().lstrip().startswith("<?xml"), f"--out .svg: {r.stderr}")
    r = run(ceilings, "--out", os.path.join(tmp, "figure0.png"))
    check(r.returncode == 0 and png_size(os.path.join(tmp, "figure0.png")), f"replacing a figure: exit {r.returncode} {r.stderr}")
    check(not leftovers(tmp), f"temporary files left: {leftovers(tmp)}")

# Bad input: exit 2, one line on stderr naming the problem, no figure created, an existing one
# left as it was.
with tempfile.TemporaryDirectory() as tmp:
    good = write(tmp, "ceilings.json", machine())
    placed = write(tmp, "placed.json", placement())

    def variant(name, change):
        doc = machine()
        change(doc)
        return write(tmp, name, doc)

    def placed_variant(name, change):
        doc = placement()
        change(doc)
        return write(tmp, name, doc)

    with open(os.path.join(tmp, "latin1.json"), "wb") as f:
        f.write(b'{"kind": "suite-roofline", "host": "\xe9"}')
    os.mkdir(os.path.join(tmp, "a-directory.json"))
    truncated = write(tmp, "truncated.json", json.dumps(machine())[:300])
    cases = [
        ([os.path.join(tmp, "missing.json")], "no such file"),
        ([os.path.join(tmp, "a-directory.json")], "cannot read it"),
        ([os.path.join(tmp, "latin1.json")], "cannot read it"),
        ([truncated], "not valid JSON"),
        ([write(tmp, "array.json", "[1, 2]")], "not a file of suite roofline"),
        ([write(tmp, "result.json", {"schema_version": 1, "context": {}, "results": []})], "kind None is not 'suite-roofline'"),
        ([variant("other-kind.json", lambda d: d.update(kind="suite-result"))], "kind 'suite-result' is not 'suite-roofline'"),
        ([placed], "give the ceilings file first"),
        ([variant("v2.json", lambda d: d.update(schema_version=2))], "schema_version 2 is not one this script knows"),
        ([variant("v-none.json", lambda d: d.pop("schema_version"))], "schema_version None"),
        ([variant("empty.json", lambda d: d.update(ceilings=[]))], "no ceilings"),
        ([variant("absent.json", lambda d: d.pop("ceilings"))], "no ceilings"),
        ([variant("unmeasured.json", lambda d: d.update(ceilings=[{"threads": 1, "peak_gflops": None, "peak": [], "bandwidth": []}]))],
         "no ceilings: no thread count has a peak or a bandwidth measured"),
        ([variant("string.json", lambda d: d["ceilings"][0]["bandwidth"][0].update(gbps="fast"))], "expected a number or null, got 'fast'"),
        ([variant("nan.json", lambda d: d["ceilings"][0].update(peak_gflops=float("nan")))], "peak_gflops: expected a number"),
        ([variant("zero-threads.json", lambda d: d["ceilings"][0].update(threads=0))], "'threads' must be a whole number"),
        ([variant("twice.json", lambda d: d["ceilings"][1].update(threads=1))], "threads 1 appears twice"),
        ([good, "--place", os.path.join(tmp, "missing-placed.json")], "missing-placed.json: no such file"),
        ([good, "--place", truncated], "not valid JSON"),
        ([good, "--place", good], "this is a ceilings file"),
        ([good, "--place", placed_variant("placed-v2.json", lambda d: d.update(schema_version=2))], "schema_version 2"),
        ([good, "--place", placed_variant("no-points.json", lambda d: d.pop("points"))], "no 'points' list"),
        ([good, "--place", placed_variant("bad-point.json", lambda d: d["points"][0].update(threads="one"))], "'threads' must be"),
    ]
    if os.geteuid() != 0:  # root reads any file
        unreadable = write(tmp, "unreadable.json", machine())
        os.chmod(unreadable, 0)
        cases.append(([unreadable], "cannot read it"))
    for n, (args, expected) in enumerate(cases):
        what = " ".join(os.path.basename(a) for a in args)
        fresh = os.path.join(tmp, f"new-{n}.png")
        r = run(*args, "--out", fresh)
        check(r.returncode == 2, f"{what}: expected exit 2, got {r.returncode}\n{r.stderr}")
        check(expected in r.stderr and r.stderr.count("\n") == 1, f"{what}: expected one line with {expected!r}, got {r.stderr!r}")
        check(not os.path.exists(fresh), f"{what}: {fresh} was created despite the error")
        existing = write(tmp, f"old-{n}.png", "the previous figure")
        r = run(*args, "--out", existing)
        check(r.returncode == 2 and open(existing).read() == "the previous figure", f"{what}: the existing output was changed")
    # Usage and outputs it may not write: the same, one line and nothing touched.
    outs = [(["--out", os.path.join(tmp, "figure.txt")], "is not a figure format"),
            (["--out", os.path.join(tmp, "no-such-dir", "f.png")], "does not exist"),
            (["--out", os.path.join(tmp, "a-directory.json")], "a directory"),
            (["--out", good], "same file as the input"),
            (["--out", placed, "--place", placed], "same file as the input"),
            ([], "the following arguments are required: --out")]
    before = open(good).read()
    for args, expected in outs:
        r = run(good, *args)
        check(r.returncode == 2 and expected in r.stderr and r.stderr.count("\n") == 1,
              f"{' '.join(args)}: expected exit 2 and one line with {expected!r}, got {r.returncode} {r.stderr!r}")
    check(open(good).read() == before, "the ceilings file was overwritten by a figure")
    check(not os.path.exists(os.path.join(tmp, "figure.txt")), "a figure.txt was written")
    check(not leftovers(tmp), f"temporary files left: {leftovers(tmp)}")

# The figure's contents, read from the matplotlib objects make_figure builds (no file written).
sys.path.insert(0, os.path.join(src, "plots"))
import roofline as rl  # noqa: E402
import roofline_model as model  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

plt = rl.pyplot()


def figure(ceilings_doc, placed_doc=None):
    return rl.make_figure(plt, model.Ceilings(ceilings_doc, "ceilings.json"),
                          model.Placement(placed_doc, "placed.json") if placed_doc else None)


def panel(fig, title):
    found = [a for a in fig.axes if a.get_title() == title]
    return found[0] if found else None


def lines(ax, gid):
    return [l for l in ax.get_lines() if l.get_gid() == gid]


def texts(ax):
    return [t.get_text() for t in ax.texts]


def close(a, b, rel=1e-9):
    return math.isclose(a, b, rel_tol=rel)


def check_ceilings(fig, doc, what):
    """Every thread count of `doc` in its panel: the peak, the narrower ISAs, a diagonal per level
    with a measured bandwidth, ending at the ridge."""
    for c in doc["ceilings"]:
        t = c["threads"]
        name = f"{t} thread{'s' if t > 1 else ''}"
        ax = panel(fig, name)
        if ax is None:
            check(False, f"{what}: no panel titled for {t} threads: {[a.get_title() for a in fig.axes]}")
            continue
        check(ax.get_xscale() == "log" and ax.get_yscale() == "log", f"{what}, {name}: axes are not log-log")
        check("flop/byte" in ax.get_xlabel() and "GFLOP/s" in ax.get_ylabel(), f"{what}, {name}: axis labels lack units")
        peak = c["peak_gflops"]
        peaks = lines(ax, rl.PEAK)
        check(len(peaks) == 1 and all(close(y, peak) for y in peaks[0].get_ydata()),
              f"{what}, {name}: expected one peak line at {peak}, got {[list(l.get_ydata()) for l in peaks]}")
        top = [p["isa"] for p in c["peak"] if p["gflops"] == peak]
        label = f"{top[-1] + ' ' if top else ''}peak {peak:.3g} GFLOP/s"
        check(label in texts(ax), f"{what}, {name}: no peak label {label!r} in {texts(ax)}")
        narrower = sorted(p["gflops"] for p in c["peak"] if p["gflops"] < peak)
        isa = sorted(l.get_ydata()[0] for l in lines(ax, rl.ISA))
        check(len(isa) == len(narrower) and all(close(a, b) for a, b in zip(isa, narrower)),
              f"{what}, {name}: narrower ISA lines at {isa}, expected {narrower}")
        measured = [b for b in c["bandwidth"] if b.get("gbps")]
        diagonals = lines(ax, rl.DIAGONAL)
        check(len(diagonals) == len(measured),
              f"{what}, {name}: {len(diagonals)} diagonals for {len(measured)} levels with a bandwidth ceiling")
        for b in measured:
            diagonal = f"{b['level']} {b['gbps']:.3g} GB/s"
            mine = [l for l in diagonals if l.get_label() == diagonal]
            check(len(mine) == 1 and diagonal in texts(ax), f"{what}, {name}: no diagonal labelled {diagonal!r}")
            if not mine:
                continue
            x, y = mine[0].get_xdata(), mine[0].get_ydata()
            check(all(close(yi, xi * b["gbps"]) for xi, yi in zip(x, y)), f"{what}, {name}: {diagonal} is not y = x * GB/s")
            check(close(x[-1], peak / b["gbps"]) and close(y[-1], peak), f"{what}, {name}: {diagonal} does not end at the ridge")
            check(any(close(r.get_xdata()[0], peak / b["gbps"]) and close(r.get_ydata()[0], peak) for r in lines(ax, rl.RIDGE)),
                  f"{what}, {name}: no ridge point for {diagonal}")


fig = figure(machine())
check_ceilings(fig, machine(), "dict machine")
title = fig._suptitle.get_text()
for part in ("vm", "(AMD EPYC)", "2026-11-27 10:00"):
    check(part in title, f"the title {title!r} lacks {part!r}")
check("incomplete" not in title, f"a complete run titled incomplete: {title!r}")
stamp = [t.get_text() for t in fig.texts if t.get_gid() == rl.STAMP]
check(len(stamp) == 1 and "0123456789abcdef" in stamp[0] and "ceilings.json" in stamp[0], f"the corner text: {stamp}")
check(not any(lines(a, rl.POINT) for a in fig.axes), "points drawn without a placement")
plt.close(fig)

# A level not measured (gbps null) has no diagonal; a thread count without a peak has diagonals
# to the edge and no ridge; an incomplete run says so.
doc = machine()
doc["ceilings"][0]["bandwidth"][1]["gbps"] = None
doc["ceilings"][1].update(peak_gflops=None, bandwidth=[{"level": "L1", "gbps": 400.0, "read_only": None, "read_write": None}])
doc["complete"] = False
fig = figure(doc)
one, two = panel(fig, "1 thread"), panel(fig, "2 threads")
check(one is not None and [l.get_label() for l in lines(one, rl.DIAGONAL)] == ["L1 210 GB/s"],
      f"DRAM not measured: diagonals {[l.get_label() for l in lines(one, rl.DIAGONAL)] if one else None}")
if two is not None:
    d = lines(two, rl.DIAGONAL)
    check(not lines(two, rl.PEAK) and not lines(two, rl.RIDGE) and len(d) == 1 and close(d[0].get_xdata()[-1], two.get_xlim()[1]),
          "no peak: expected one diagonal to the right edge, no peak line, no ridge")
else:
    check(False, "no peak: the 2-thread panel is missing")
check("incomplete" in fig._suptitle.get_text(), "an incomplete run is not said to be so in the title")
plt.close(fig)

# Points: at (intensity.stream, gflops) in their thread count's panel, colour of their level's
# diagonal, marker by group, hollow where not verified, numbered and named in the legend; kernels
# without flops at their GB/s in the second panel; a thread count without ceilings gets a panel.
doc, placed = machine(), placement()
fig = figure(doc, placed)
check_ceilings(fig, doc, "with points")
one = panel(fig, "1 thread")
diagonal_color = {l.get_label().split()[0]: to_rgba(l.get_color()) for l in lines(one, rl.DIAGONAL)}
by_label = {p["label"]: p for p in placed["points"]}
for t, title in ((1, "1 thread"), (2, "2 threads"), (4, "4 threads: no ceilings measured")):
    ax = panel(fig, title)
    if ax is None:
        check(False, f"points: no panel {title!r}: {[a.get_title() for a in fig.axes]}")
        continue
    expected = [p for p in placed["points"] if p["threads"] == t and p["gflops"] is not None]
    drawn = lines(ax, rl.POINT)
    check(len(drawn) == len(expected), f"points: {title}: {len(drawn)} points drawn, expected {len(expected)}")
    for p, l in zip(expected, drawn):
        check(close(l.get_xdata()[0], p["intensity"]["stream"]) and close(l.get_ydata()[0], p["gflops"]),
              f"points: {p['label']} drawn at ({l.get_xdata()[0]}, {l.get_ydata()[0]})")
        check((l.get_markerfacecolor() == "none") == (not p["verified"]), f"points: {p['label']}: hollow must mean not verified")
        if p["level"] in diagonal_color:
            check(to_rgba(l.get_markeredgecolor()) == diagonal_color[p["level"]], f"points: {p['label']} not in its level's colour")
one_points = lines(one, rl.POINT)
check(len({l.get_marker() for l in one_points}) == 2, "points: stream and fem share a marker")
legend = [t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()]
for n, label in enumerate(["triad sequential 64MiB t=1 compact/local", "triad sequential 16KiB t=1 compact/local"], 1):
    check(any(t.startswith(f"{n}  {label}") for t in legend), f"points: the legend does not name point {n} {label!r}: {legend}")
check(any(t.startswith("1  ") and "95% of its ceiling" in t for t in legend), f"points: the fraction is not in the legend: {legend}")
check(any("fem-spmv" in t and "not verified" in t for t in legend), "points: the legend does not say which is not verified")
flat = panel(fig, "1 thread: kernels without flops")
if flat is None:
    check(False, f"no panel for the kernels without flops: {[a.get_title() for a in fig.axes]}")
else:
    drawn = sorted(l.get_ydata()[0] for l in lines(flat, rl.POINT))
    check(drawn == [13.0, 90.0], f"kernels without flops: drawn at GB/s {drawn}, expected [13.0, 90.0]")
    check(flat.get_yscale() == "log", "kernels without flops: the GB/s axis is not log")
    ceilings_drawn = sorted(l.get_ydata()[0] for l in lines(flat, rl.BW_CEILING))
    check(ceilings_drawn == [16.0, 210.0], f"kernels without flops: level ceilings at {ceilings_drawn}, expected [16, 210]")
    hollow = [l for l in lines(flat, rl.POINT) if l.get_markerfacecolor() == "none"]
    check(len(hollow) == 1 and hollow[0].get_ydata()[0] == 90.0, "kernels without flops: the unverified sfc-build is not hollow")
notes = " ".join(t.get_text() for t in fig.texts)
check("latency random 1MiB t=1 compact/local" in notes and "no bandwidth or flops" in notes,
      f"the records not placed are not listed under the figure: {notes!r}")
key = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
for entry in ("stream", "fem", "sfc", "L1 (46.2KiB)", "DRAM", rl.HOLLOW_NOTE):
    check(entry in key, f"the key under the figure lacks {entry!r}: {key}")
plt.close(fig)

# The committed fixtures (the shape the C++ side writes): every ceiling and every point drawn.
ceilings_doc = json.load(open(os.path.join(fixtures, "ceilings.json")))
placed_doc = json.load(open(os.path.join(fixtures, "placed.json")))
check(ceilings_doc["kind"] == "suite-roofline" and placed_doc["kind"] == "suite-roofline-placement", "fixtures: wrong kinds")
check(sorted(c["threads"] for c in ceilings_doc["ceilings"]) == [1, 2], "fixtures: not a 2-thread machine")
fig = figure(ceilings_doc, placed_doc)
check_ceilings(fig, ceilings_doc, "fixture")
drawn = sum(len(lines(a, rl.POINT)) for a in fig.axes)
check(drawn == len(placed_doc["points"]) >= 12, f"fixture: {drawn} of {len(placed_doc['points'])} points drawn")
plt.close(fig)

for f in failures:
    print("FAIL:", f)
print(f"roofline_plot_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
