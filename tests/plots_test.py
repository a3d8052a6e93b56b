#!/usr/bin/python3
"""ctest: plots/plot.py renders the committed fixture results (tests/fixtures/results/) into every
expected figure, each a real PNG (signature, IHDR) of plausible size, and refuses bad input with
exit status 2 and one clear line. Then, on the matplotlib figures its functions build (fixtures
and copies of them changed in memory): log bandwidth axes, cache markers at the measured sizes
where the context has context.caches_measured (else the reported ones, so labelled), the probe's
sweeps in the 1-thread panels, the runs in a corner of every figure, whitespace-free CPU names,
counters titled by the kind of event counted, series kept apart by run and huge-pages setting,
unstable records hollow. Usage: plots_test.py SOURCE_DIR"""
import copy
import json
import os
import stat
import struct
import subprocess
import sys
import tempfile

src = sys.argv[1]
plot = os.path.join(src, "plots", "plot.py")
fixtures = os.path.join(src, "tests", "fixtures", "results")
failures = []


def check(cond, message):
    if not cond:
        failures.append(message)


def run(args, out):
    return subprocess.run([sys.executable, plot, *args, "--out", out], capture_output=True, text=True, timeout=120)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def expect_figures(args, names, svg=False):
    with tempfile.TemporaryDirectory() as out:
        r = run(args + (["--svg"] if svg else []), out)
        check(r.returncode == 0, f"plot.py {' '.join(args)}: exit {r.returncode}\n{r.stderr}")
        listed = set(os.path.basename(p) for p in r.stdout.split())
        for name in names:
            path = os.path.join(out, name + ".png")
            check(os.path.exists(path), f"{name}.png missing for {args}")
            check(name + ".png" in listed, f"{name}.png not listed on stdout for {args}")
            if not os.path.exists(path):
                continue
            size = os.path.getsize(path)
            dims = png_size(path)
            check(dims is not None, f"{name}.png is not a PNG")
            check(10_000 < size < 5_000_000, f"{name}.png has an implausible size: {size} bytes")
            if dims:
                check(dims[0] >= 500 and dims[1] >= 300, f"{name}.png is only {dims[0]}x{dims[1]} pixels")
            if svg:
                svg_path = os.path.join(out, name + ".svg")
                check(os.path.exists(svg_path) and os.path.getsize(svg_path) > 5_000, f"{name}.svg missing or tiny")
        return out, r


fx = lambda name: os.path.join(fixtures, name)

# One machine (two files of the same machine and build merge).
expect_figures([fx("vm-native.json"), fx("vm-native-latency.json")],
               ["bandwidth_vs_footprint", "latency_vs_footprint", "threads_scaling", "patterns"])
# Counters and energy (hand-made blocks on real records).
expect_figures([fx("vm-native-HANDMADE-counters-energy.json")], ["bandwidth_vs_footprint", "patterns", "counters", "energy"])

# Both schema versions: a version-1 file (a named parameter as its index) beside the same records
# as version 2 writes them (the name), on one figure.
with tempfile.TemporaryDirectory() as tmp:
    doc = json.load(open(fx("v1-mpm-case-index.json")))
    doc["schema_version"] = 2
    for r, name in zip(doc["results"], ("dam-collapse", "dam-break")):
        r["parameters"]["case"] = name
    v2 = os.path.join(tmp, "v2.json")
    json.dump(doc, open(v2, "w"))
    out = os.path.join(tmp, "figures")
    r = run([fx("v1-mpm-case-index.json"), v2, "--svg"], out)
    check(r.returncode == 0, f"both versions: exit {r.returncode}\n{r.stderr}")
    svg = open(os.path.join(out, "orderings.svg"), encoding="utf-8").read() if r.returncode == 0 else ""
    # Version 2's names label their series; version 1's indices stay the numbers they are.
    for label in ("case=dam-collapse", "case=dam-break", "case=0", "case=1"):
        check(label in svg, f"the two-version figure lacks the label {label!r}")

# Two builds of one machine: one line per machine, labelled by host, CPU and -march.
with tempfile.TemporaryDirectory() as out:
    r = run([fx("vm-native.json"), fx("vm-x86-64-v3.json"), "--svg"], out)
    check(r.returncode == 0, f"two machines: exit {r.returncode}\n{r.stderr}")
    svg = open(os.path.join(out, "bandwidth_vs_footprint.svg"), encoding="utf-8").read() if r.returncode == 0 else ""
    for label in ("vm (AMD EPYC) [native]", "vm (AMD EPYC) [x86-64-v3]"):
        check(label in svg, f"the two-machine figure lacks the label {label!r}")
    for name in ("bandwidth_vs_footprint", "threads_scaling", "patterns"):
        check(png_size(os.path.join(out, name + ".png")) is not None, f"two machines: {name}.png missing")

