#!/usr/bin/python3
"""A hostile but realistic user's round over every command of the suite (issue 52's own round).

Usage: hostile_round.py SUITE_BINARY [--list]

Each case is a command line and what it must do: `usage` (exit 2, exactly one line on stderr,
nothing created in the scratch folder and every file there byte for byte), `ok` (exit 0), or
`any` (a clean end: exit 0 to 3, no signal, no timeout). Every case must also end within its
time limit, without `terminate called`, an assertion or a Python traceback. Prints one line per
case that was not handled, then the counts; exit 1 when any case was not handled.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

TIMEOUT = 20


def snapshot(root):
    """Every name under root with its content's hash (a FIFO or a directory by its kind)."""
    out = {}
    for base, dirs, files in os.walk(root):
        for n in dirs + files:
            p = os.path.join(base, n)
            if os.path.islink(p):
                out[p] = "link:" + os.readlink(p)
            elif os.path.isdir(p):
                out[p] = "dir"
            elif not os.path.isfile(p):
                out[p] = "special"
            else:
                with open(p, "rb") as f:
                    out[p] = hashlib.sha256(f.read()).hexdigest()
    return out


def roofline_dram_size(run_file):
    """--dram-size for a small roofline: 48 MiB, or twice the last level where hwloc says it holds more
    (the roofline refuses a memory footprint the caches hold; some hosts report 1016 MiB), as
    tests/cli/roofline_size.hpp sizes it, from the topology a run recorded."""
    with open(run_file) as f:
        caches = json.load(f)["context"]["topology"]["caches"]
    top = max((c["level"] for c in caches), default=0)
    llc = sum(c["size_bytes"] * c["instances"] for c in caches if c["level"] == top)
    mib = max(48, (2 * llc + (1 << 20) - 1) >> 20)
    return f"--dram-size={mib}MiB"


