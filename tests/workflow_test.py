#!/usr/bin/python3
"""The GitHub Actions workflow (.github/workflows/*.yml) is valid YAML with jobs and steps, and
every command it runs exists as written: each `./suite SUBCOMMAND --option` is accepted by that
subcommand's --help, each script it names is in the tree, and each `make` target is in the
Makefile. A workflow that runs nowhere here must at least not break on a renamed option.

Usage: tests/workflow_test.py SOURCE_DIR SUITE_BINARY
"""
import glob
import os
import re
import shlex
import subprocess
import sys

import yaml

top, suite = sys.argv[1], sys.argv[2]
failures = []
workflows = sorted(glob.glob(os.path.join(top, ".github", "workflows", "*.yml")))
if not workflows:
    failures.append("no workflow under .github/workflows/")
makefile = open(os.path.join(top, "Makefile")).read()
help_cache = {}


def suite_help(sub):
    if sub not in help_cache:
        argv = [suite] + ([sub] if sub else []) + ["--help"]
        r = subprocess.run(argv, capture_output=True, text=True, timeout=60)
        help_cache[sub] = (r.returncode, r.stdout + r.stderr)
    return help_cache[sub]


def check_line(where, line):
    line = line.strip()
    if not line or line.startswith("#"):
        return
    for part in re.split(r"&&|\|\||;|\|", line):
        words = shlex.split(part, comments=True)
        # "[ -f x ] && ./suite ..." and "for f in ...; do": look at the command words only.
        while words and words[0] in ("do", "then", "else", "!"):
            words = words[1:]
        if not words:
            continue
        cmd = words[0]
        if cmd == "./suite":
            args = words[1:]
            sub = args[0] if args and not args[0].startswith("-") else ""
            rest = args[1:] if sub else args
            if sub == "history" and rest and not rest[0].startswith("-"):
                sub, rest = "history " + rest[0], rest[1:]
            code, text = suite_help(sub) if " " not in sub else _nested_help(sub)
            if code != 0:
                failures.append(f"{where}: ./suite {sub} --help exits {code}")
                continue
            for a in rest:
                if a.startswith("--"):
                    opt = a.split("=", 1)[0]
                    if opt not in text:
                        failures.append(f"{where}: ./suite {sub} has no option {opt} (not in its --help)")
        elif cmd.startswith("scripts/"):
            if not os.access(os.path.join(top, cmd), os.X_OK):
                failures.append(f"{where}: {cmd} is not an executable file of the tree")
        elif cmd == "make":
            for target in words[1:]:
                if not target.startswith("-") and "=" not in target and not re.search(rf"^{re.escape(target)}:", makefile, re.M):
                    failures.append(f"{where}: make target {target} is not in the Makefile")


def _nested_help(sub):
    if sub not in help_cache:
        r = subprocess.run([suite] + sub.split() + ["--help"], capture_output=True, text=True, timeout=60)
        help_cache[sub] = (r.returncode, r.stdout + r.stderr)
    return help_cache[sub]


for path in workflows:
    name = os.path.relpath(path, top)
    doc = yaml.safe_load(open(path))
    if not isinstance(doc, dict) or "jobs" not in doc or not (doc.get("on") or doc.get(True)):
        failures.append(f"{name}: expected a mapping with 'on' and 'jobs'")
        continue
    for job, spec in doc["jobs"].items():
        steps = spec.get("steps") or []
        if not steps:
            failures.append(f"{name}: job {job} has no steps")
        for i, step in enumerate(steps):
            if "run" in step:
                for n, line in enumerate(step["run"].splitlines()):
                    check_line(f"{name} job {job} step {i + 1} ({step.get('name', '')}) line {n + 1}", line)

for f in failures:
    print("FAIL:", f)
print(f"{len(workflows)} workflow(s), {len(help_cache)} suite command(s) checked: {'failed' if failures else 'ok'}")
sys.exit(1 if failures else 0)
