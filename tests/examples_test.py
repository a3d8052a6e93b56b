#!/usr/bin/python3
"""ctest: machines compared by cache level (suite compare by role), on committed results.

1. The committed examples (results/examples/*.json, made by `make examples`) are valid against
   today's schema, record the role of every default point, and are comparable with a fresh run of
   today's build: `suite compare FRESH EXAMPLE` succeeds and finds every point of the fresh run.
2. The committed fixtures of two machines whose caches differ (tests/fixtures/results/roles-*.json,
   also made by `make examples`): every default point matched by role, none left unmatched, each
   file's size shown, a geometric mean per role; `--plot DIR` draws real PNGs, one per kernel,
   pattern and thread count, and refuses a directory it may not write before reading anything.
3. Bad input, one line on stderr and exit 2, no table: no roles and no shared sizes, another
   schema version, a role one file lacks; settings the user chose named when the machines differ.

Usage: examples_test.py SUITE SOURCE_DIR
"""
import copy
import json
import os
import re
import subprocess
import sys
import tempfile

import jsonschema

suite, src = sys.argv[1], sys.argv[2]
fixtures = os.path.join(src, "tests", "fixtures", "results")
small, big = os.path.join(fixtures, "roles-small-caches.json"), os.path.join(fixtures, "roles-big-caches.json")
failures = []


def check(cond, message):
    if not cond:
        failures.append(message)


def run(*args, timeout=300):
    return subprocess.run([suite, *args], capture_output=True, text=True, timeout=timeout)


def roles(doc):
    return [(r["size"].get("role") or {}).get("name") for r in doc["results"]]


def found_all(out, n):
    """The compare summary says all n points of [1] were found, and nothing of another file is left over."""
    m = re.search(r"(\d+) point\(s\) of \[1\] found in another file([;.])", out)
    return m is not None and int(m.group(1)) == n and m.group(2) == "." and "are not in [1]" not in out


def one_line_error(r, what, text):
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2\n{r.stderr}")
    check(len(lines) == 1, f"{what}: {len(lines)} lines on stderr, expected one:\n{r.stderr}")
    check(text in r.stderr, f"{what}: stderr lacks {text!r}:\n{r.stderr}")
    check("vs [1]" not in r.stdout, f"{what}: printed a table:\n{r.stdout}")



def todays_schema_version():
    """The schema_version this build writes: what `suite list --json` says is not it, so a tiny run's."""
    with tempfile.TemporaryDirectory() as t:
        out = os.path.join(t, "v.json")
        r = run("--kernel=copy", "--sizes=64KiB", "--threads=1", "--reps=2", "--min-time=0.001", "--quiet", "--out=" + out)
        check(r.returncode == 0, f"a tiny run failed: {r.returncode}\n{r.stderr}")
        with open(out) as f:
            return json.load(f)["schema_version"]


version = todays_schema_version()
with open(os.path.join(src, "results", "schema", f"v{version}.json")) as f:
    schema = json.load(f)
examples_dir = os.path.join(src, "results", "examples")
examples = sorted(os.path.join(examples_dir, n) for n in os.listdir(examples_dir) if n.endswith(".json"))
check(examples, "no committed example in results/examples/")