def make_scratch(suite):
    d = tempfile.mkdtemp(prefix="suite-hostile-")
    subprocess.run([suite, "--kernel=triad", "--sizes=64KiB", "--threads=1", "--reps=2", "-q",
                    "--out=" + d + "/run.json"], check=True, timeout=120)
    subprocess.run([suite, "--kernel=peak-flops", "--isa=scalar", "--size=4096", "--threads=1", "--reps=2", "-q",
                    "--out=" + d + "/peak.json"], check=True, timeout=120)
    subprocess.run([suite, "roofline", "--threads=1", "--min-time=0.02", roofline_dram_size(d + "/run.json"),
                    "--no-png", "--no-probe", "--out=" + d + "/roof.json"], check=True, timeout=300,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    subprocess.run([suite, "history", "add", d + "/run.json", "--db=" + d + "/h.sqlite", "--commit=abcdef1"],
                   check=True, timeout=120, stdout=subprocess.DEVNULL)
    with open(d + "/notes.txt", "w") as f:
        f.write("the user's notes\n")
    with open(d + "/empty.json", "w"):
        pass
    with open(d + "/notjson.json", "w") as f:
        f.write("this is not json {")
    with open(d + "/array.json", "w") as f:
        f.write("[1, 2, 3]")
    with open(d + "/object.json", "w") as f:
        f.write("{}")
    with open(d + "/deep.json", "w") as f:
        f.write("[" * 200000)
    with open(d + "/binary.json", "wb") as f:
        f.write(bytes(range(256)) * 64)
    run = json.load(open(d + "/run.json"))
    newer = dict(run, schema_version=99)
    json.dump(newer, open(d + "/newer.json", "w"))
    trunc = open(d + "/run.json").read()
    open(d + "/truncated.json", "w").write(trunc[: len(trunc) // 2])
    norec = dict(run, results=[])
    json.dump(norec, open(d + "/norecords.json", "w"))
    nan = open(d + "/run.json").read().replace('"seed": 1', '"seed": NaN', 1)
    open(d + "/nan.json", "w").write(nan)
    roof = json.load(open(d + "/roof.json"))
    json.dump(dict(roof, fingerprint="0000000000000000"), open(d + "/roof_fp.json", "w"))
    r2 = json.loads(json.dumps(roof))
    r2["ceilings"] = []
    json.dump(r2, open(d + "/roof_empty.json", "w"))
    r3 = json.loads(json.dumps(roof))
    r3["ceilings"][0]["peak"][0]["gflops"] = -1
    json.dump(r3, open(d + "/roof_neg.json", "w"))
    r4 = json.loads(json.dumps(roof))
    r4["ceilings"][0]["peak"][0]["gflops"] = 1e308 * 10 if False else 1e308
    json.dump(r4, open(d + "/roof_huge.json", "w"))
    os.mkfifo(d + "/fifo.json")
    os.mkdir(d + "/adir")
    os.symlink(d + "/run.json", d + "/link.json")
    os.symlink(d + "/nowhere.json", d + "/dangling.json")
    with open(d + "/mesh.txt", "w") as f:
        f.write("3 1\n0 0\n1 0\n0 1\n1 2 3\n")
    with open(d + "/badmesh.txt", "w") as f:
        f.write("3 1\n0 0\n1 0\nnan 1\n1 2 3\n")
    with open(d + "/mesh_hugecount.txt", "w") as f:
        f.write("99999999999999 1\n0 0\n")
    return d


def cases(d):
    u, ok, anyc = "usage", "ok", "any"
    c = []
    dry = ["--dry-run", "--threads=1"]
    # run: sizes
    for v in ["0", "-1", "1.5B", "64KiB:", ":64KiB", "64KiB:1KiB", "16KiB:1MiB:x1", "16KiB:1MiB:x0.5",
              "16KiB:1MiB:xnan", "64KiB,,128KiB", "64KiB,64KiB", "nan", "inf", "1e3", "0x40",
              "99999999999999999999", "18446744073709551616B", "64 KiB", "64KiB ", "\u221e", "64\uff2biB", "1EiB",
              "64KiB\n", "-64KiB", "+64KiB", "64KiB;rm", "1e-3MiB"]:
        c.append((["--kernel=triad", "--sizes=" + v] + dry, u))
    for v in ["0", "-1", "1-", "-", "2-1", "1-8:0", "1-8:-1", "all,all", "1,1", "999999", "1.5", "a", "1 2",
              "ALL", "0-0", "1-99999999999", "+1"]:
        c.append((["--kernel=triad", "--size=64KiB", "--dry-run", "--threads=" + v], u))
    for v in ["0-", "99999", "0,0", "a", "-1", "compact,scatter", "0-99999999999", "0--1", "0:1"]:
        c.append((["--kernel=triad", "--size=64KiB", "--pin=" + v] + dry, u))
    for v in ["node:", "node:-1", "node:99", "node:1.5", "interleave:x", "LOCAL", "local,local", "node:0x0",
              "remote:1", ""]:
        c.append((["--kernel=triad", "--size=64KiB", "--placement=" + v] + dry, u))
    for v in ["0", "-1", "1e3", "10000001", "abc", "1.0", ""]:
        c.append((["--kernel=triad", "--size=64KiB", "--reps=" + v] + dry, u))
    for v in ["-1", "18446744073709551616", "1e3", "0x10", "", " 1"]:
        c.append((["--kernel=triad", "--size=64KiB", "--seed=" + v] + dry, u))
    for v in ["xml", "csv,json", "", "JSON "]:
        c.append((["--kernel=triad", "--size=64KiB", "--format=" + v] + dry, u))
    for v in ["nonsense", "cycles,cycles", ",", "cycles,", ""]:
        c.append((["--kernel=triad", "--size=64KiB", "--counters=" + v] + dry, u))
    for v in ["bogus", "perf,sysfs", ""]:
        c.append((["--kernel=triad", "--size=64KiB", "--energy=" + v] + dry, u))
    for v in ["-1", "nan", "inf", "1e9", "abc"]:
        c.append((["--kernel=triad", "--size=64KiB", "--energy-baseline=" + v] + dry, u))
    for v in ["0", "-1", "nan", "inf", "1e9", "abc"]:
        c.append((["--kernel=triad", "--size=64KiB", "--min-time=" + v] + dry, u))
    for v in ["yes", "THP ", ""]:
        c.append((["--kernel=triad", "--size=64KiB", "--hugepages=" + v] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--pattern=random", "--stores=nt"] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--stores=bogus"] + dry, u))
    c.append((["--kernel=peak-flops", "--isa=avx1024"] + dry, u))
    c.append((["--kernel=peak-flops", "--isa=scalar,scalar"] + dry, u))
    for v in ["", ",", "add,,add", "ADD", "add ", "../add", "add,add", "\u0430dd"]:
        c.append((["--kernel=" + v, "--size=64KiB"] + dry, u))
    for v in ["strided:0", "strided:-1", "strided:", "strided:1.5", "strided:99999999999999999999",
              "random,random", "Random"]:
        c.append((["--kernel=add", "--size=64KiB", "--pattern=" + v] + dry, u))
    for v in ["bogus", "natural,natural"]:
        c.append((["--kernel=fem-spmv", "--mesh=disk:refine=2", "--ordering=" + v] + dry, u))
    for v in ["disk:refine=-1", "disk:refine=99", "box:0,1,1", "box:-1,1,1", "box:1,1", "file:",
              "file:/nonexistent", "file:/dev/null", "file:/proc/self/status", "file:" + d + "/adir",
              "disk:refine=1.5", "box:99999,99999,99999", "file:" + d + "/badmesh.txt",
              "file:" + d + "/mesh_hugecount.txt", "disk", "disk:refine=", "file:" + d + "/fifo.json"]:
        c.append((["--kernel=fem-spmv", "--mesh=" + v] + dry, u))
    for v in ["0", "1.5", "1e300", "-1", "abc"]:
        c.append((["--kernel=fem-cg", "--mesh=disk:refine=2", "--cg-max=" + v] + dry, u))
    for v in ["0", "1", "-1", "nan"]:
        c.append((["--kernel=fem-cg", "--mesh=disk:refine=2", "--cg-tol=" + v] + dry, u))
    for v in ["-1", "nan", "inf"]:
        c.append((["--kernel=fem-spmv", "--mesh=disk:refine=2", "--delta=" + v] + dry, u))
    for v in ["dam", "3", "-1"]:
        c.append((["--kernel=mpm-p2g", "--case=" + v] + dry, u))
    for v in ["0", "-1", "1.5"]:
        c.append((["--kernel=mpm-p2g", "--ppe=" + v] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--delta=1"] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--phase=bogus"] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--bogus"] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--size=128KiB"] + dry, u))
    c.append((["--kernel=triad", "--size=64KiB", "--sizes=64KiB"] + dry, u))
    # run: outputs
    for v in ["/dev/full", d + "/adir", d + "/link.json", "/proc/version", d + "/fifo.json", d + "/adir/",
              d + "/missing/x.json", d + "/" + "x" * 300 + ".json", d + "/run.json.lock/x",
              d + "/dangling.json", d + "/mesh.txt/x.json"]:
        c.append((["--kernel=triad", "--size=64KiB", "--out=" + v] + dry, u))
    c.append((["--kernel=fem-spmv", "--mesh=file:" + d + "/mesh.txt", "--out=" + d + "/mesh.txt"] + dry, u))
    # list, info
    c += [(["list", "--bogus"], u), (["list", "extra"], u), (["info", "extra"], u), (["info", "--bogus"], u),
          (["list", "--json"], ok), (["list", "--counters", "--json"], anyc), (["info", "--json"], ok),
          (["--version", "extra"], anyc), (["bogus-command"], u)]
    # compare, check
    bad_inputs = ["/nonexistent.json", d + "/adir", d + "/empty.json", d + "/notjson.json", d + "/array.json",
                  d + "/object.json", d + "/deep.json", d + "/binary.json", d + "/newer.json", d + "/truncated.json",
                  "/dev/null", "/proc/version", d + "/fifo.json", d + "/roof.json", d + "/nan.json",
                  d + "/dangling.json", d + "/h.sqlite"]
    for b in bad_inputs:
        c.append((["compare", b, d + "/run.json"], u))
        c.append((["check", "--baseline", b, d + "/run.json"], u))
    c.append((["--kernel=triad", "--size=64KiB", "--out=" + d + "/new\nline.json"] + dry, anyc))
    c += [(["compare"], u), (["compare", d + "/run.json"], anyc), (["compare", d + "/run.json", d + "/run.json"], anyc),
          (["compare", d + "/run.json", d + "/link.json"], anyc), (["compare", "--format=bogus", d + "/run.json",
                                                                      d + "/run.json"], u),
          (["check", d + "/run.json"], u), (["check", "--baseline", d + "/run.json"], u),
          (["check", "--baseline", d + "/run.json", d + "/run.json", "--markdown=" + d + "/run.json"], u),
          (["check", "--baseline", d + "/run.json", d + "/run.json", "--markdown=/dev/full"], u),
          (["check", "--baseline", d + "/run.json", d + "/run.json", "--markdown=" + d + "/adir"], u),
          (["check", "--baseline", d + "/run.json", d + "/run.json", "--markdown=" + d + "/fifo.json"], u),
          (["check", "--baseline", d + "/run.json", d + "/norecords.json"], anyc)]
    for v in ["-5%", "abc", "nan%", "1000000%", ""]:
        c.append((["check", "--baseline", d + "/run.json", d + "/run.json", "--tolerance=" + v], u))
    for v in ["0", "1", "nan", "-0.1", "abc"]:
        c.append((["check", "--baseline", d + "/run.json", d + "/run.json", "--alpha=" + v], u))
    # history
    db = "--db=" + d + "/h.sqlite"
    for v in [d + "/adir", d + "/fifo.json", "/dev/null", "/proc/version", d + "/run.json", d + "/notes.txt",
              d + "/missing/h.sqlite", d + "/link.json"]:
        c.append((["history", "list", "--db=" + v], u))
        c.append((["history", "add", d + "/run.json", "--db=" + v], u))
    c += [(["history", "add", db], u), (["history", "add", d + "/norecords.json", db], u),
          (["history", "add", d + "/fifo.json", db], u), (["history", "add", d + "/roof.json", db], u),
          (["history", "add", d + "/run.json", db, "--wait=-1"], u),
          (["history", "add", d + "/run.json", db, "--wait=99999"], u),
          (["history", "add", d + "/run.json", db, "--branch="], u),
          (["history", "list", db], ok), (["history", "steps", db, "--kernel=bogus"], u),
          (["history", "steps", db, "--machine=zzzz"], u), (["history", "check", d + "/run.json", db, "--window=0"], u),
          (["history", "check", d + "/run.json", db, "--tolerance=-5%"], u),
          (["history", "check", d + "/run.json", db, "--alpha=0"], u),
          (["history", "check", d + "/run.json", db, "--alpha=nan"], u),
          (["history", "check", d + "/run.json", d + "/run.json", db], u),
          (["history", "check", d + "/run.json", db, "--markdown=" + d + "/h.sqlite"], u),
          (["history", "check", d + "/run.json", db, "--confirm=" + d + "/fifo.json"], u),
          (["history", "html", db, "--out=" + d + "/notes.txt"], u),
          (["history", "html", db, "--out=" + d + "/fifo.json"], u),
          (["history", "html", db, "--out=" + d + "/link.json"], u),
          (["history", "html", db], u), (["history", "noise", db, "--window=0"], u),
          (["history", "bogus"], u), (["history"], anyc)]
    for v in ["ab", "abc1234;x", "abc1234\nx", "main", "a" * 41, "g123456", " abcdef1"]:
        c.append((["history", "add", d + "/run.json", db, "--commit=" + v], u))
    # roofline
    for v in ["0", "bogus", "1-", "999999"]:
        c.append((["roofline", "--threads=" + v], u))
    for v in ["bogus", "99999"]:
        c.append((["roofline", "--pin=" + v], u))
    for v in ["0", "-1", "nan", "100", "abc"]:
        c.append((["roofline", "--min-time=" + v], u))
    for v in ["0", "-1", "1KiB", "bogus", "1MiB", "1000GiB", "1EiB"]:
        c.append((["roofline", "--dram-size=" + v], u))
    for b in bad_inputs + [d + "/norecords.json"]:
        if b.endswith("roof.json"):
            continue
        c.append((["roofline", "--place=" + b, "--ceilings=" + d + "/roof.json"], u))
    for b in bad_inputs + [d + "/run.json", d + "/roof_fp.json", d + "/roof_empty.json", d + "/roof_neg.json"]:
        if b.endswith("roof.json"):
            continue
        c.append((["roofline", "--place=" + d + "/run.json", "--ceilings=" + b], u))
    c += [(["roofline", "--ceilings=" + d + "/roof.json"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=" + d + "/adir"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=/dev/full"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=" + d + "/fifo.json"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=" + d + "/run.json"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=" + d + "/roof.json"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--out=" + d + "/x.png"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json", "--threads=1"], u),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof.json"], ok),
          (["roofline", "--place=" + d + "/link.json", "--ceilings=" + d + "/roof.json"], ok),
          (["roofline", "--place=" + d + "/peak.json", "--ceilings=" + d + "/roof.json"], anyc),
          (["roofline", "--place=" + d + "/run.json", "--ceilings=" + d + "/roof_huge.json"], anyc),
          (["roofline", "--bogus"], u)]
    # mpm
    mp = ["mpm", "--mesh=box:4,4,4", "--dry-run"]
    for o, vals in [("--mesh", ["box:0,4,4", "disk:refine=2", "box:4,4", "box:99999,99999,99999", "file:/dev/null",
                                "file:" + d + "/fifo.json"]),
                    ("--steps", ["-1", "abc", "1e99", "1.5"]),
                    ("--dt", ["-1", "nan", "inf", "1e300", "abc"]),
                    ("--case", ["bogus", ""]), ("--ppe", ["0", "-1", "1.5"]),
                    ("--threads", ["0", "-1", "9999999", "1,2"]),
                    ("--vtk-every", ["-1", "abc"]), ("--integrator", ["bogus"]), ("--solver", ["bogus"]),
                    ("--newton-max", ["0", "-1"]), ("--courant", ["0", "2", "nan", "-1"]),
                    ("--damping", ["-1", "nan"]), ("--young", ["0", "-1", "nan", "1e-320"]),
                    ("--density", ["0", "-1", "1e300"]), ("--poisson", ["0.5", "-1", "1", "nan"]),
                    ("--seed", ["-1", "abc"]), ("--particles", ["bogus"]), ("--ordering", ["bogus"]),
                    ("--strategy", ["bogus"]), ("--sort-every", ["-1", "abc", "autos"]), ("--sort-threshold", ["0", "nan", "abc"]),
                    ("--renumber-share", ["-1", "2", "nan", "abc"]), ("--warm-steps", ["-1"]),
                    ("--newmark", ["bogus", "0.1,0.1", "1,1,1"]), ("--strain", ["bogus"]),
                    ("--force", ["bogus"]), ("--column", ["0", "-1", "bogus"])]:
        for v in vals:
            c.append((mp + [o + "=" + v], u))
    c += [(mp + ["--particles=dynamic", "--renumber-share=" + v], u) for v in ["-0.5", "1.01", "nan", "inf"]]
    c += [(["mpm", "--mesh=box:4,4,4", "--integrator=implicit", "--dt=1e-300", "--dry-run"], u),
          (["mpm", "--mesh=box:4,4,4", "--dt=0", "--dry-run"], ok),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d + "/notes.txt", "--steps=1", "--no-png"], u),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d + "/fifo.json", "--steps=1", "--no-png"], u),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d + "/link.json", "--steps=1", "--no-png"], u),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d + "/missing/m", "--steps=1", "--no-png"], u),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d, "--steps=1", "--no-png"], u),
          (["mpm", "--mesh=box:4,4,4", "--out=" + d + "/adir", "--steps=0", "--no-png", "-q"], ok)]
    # matrix, traverse
    for o, vals in [("--mesh", ["disk:refine=-1", "box:0,1,1", "file:/nonexistent", "file:" + d + "/fifo.json"]),
                    ("--ordering", ["bogus", "natural,natural"]), ("--delta", ["nan", "-1"]),
                    ("--threads", ["0", "-1"]), ("--max-factor", ["bogus", "-1", "0"]), ("--reps", ["0", "-1"]),
                    ("--seed", ["-1"]), ("--export", ["bogus"])]:
        for v in vals:
            c.append((["matrix", "--mesh=disk:refine=2", o + "=" + v, "--dry-run"], u))
    for o, vals in [("--mesh", ["disk:refine=-1", "file:" + d + "/fifo.json"]), ("--ordering", ["bogus"]),
                    ("--threads", ["0"]), ("--depth", ["0", "-1", "99"]), ("--seed", ["-1"])]:
        for v in vals:
            c.append((["traverse", "--mesh=disk:refine=2", o + "=" + v, "--dry-run"], u))
    c += [(["matrix", "--mesh=disk:refine=2", "--out=" + d + "/notes.txt", "--dry-run"], u),
          (["traverse", "--mesh=disk:refine=2", "--out=" + d + "/notes.txt", "--dry-run"], u),
          (["deterministic", "--kernel=bogus"], u)]
    return c


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    suite = os.path.abspath(argv[1])
    d = make_scratch(suite)
    all_cases = cases(d)
    if "--list" in argv:
        for args, want in all_cases:
            print(want, " ".join(args))
        shutil.rmtree(d, ignore_errors=True)
        return 0
    handled, failures = 0, []
    for args, want in all_cases:
        before = snapshot(d)
        try:
            p = subprocess.run([suite] + args, capture_output=True, timeout=TIMEOUT, cwd=d,
                               stdin=subprocess.DEVNULL)
            status, out, err = p.returncode, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace")
        except subprocess.TimeoutExpired:
            failures.append((args, want, "timed out after %d s" % TIMEOUT))
            continue
        after = snapshot(d)
        problems = []
        if status < 0:
            problems.append("killed by signal %d" % -status)
        if any(s in err for s in ("terminate called", "Assertion", "Traceback", "what():")):
            problems.append("crash text on stderr")
        if want == "usage":
            if status != 2:
                problems.append("exit %d, not 2" % status)
            elif err.count("\n") != 1:
                problems.append("%d lines on stderr" % err.count("\n"))
            if after != before:
                changed = sorted(set(after.items()) ^ set(before.items()))
                problems.append("files changed: %s" % sorted({k for k, _ in changed})[:3])
        elif want == "ok" and status != 0:
            problems.append("exit %d, not 0" % status)
        elif want == "any" and status not in (0, 1, 2, 3):
            problems.append("exit %d" % status)
        if problems:
            failures.append((args, want, "; ".join(problems) + " | " + err.strip().replace("\n", " / ")[:300]))
        else:
            handled += 1
        # What a case may write (an ok case) is removed so that the next one starts alike.
        for p in after:
            if p not in before and os.path.lexists(p):
                if os.path.isdir(p) and not os.path.islink(p):
                    shutil.rmtree(p, ignore_errors=True)
                else:
                    try:
                        os.unlink(p)
                    except OSError:
                        pass
    for args, want, why in failures:
        print("NOT HANDLED (%s): suite %s: %s" % (want, " ".join(repr(a) if (" " in a or "\n" in a) else a
                                                              for a in args), why))
    print("tried %d, handled %d, not handled %d" % (len(all_cases), handled, len(failures)))
    shutil.rmtree(d, ignore_errors=True)
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