# Bad input: exit 2, one line on stderr naming the problem, nothing written.
with tempfile.TemporaryDirectory() as tmp:
    doc = json.load(open(fx("vm-native-latency.json")))
    doc["schema_version"] = 99
    future = os.path.join(tmp, "future.json")
    json.dump(doc, open(future, "w"))
    truncated = os.path.join(tmp, "truncated.json")
    open(truncated, "w").write(open(fx("vm-native-latency.json")).read()[:500])
    foreign = os.path.join(tmp, "foreign.json")
    json.dump({"context": {}, "benchmarks": []}, open(foreign, "w"))
    cases = [(future, "schema_version 99"), (truncated, "not valid JSON"), (foreign, "not a suite result"),
             (os.path.join(tmp, "missing.json"), "no such file")]
    for path, expected in cases:
        out = os.path.join(tmp, "out-" + os.path.basename(path))
        r = run([path], out)
        check(r.returncode == 2, f"{path}: expected exit 2, got {r.returncode}\n{r.stderr}")
        check(expected in r.stderr and r.stderr.count("\n") == 1, f"{path}: expected one line with {expected!r}, got {r.stderr!r}")
        check(not os.path.exists(out), f"{path}: the output directory was created despite the error")

# Figures go through the suite's one output policy (plots/safe_output.py): never into a FIFO
# or over a file being plotted, never into a --out that is a file; exit 2, one line, the
# FIFO still a FIFO, the input unchanged, no temporary file left.
with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "figs")
    os.mkdir(out)
    fifo = os.path.join(out, "bandwidth_vs_footprint.png")
    os.mkfifo(fifo)
    r = run([fx("vm-native.json")], out)
    check(r.returncode == 2 and "a FIFO" in r.stderr and r.stderr.count("\n") == 1,
          f"a FIFO in place of a figure: expected exit 2 and one line naming it, got {r.returncode} {r.stderr!r}")
    check(stat.S_ISFIFO(os.lstat(fifo).st_mode), "the FIFO was replaced")
    os.unlink(fifo)
    plotted = os.path.join(out, "bandwidth_vs_footprint.png")
    text = open(fx("vm-native.json")).read()
    open(plotted, "w").write(text)
    r = run([plotted], out)
    check(r.returncode == 2 and "same file as the input" in r.stderr,
          f"a figure over its own input: expected exit 2, got {r.returncode} {r.stderr!r}")
    check(open(plotted).read() == text, "the plotted file was overwritten by a figure")
    check(not [n for n in os.listdir(out) if ".tmp." in n], f"temporary files left: {os.listdir(out)}")
    not_a_dir = os.path.join(tmp, "file")
    open(not_a_dir, "w").write("x")
    r = run([fx("vm-native.json")], not_a_dir)
    check(r.returncode == 2 and "not a directory" in r.stderr, f"--out a file: expected exit 2, got {r.returncode} {r.stderr!r}")

# Figure contents, read from the figure objects plot.py builds (no files written).
sys.path.insert(0, os.path.join(src, "plots"))
import plot as pl  # noqa: E402  (the module; `plot` is the script's path)
import figure_parts as parts  # noqa: E402

plt = pl.pyplot()
native = json.load(open(fx("vm-native.json")))
latency_doc = json.load(open(fx("vm-native-latency.json")))


def figures(*docs):
    """{name: figure} for in-memory result documents, as plot.py would write them."""
    return dict(pl.make_figures(plt, pl.gather([(f"doc{i}.json", d) for i, d in enumerate(docs)])))


def panel(fig, title):
    found = [a for a in fig.axes if a.get_visible() and a.get_title() == title]
    return found[0] if found else None


def texts(ax):
    return [t.get_text().strip() for t in ax.texts]


def legend_texts(ax):
    leg = ax.get_legend()
    return [t.get_text() for t in leg.get_texts()] if leg else []


def hollow_points(ax):
    """Points drawn as hollow markers (white face, no line): plot.py's unstable points."""
    return sum(len(l.get_xdata()) for l in ax.get_lines()
               if l.get_linestyle() == "None" and l.get_markerfacecolor() == "white")


def close(figs):
    for f in figs.values():
        plt.close(f)


def probed(doc, l3=9860448):
    """A copy of `doc` with a cache probe in its context, as `suite run --probe-caches` writes it
    (the sizes the development VM measured); l3=None: the probe found no L3."""
    d = copy.deepcopy(doc)
    sweep = [4096 * 2 ** (i / 4) for i in range(40)]
    d["context"]["caches_measured"] = {
        "method": "latency: the latency kernel (random pointer chase), 1 thread; bandwidth: the load kernel, 1 thread; ...",
        "levels": [{"level": 1, "capacity_bytes": 47209, "reported_bytes": 49152, "latency_ns": 1.1, "partial": False},
                   {"level": 2, "capacity_bytes": 655781, "reported_bytes": 1048576, "latency_ns": 4.0, "partial": False},
                   {"level": 3, "capacity_bytes": l3, "reported_bytes": 33554432, "latency_ns": 15.0, "partial": False}],
        "bandwidth_sweep": [{"size_bytes": round(x), "gbps": 300.0 / (1 + x / 1e6)} for x in sweep],
        "latency_sweep": [{"size_bytes": round(x), "ns": 1 + x / 1e5} for x in sweep]}
    return d


