#!/usr/bin/python3
"""ctest: plots/plot.py renders the committed fixture results (tests/fixtures/results/) into every
expected figure, each a real PNG (signature, IHDR) of plausible size, and refuses bad input with
exit status 2 and one clear line. Usage: plots_test.py SOURCE_DIR"""
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

for f in failures:
    print("FAIL:", f)
print(f"plots_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
