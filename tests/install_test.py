#!/usr/bin/env python3
"""The suite installed into a prefix (issue 36), used as a cluster user would use it.

  1. `cmake --install BUILD --prefix P` into a temporary prefix;
  2. from an unrelated directory, under strace, the installed programs run: --version, list, a
     small run and its figures (P/share/suite/plots/plot.py), suite traverse and suite mpm with
     their figures, suite history add and html; the outputs equal the build tree's, and not one
     file inside the source or build tree is opened, stat'ed or run;
  3. a broken install (a plot script, Chart.js missing): one line naming the file and where it
     was looked for, exit 2, nothing written, no Python traceback;
  4. the packaging: the Spack recipe is valid Python whose variants map onto CMake's options,
     and the container recipe installs its packages through scripts/install-deps.sh (one list).

usage: install_test.py CMAKE SOURCE_DIR BUILD_DIR PYTHON     exit 0 when every claim holds
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import types

cmake, source, build, python = sys.argv[1:5]
source, build = os.path.realpath(source), os.path.realpath(build)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def run(argv, cwd, traced=None):
    """Runs argv in cwd; with `traced`, under strace, its trace appended there."""
    if traced:
        argv = ["strace", "-f", "-qq", "-o", traced + ".part", "-e", "trace=%file,execve"] + argv
    r = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=600)
    if traced:
        with open(traced + ".part") as part, open(traced, "a") as whole:
            whole.write(part.read())
    return r


tmp = tempfile.mkdtemp(prefix="suite-install-")
try:
    prefix, work, ref = os.path.join(tmp, "prefix"), os.path.join(tmp, "work"), os.path.join(tmp, "ref")
    os.makedirs(work)
    os.makedirs(ref)
    r = subprocess.run([cmake, "--install", build, "--prefix", prefix], capture_output=True, text=True)
    check(r.returncode == 0, "cmake --install into a temporary prefix (%d: %s)" % (r.returncode, r.stderr.strip()[-300:]))
    suite = os.path.join(prefix, "bin", "suite")
    for f in ("bin/suite", "share/suite/plots/plot.py", "share/suite/plots/safe_output.py", "share/suite/schema/v1.json",
              "share/suite/schema/v2.json", "share/man/man1/suite.1", "share/doc/suite/README.md"):
        check(os.path.isfile(os.path.join(prefix, f)), "installed: " + f)
    built = os.path.join(build, "suite")
    has_strace = shutil.which("strace") is not None
    trace = os.path.join(tmp, "trace.txt") if has_strace else None
    if not has_strace:
        check(False, "strace is installed (scripts/install-deps.sh test installs it)")

    # --version and list: the same facts as the build tree's program, its data found installed.
    v = run([suite, "--version"], work, trace)
    vb = run([built, "--version"], ref)
    check(v.returncode == 0 and v.stdout.splitlines()[:3] == vb.stdout.splitlines()[:3],
          "suite --version: version, revision, compiler, flags and parts as the build tree's")
    check("(installed)" in v.stdout and prefix in v.stdout, "suite --version names the installed data directory: " + v.stdout.splitlines()[-1])
    listed, listed_ref = run([suite, "list"], work, trace), run([built, "list"], ref)
    check(listed.returncode == 0 and listed.stdout == listed_ref.stdout, "suite list: the same as the build tree's")

    # A small run, then its figures drawn by the installed plot script.
    small = ["--kernel=copy", "--size=64KiB", "--threads=1", "--reps=3", "--counters=none", "--energy=none", "--quiet", "--out=r.json"]
    r = run([suite] + small, work, trace)
    check(r.returncode == 0 and os.path.isfile(os.path.join(work, "r.json")), "a small run from the installed program (%s)" % r.stderr.strip()[-200:])
    r = run([python, os.path.join(prefix, "share/suite/plots/plot.py"), "r.json", "--out", "figs"], work, trace)
    pngs = [f for f in os.listdir(os.path.join(work, "figs"))] if os.path.isdir(os.path.join(work, "figs")) else []
    check(r.returncode == 0 and any(f.endswith(".png") for f in pngs), "its figures, by the installed plot.py (%s)" % r.stderr.strip()[-200:])

    # suite traverse and suite mpm with their figures; mpm's numbers equal the build tree's.
    r = run([suite, "traverse", "--mesh=disk:refine=1", "--ordering=natural", "--threads=1", "--out=tv"], work, trace)
    check(r.returncode == 0 and os.path.isfile(os.path.join(work, "tv", "natural-t1-100.png")), "suite traverse and its PNGs (%s)" % r.stderr.strip()[-200:])
    mpm = ["mpm", "--mesh=box:4,4,4", "--steps=10", "--vtk-every=5", "--quiet", "--out=dam"]
    r, rb = run([suite] + mpm, work, trace), run([built] + mpm, ref)
    check(r.returncode == 0 and os.path.isfile(os.path.join(work, "dam", "front.png")), "suite mpm and front.png (%s)" % r.stderr.strip()[-200:])
    def simulated(path):
        """front.csv without its last column, stepping_seconds: what was computed, not how long it took."""
        with open(path) as f:
            return [line.rstrip("\n").rsplit(",", 1)[0] for line in f]
    same = rb.returncode == 0 and simulated(os.path.join(work, "dam", "front.csv")) == simulated(os.path.join(ref, "dam", "front.csv"))
    check(same, "suite mpm: front.csv bit for bit the build tree's (all but the stepping_seconds column)")

    # The history and its page, with the installed Chart.js.
    r = run([suite, "history", "add", "r.json", "--db=h.sqlite"], work, trace)
    check(r.returncode == 0, "suite history add (%s)" % r.stderr.strip()[-200:])
    r = run([suite, "history", "html", "--db=h.sqlite", "--out=page"], work, trace)
    check(r.returncode == 0 and os.path.isfile(os.path.join(work, "page", "chart.min.js")), "suite history html with its Chart.js (%s)" % r.stderr.strip()[-200:])

    # Not one path inside the source or build tree was opened, stat'ed or run.
    if has_strace:
        touched = set()
        for line in open(trace):
            for path in re.findall(r'"(/[^"]*)"', line):
                real = os.path.normpath(path)
                if real == source or real.startswith(source + "/") or real == build or real.startswith(build + "/"):
                    touched.add(real)
        check(not touched, "the installed programs read nothing in the source or build tree (%s)" % sorted(touched)[:5])

    # A broken install: one line, exit 2, nothing written, no traceback.
    broken = os.path.join(tmp, "broken")
    shutil.copytree(prefix, broken, symlinks=True)
    os.remove(os.path.join(broken, "share/suite/plots/mpm_front.py"))
    os.remove(os.path.join(broken, "share/suite/chart.min.js")) if os.path.exists(os.path.join(broken, "share/suite/chart.min.js")) else None
    bsuite = os.path.join(broken, "bin", "suite")
    r = run([bsuite] + mpm[:-1] + ["--out=dam2"], work)
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 2 and len(lines) == 1 and "plots/mpm_front.py is missing from the installed tree" in lines[0]
          and "looked in" in lines[0] and "Traceback" not in r.stderr and not os.path.exists(os.path.join(work, "dam2")),
          "a plot script missing: suite mpm says which and where it looked, exit 2, nothing written (%d: %s)" % (r.returncode, lines))
    r = run([bsuite, "history", "html", "--db=h.sqlite", "--out=page2"], work)
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 2 and len(lines) == 1 and "chart.min.js" in lines[0] and not os.path.exists(os.path.join(work, "page2")),
          "Chart.js missing: suite history html says which file, exit 2, nothing written (%d: %s)" % (r.returncode, lines))
finally:
    shutil.rmtree(tmp, ignore_errors=True)

# The Spack recipe: valid Python against a stand-in for spack.package, its variants mapped onto
# options that CMakeLists.txt has.
calls = {"variant": [], "depends_on": [], "conflicts": [], "license": []}


class _Stub:
    def __init__(self, *a, **k):
        pass


def _record(kind):
    return lambda *a, **k: calls[kind].append((a, k))


stub = types.ModuleType("spack.package")
stub.CMakePackage = _Stub
stub.version = lambda *a, **k: None
for kind in calls:
    setattr(stub, kind, _record(kind))
stub.__all__ = ["CMakePackage", "version"] + list(calls)
sys.modules["spack"] = types.ModuleType("spack")
sys.modules["spack.package"] = stub
namespace = {}
recipe = os.path.join(source, "packaging", "spack", "package.py")
exec(compile(open(recipe).read(), recipe, "exec"), namespace)
variants = {a[0] for a, k in calls["variant"]}
licenses = [a[0] for a, k in calls["license"]]
license_text = open(os.path.join(source, "LICENSE")).read()
check(licenses == ["BSD-3-Clause"] and license_text.startswith("BSD 3-Clause License"),
      "the Spack recipe's license(...) names the LICENSE file's licence, BSD-3-Clause (%s)" % licenses)
check(variants == {"mpi", "metis", "suitesparse"}, "the Spack recipe has the variants mpi, metis, suitesparse (%s)" % sorted(variants))


class FakeSpec:
    def __init__(self, on):
        self.on = on

    def satisfies(self, text):
        return all((name in self.on) == (sign == "+") for sign, name in re.findall(r"([+~])(\w+)", text))

    def __contains__(self, text):
        return self.satisfies(text)


class FakePackage(namespace["Suite"]):
    def __init__(self, on):
        self.spec = FakeSpec(on)

    def define(self, name, value):
        return (name, value)

    def define_from_variant(self, name, variant):
        return (name, variant in self.spec.on)


options = set(re.findall(r"option\((SUITE_\w+)", open(os.path.join(source, "CMakeLists.txt")).read() +
                         open(os.path.join(source, "cmake", "valgrind_twin.cmake")).read()))
cache = {"SUITE_ARCH"}  # set() cache variables, not option()s
for on in ({"mpi", "metis", "suitesparse"}, set()):
    args = dict(FakePackage(on).cmake_args())
    check(set(args) <= options | cache, "the recipe's CMake arguments are the build's options (%s)" % sorted(set(args) - options - cache))
    check(args.get("SUITE_WITH_MPI") == ("mpi" in on) and args.get("SUITE_WITH_SPARSE") == ("metis" in on),
          "variants %s map onto SUITE_WITH_MPI and SUITE_WITH_SPARSE" % (sorted(on) or "none"))

# The container recipe: its packages come from scripts/install-deps.sh, not a list of its own.
containerfile = open(os.path.join(source, "packaging", "Containerfile")).read()
check("scripts/install-deps.sh" in containerfile and "apt-get install" not in containerfile and "FROM debian:12" in containerfile,
      "the Containerfile installs through scripts/install-deps.sh on Debian 12, with no package list of its own")
check("make install" in containerfile, "the Containerfile installs the suite with make install")

print("install: %d claim(s) failed" % len(failures) if failures else "install: every claim holds")
sys.exit(1 if failures else 0)