# Bandwidth on log axes (random and sin-add are not flattened onto zero); latency too.
figs = figures(native, latency_doc)
for name in ("bandwidth_vs_footprint", "latency_vs_footprint", "patterns"):
    for ax in (a for a in figs[name].axes if a.get_visible()):
        check(ax.get_yscale() == "log", f"{name}: panel {ax.get_title()!r} has a {ax.get_yscale()} y axis, not log")
check(figs["threads_scaling"].axes[0].get_yscale() == "log", "threads_scaling: the bandwidth panel's y axis is not log")
check("GB/s" in figs["bandwidth_vs_footprint"].axes[0].get_ylabel(), "bandwidth_vs_footprint: no unit on the y axis")
# Without a probe the markers are hwloc's sizes, labelled as reported.
one = panel(figs["bandwidth_vs_footprint"], "1 thread")
check("L2 1MiB reported" in texts(one), f"no probe: expected the marker 'L2 1MiB reported', got {texts(one)}")
check(not any("measured" in t for t in texts(one)), f"no probe, yet a marker says measured: {texts(one)}")
check(not any(l.startswith("cache probe") for l in legend_texts(one)), "no probe, yet a probe line")

# Every figure: the runs in small text in a corner: host, CPU, date, suite version and revision.
for name, fig in figs.items():
    stamp = [t.get_text() for t in fig.texts if t.get_gid() == parts.STAMP_GID]
    check(len(stamp) == 1, f"{name}: expected one corner text naming the runs, got {stamp}")
    for part in ("vm", "AMD EPYC", "2026-11-22 04:44", "suite 0.1.0", "2ddd7e4d2055-dirty"):
        check(stamp and part in stamp[0], f"{name}: the corner text lacks {part!r}: {stamp}")
close(figs)

# With a probe: markers at the measured sizes (per-core caches once per thread, the shared L3
# once), and its sweeps as a grey line in the 1-thread panels only.
figs = figures(probed(native), probed(latency_doc))
bw = figs["bandwidth_vs_footprint"]
one, two = panel(bw, "1 thread"), panel(bw, "2 threads")
for label in ("L1d 46.1KiB measured", "L2 640KiB measured", "L3 9.4MiB measured"):
    check(label in texts(one), f"probe: 1-thread marker {label!r} missing: {texts(one)}")
for label in ("L1d 92.2KiB measured (x2)", "L2 1.25MiB measured (x2)", "L3 9.4MiB measured"):
    check(label in texts(two), f"probe: 2-thread marker {label!r} missing: {texts(two)}")
check(not any("reported" in t for t in texts(one) + texts(two)), "probe: a marker still at a reported size")
probe_lines = [l for l in one.get_lines() if l.get_label().startswith("cache probe")]
check(len(probe_lines) == 1 and "load kernel" in probe_lines[0].get_label() and len(probe_lines[0].get_xdata()) == 40,
      f"probe: expected one 40-point probe line naming the load kernel in the 1-thread panel, got {[l.get_label() for l in probe_lines]}")
check(not any(l.get_label().startswith("cache probe") for l in two.get_lines()), "probe line drawn in the 2-thread panel")
lat = panel(figs["latency_vs_footprint"], "1 thread")
check(any(l.get_label().startswith("cache probe") and "latency kernel" in l.get_label() for l in lat.get_lines()),
      f"probe: no latency-kernel probe line in latency_vs_footprint: {legend_texts(lat)}")
close(figs)
# A level the probe did not find falls back to the reported size, so labelled.
figs = figures(probed(native, l3=None))
one = panel(figs["bandwidth_vs_footprint"], "1 thread")
check("L3 32MiB reported" in texts(one) and "L2 640KiB measured" in texts(one), f"probe without L3: {texts(one)}")
close(figs)

# The CPU model without hwloc's padding, in the title and the corner.
padded = copy.deepcopy(native)
padded["context"]["cpu_model"] = "  Oxide Virtual   Turin-like Processor             "
figs = figures(padded)
title = figs["bandwidth_vs_footprint"]._suptitle.get_text()
check("(Oxide Virtual Turin-like Processor)" in title and "  " not in title, f"padded CPU name: title {title!r}")
close(figs)