with tempfile.TemporaryDirectory() as tmp:
    # 1. The examples: valid, with roles, comparable with a fresh run of today's build.
    fresh = os.path.join(tmp, "fresh.json")
    r = run("--kernel=copy,latency", "--threads=1", "--reps=3", "--min-time=0.01", "--quiet", "--out=" + fresh)
    check(r.returncode == 0, f"the fresh run failed: {r.returncode}\n{r.stderr}")
    for path in examples + [small, big] + ([fresh] if r.returncode == 0 else []):
        with open(path) as f:
            doc = json.load(f)
        check(doc.get("schema_version") == version,
              f"{path}: schema_version {doc.get('schema_version')}, today's build writes {version}: make examples")
        errors = list(jsonschema.Draft202012Validator(schema).iter_errors(doc))
        check(not errors, f"{path}: not valid against today's schema (v{version}.json): {errors[:1]}")
        check(all(roles(doc)), f"{path}: a default point without its role: {roles(doc)}")
    for example in examples:
        if r.returncode != 0:
            break
        c = run("compare", fresh, example)
        check(c.returncode == 0, f"compare with a fresh run of today's build: exit {c.returncode}\n{c.stderr}")
        with open(fresh) as f:
            n = len(json.load(f)["results"])
        check(f"{n} point(s) of [1] found in another file." in c.stdout,
              f"{example}: not every point of the fresh run found:\n{c.stdout}")

    # 2. Two machines whose caches differ: every default point meets its role.
    with open(small) as f:
        a = json.load(f)
    with open(big) as f:
        b = json.load(f)
    sizes = lambda doc: {(x["kernel"], x["threads"], x["size"]["role"]["name"]): x["size"]["requested"] for x in doc["results"]}
    check(a["context"]["topology"]["caches"] != b["context"]["topology"]["caches"], "the fixtures' caches are the same")
    check(set(roles(a)) == set(roles(b)) == {"L1/2", "L2/2", "DRAM"}, f"roles {set(roles(a))} and {set(roles(b))}")
    differ = [k for k in sizes(a) if k in sizes(b) and sizes(a)[k] != sizes(b)[k]]
    check(len(differ) >= len(sizes(a)) // 2, f"the fixtures' sizes hardly differ: {differ}")
    c = run("compare", small, big)
    check(c.returncode == 0, f"compare by role: exit {c.returncode}\n{c.stderr}")
    check(found_all(c.stdout, len(a["results"])), f"not every point matched by role:\n{c.stdout}")
    check("[2] size" in c.stdout and "per cache role" in c.stdout, f"no sizes or no mean per role:\n{c.stdout}")
    for role in ("L1/2", "L2/2", "DRAM"):
        check(re.search(r"^" + re.escape(role) + r"\s+\d+\.\d{3}x\s+\d+$", c.stdout, re.M), f"no mean for {role}:\n{c.stdout}")
    # Three files: one column set each, ratios to the first.
    c3 = run("compare", small, big, big)
    check(c3.returncode == 0 and "[3] size" in c3.stdout and "[3] vs [1]" in c3.stdout, f"three files:\n{c3.stdout}{c3.stderr}")
    # Sizes given (no roles) match by size only: the same file without roles meets itself, not the other.
    plain = copy.deepcopy(a)
    for x in plain["results"]:
        x["size"].pop("role")
    json.dump(plain, open(os.path.join(tmp, "plain.json"), "w"))
    c = run("compare", os.path.join(tmp, "plain.json"), small)
    check(c.returncode == 0 and found_all(c.stdout, len(a["results"])), f"by size:\n{c.stdout}{c.stderr}")

    # The figures.
    figs = os.path.join(tmp, "figs")
    c = run("compare", small, big, "--plot", figs)
    check(c.returncode == 0, f"--plot: exit {c.returncode}\n{c.stderr}")
    pngs = sorted(os.listdir(figs)) if os.path.isdir(figs) else []
    expected = {f"compare-{k}-{p}-{t}.png" for k, p in {(x["name"], x.get("pattern")) for x in a["results"]}
                for t in ("t1", "all")}
    check(expected <= set(pngs), f"--plot wrote {pngs}, expected {sorted(expected)}")
    for name in pngs:
        if name.endswith(".png"):
            with open(os.path.join(figs, name), "rb") as f:
                check(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{name} is not a PNG")
            check(os.path.getsize(os.path.join(figs, name)) > 10_000, f"{name} is implausibly small")
    # Unstable points hollow, each machine's caches marked in its colour (the figures as built).
    sys.path.insert(0, os.path.join(src, "plots"))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import compare as compare_plot
    from results_model import Machine
    machines = []
    for path, doc in ((small, a), (big, b)):
        m = Machine(doc)
        m.add(doc, path)
        m.finish()
        m.name = os.path.basename(path)
        machines.append(m)
    shaky = {(x["name"], x.get("pattern")) for x in a["results"] + b["results"] if (x.get("stability") or {}).get("unstable")}
    hollow_seen = 0
    for name, fig in compare_plot.figures(plt, machines):
        ax = fig.axes[0]
        colours = {tuple(line.get_color()) for line in ax.get_lines() if line.get_label().startswith("[")}
        marks = [line for line in ax.get_lines() if list(line.get_xdata()) and len(set(line.get_xdata())) == 1
                 and line.get_linestyle() == ":"]
        check(len(colours) == 2, f"{name}: {len(colours)} series colours, expected one per file")
        check({tuple(m.get_color()) for m in marks} == colours, f"{name}: the cache markers are not in the files' colours")
        hollow_seen += sum(1 for line in ax.get_lines() if line.get_markerfacecolor() == "white")
        plt.close(fig)
    check(not shaky or hollow_seen, f"unstable points in {sorted(shaky)[:3]}... but none drawn hollow")

    # Claimed like any output: never over an input, never under a missing parent; nothing read first.
    one_line_error(run("compare", small, big, "--plot", small), "--plot over an input", "--plot")
    missing = os.path.join(tmp, "no", "such")
    one_line_error(run("compare", small, os.path.join(tmp, "absent.json"), "--plot", missing), "--plot under a missing parent", "--plot")
    check(not os.path.exists(os.path.join(tmp, "no")), "--plot created a directory under a missing parent")

    # 3. Bad input.
    odd = copy.deepcopy(plain)
    for x in odd["results"]:
        x["size"]["requested"] += 64
    json.dump(odd, open(os.path.join(tmp, "odd.json"), "w"))
    one_line_error(run("compare", os.path.join(tmp, "odd.json"), big), "no roles, no shared size", "record(s) no cache role")
    other = copy.deepcopy(a)
    other["schema_version"] = 99
    json.dump(other, open(os.path.join(tmp, "v99.json"), "w"))
    one_line_error(run("compare", small, os.path.join(tmp, "v99.json")), "another schema version", "v99.json")
    lacking = copy.deepcopy(b)
    lacking["results"] = [x for x in lacking["results"] if x["size"]["role"]["name"] != "DRAM"]
    json.dump(lacking, open(os.path.join(tmp, "no-dram.json"), "w"))
    one_line_error(run("compare", small, os.path.join(tmp, "no-dram.json")), "a role one file lacks", "has no DRAM point")
    c = run("compare", small, os.path.join(tmp, "no-dram.json"), "--force")
    check(c.returncode == 0 and "per cache role" in c.stdout, f"--force compares the roles they share:\n{c.stderr}")
    # What differs, said precisely: -march=native's ISA is the machine's; a chosen flag is the build's.
    native = copy.deepcopy(b)
    native["context"]["instruction_set"]["avx512f"] = not a["context"]["instruction_set"]["avx512f"]
    json.dump(native, open(os.path.join(tmp, "isa.json"), "w"))
    c = run("compare", small, os.path.join(tmp, "isa.json"))
    check(c.returncode == 0 and re.search(r"instruction_set\s+machine", c.stdout), f"-march=native's ISA:\n{c.stdout}{c.stderr}")
    flags = copy.deepcopy(b)
    flags["context"]["compiler_flags"] = flags["context"]["compiler_flags"].replace("-DNDEBUG", "").replace("-O3", "-O2")
    json.dump(flags, open(os.path.join(tmp, "o2.json"), "w"))
    r = run("compare", small, os.path.join(tmp, "o2.json"))
    one_line_error(r, "machines and chosen flags differ", "-O3 only in [1]")
    check("-O2 only in [2]" in r.stderr, f"the flag of [2] not named:\n{r.stderr}")

for f in failures:
    print("FAIL:", f)
print(f"examples_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