# Counters titled by what was counted.
handmade = json.load(open(fx("vm-native-HANDMADE-counters-energy.json")))
figs = figures(handmade)
check(figs["counters"]._suptitle.get_text().startswith("Hardware counters"), "hardware events: title is not 'Hardware counters'")
close(figs)
software = copy.deepcopy(handmade)
for r in software["results"]:
    for e in r["counters"]["events"]:
        e["kind"] = "software"
figs = figures(software)
title = figs["counters"]._suptitle.get_text()
check(title.startswith("Counters (software events: ") and "Hardware" not in title, f"software events: title {title!r}")
close(figs)

# Series never merge across contexts. Another run of the machine (other date and command line)
# measuring the same kernels: separate lines, labelled by run; the same run given twice: once.
def bw_lines(figs, title="1 thread"):
    return [l.get_label() for l in panel(figs["bandwidth_vs_footprint"], title).get_lines()
            if not l.get_label().startswith("_")]


figs = figures(native)
alone = bw_lines(figs)
close(figs)
figs = figures(native, copy.deepcopy(native))
check(bw_lines(figs) == alone, f"the same run twice: expected {alone}, got {bw_lines(figs)}")
close(figs)
later = copy.deepcopy(native)
later["context"]["date"] = "2026-11-23T10:00:00Z"
later["context"]["command_line"] = later["context"]["command_line"] + ["--reps=7"]
figs = figures(native, later)
labels = bw_lines(figs)
check(len(labels) == 2 * len(alone), f"two runs of one machine: expected {2 * len(alone)} lines, got {len(labels)}")
for tag in ("run 2026-11-22 04:44", "run 2026-11-23 10:00"):
    check("copy sequential [" + tag + "]" in labels, f"two runs: no line labelled 'copy sequential [{tag}]' in {labels}")
close(figs)
# Records of one file with different huge-pages settings: separate lines and bars, so labelled.
mixed = copy.deepcopy(native)
for r in list(mixed["results"]):
    if r["name"] == "copy":
        r2 = copy.deepcopy(r)
        r2["hugepages"] = {"requested": "thp", "anon_huge_bytes": 0}
        mixed["results"].append(r2)
figs = figures(mixed)
labels = bw_lines(figs)
check("copy sequential [huge pages thp]" in labels and "copy sequential [huge pages unrecorded]" in labels,
      f"huge pages: expected separate labelled copy lines, got {labels}")
bars = [legend_texts(a) for a in figs["patterns"].axes if a.get_visible() and a.get_title().startswith("copy")]
check(bars and "sequential [huge pages thp]" in bars[0], f"huge pages: patterns legend {bars}")
close(figs)

# Unstable records hollow, the legend saying so once; no note where nothing is unstable.
shaky = copy.deepcopy(native)
flagged = {}
for r in shaky["results"]:
    if r["pattern"] == "random" and r["size"]["requested"] == 1048576:
        r["stability"] = {"unstable": True, "reasons": ["the repetitions spread 23% (over 10%)"]}
        flagged[r["threads"]] = flagged.get(r["threads"], 0) + 1
    else:
        r["stability"] = {"unstable": False, "reasons": []}
figs = figures(shaky)
for t, title in ((1, "1 thread"), (2, "2 threads")):
    ax = panel(figs["bandwidth_vs_footprint"], title)
    check(hollow_points(ax) == flagged[t], f"unstable: {title}: {hollow_points(ax)} hollow points, expected {flagged[t]}")
    check(legend_texts(ax).count(parts.UNSTABLE_NOTE) == 1, f"unstable: {title}: legend {legend_texts(ax)}")
pat = [a for a in figs["patterns"].axes if a.get_visible()]
white = sum(1 for a in pat for p in a.patches if tuple(p.get_facecolor()) == (1.0, 1.0, 1.0, 1.0))
check(white == flagged[1], f"unstable: {white} hollow bars in patterns, expected {flagged[1]} (1 thread)")
check(all(legend_texts(a).count(parts.UNSTABLE_NOTE) == 1 for a in pat), "unstable: a patterns legend lacks the note")
close(figs)
figs = figures(native)
check(hollow_points(panel(figs["bandwidth_vs_footprint"], "1 thread")) == 0, "no stability block, yet hollow points")
check(not any(parts.UNSTABLE_NOTE in legend_texts(a) for f in figs.values() for a in f.axes), "nothing unstable, yet the note")
close(figs)

# End to end: a probed, partly unstable result with software counters renders every figure.
with tempfile.TemporaryDirectory() as tmp:
    full = probed(shaky)
    for r in full["results"]:
        r["counters"] = copy.deepcopy(software["results"][0]["counters"])
    path = os.path.join(tmp, "full.json")
    json.dump(full, open(path, "w"))
    expect_figures([path], ["bandwidth_vs_footprint", "threads_scaling", "patterns", "counters"])

for f in failures:
    print("FAIL:", f)
print(f"plots_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
