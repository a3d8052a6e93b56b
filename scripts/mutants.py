#!/usr/bin/env python3
"""`make test-mutants`: do the tests catch the bugs of tests/mutants/mutants.txt?

Each mutant is one sed expression on one file. The runner copies the tree (git's tracked files
and the untracked ones it does not ignore) to build-mutants/src, never touching the working tree,
configures and builds that copy once as `make build` does, and runs the tests the list names on
the unchanged copy (a test that fails there cannot kill anything and is left out). Then, one
mutant at a time: apply the sed expression, rebuild only what the tests need (suite, suite_tests
and what they depend on), run the mutant's CTest labels (`ctest -L`) and, for a mutant of
placement, the emulated two-node machine (scripts/numa-vm/run.sh of the copy), and put the file
back. A mutant is killed when a test fails, SURVIVED when none does; a sed expression that changes
nothing or more than one line, or a mutant that does not compile, is an ERROR of the list.
The file put back is rebuilt with the next mutant, and the whole copy once more at the end, so
every mutant is tested against the original of every other file.

usage: mutants.py [--only REGEX] [--list] [--keep] [--all-tests] [--no-baseline] [--jobs N]
  --only REGEX   the mutants whose name matches (re.search), e.g. --only 'gate|cg-'
  --list         print the list and check each sed expression against the working tree; build nothing
  --keep         keep the copy and its build (build-mutants/src): the next run starts from it
  --all-tests    run every selected test of a mutant (default: stop at the first that fails)
  --no-baseline  skip the run of the selected tests on the unchanged copy
Environment: JOBS (build and ctest jobs, default 2), ARCH and CMAKE_FLAGS as for `make build`.
Exit 0: every mutant killed; 1: a mutant survived or the list has an error; 2: usage or setup.
"""
import argparse
import difflib
import fcntl
import filecmp
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LIST = ROOT / "tests" / "mutants" / "mutants.txt"
WORK = ROOT / "build-mutants"
COPY = WORK / "src"
BUILD = COPY / "build"
LOGS = WORK / "logs"
NUMA = "numa-vm"  # the pseudo-label of the emulated two-node machine
WHOLE_BUILD = {"fuzz", "build"}  # labels whose tests need more than suite and suite_tests
JOBS = os.environ.get("JOBS", "2")


class Mutant:
    def __init__(self, line, name, path, labels, sed, bug):
        self.line, self.name, self.path, self.labels, self.sed, self.bug = line, name, path, labels, sed, bug

    def ctest_labels(self):
        return [label for label in self.labels if label != NUMA]


def read_list(path):
    """The mutants of the list and the errors of its lines."""
    mutants, errors, names = [], [], set()
    for number, raw in enumerate(path.read_text().splitlines(), 1):
        if not raw.strip() or raw.startswith("#"):
            continue
        where = f"{path.relative_to(ROOT)}:{number}"
        fields = raw.split("\t")
        if len(fields) != 5 or not all(f.strip() for f in fields):
            errors.append(f"{where}: {len(fields)} fields, not 5 non-empty ones separated by tabs (NAME PATH LABELS SED BUG)")
            continue
        name, rel, labels, sed, bug = (f.strip() for f in fields)
        label_list = [label.strip() for label in labels.split(",") if label.strip()]
        if name in names:
            errors.append(f"{where}: the name {name} is taken by an earlier line")
        elif not re.fullmatch(r"[A-Za-z0-9_.-]+", name) or not all(re.fullmatch(r"[A-Za-z0-9_-]+", x) for x in label_list):
            errors.append(f"{where}: a name or label with characters other than letters, digits, '_', '-'")
        else:
            names.add(name)
            mutants.append(Mutant(number, name, rel, label_list, sed, bug))
    return mutants, errors


def mutate(m, file):
    """The text of `file` with the mutant's sed expression applied, or the reason it is no mutant."""
    if not file.is_file():
        return None, f"{m.path} does not exist"
    done = subprocess.run(["sed", "-e", m.sed, str(file)], capture_output=True, text=True)
    if done.returncode != 0:
        return None, f"sed failed: {done.stderr.strip()}"
    before, after = file.read_text(), done.stdout
    if after == before:
        return None, "the sed expression changes nothing (the code it names has moved or changed?)"
    ops = difflib.SequenceMatcher(None, before.splitlines(), after.splitlines(), autojunk=False).get_opcodes()
    lines = sum(max(i2 - i1, j2 - j1) for tag, i1, i2, j1, j2 in ops if tag != "equal")
    if lines != 1:
        return None, f"the sed expression changes {lines} lines; a mutant is one place"
    return after, None


def tracked_files():
    out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                         capture_output=True, check=True).stdout.decode()
    return [rel for rel in out.split("\0") if rel and (ROOT / rel).is_file() and not rel.startswith("build-mutants/")]


def sync_copy():
    """Makes build-mutants/src hold the working tree's files. Only files whose content differs are
    written (with a new time), so a kept build stays valid and rebuilds what changed."""
    assert COPY.resolve().is_relative_to(WORK.resolve()) and WORK.resolve() != ROOT.resolve()
    manifest = WORK / "manifest.txt"
    before = set(manifest.read_text().splitlines()) if manifest.exists() and COPY.exists() else set()
    files = tracked_files()
    written = 0
    for rel in files:
        src, dst = ROOT / rel, COPY / rel
        if dst.is_file() and filecmp.cmp(src, dst, shallow=False):
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src, dst)
        shutil.copymode(src, dst)
        written += 1
    for rel in before - set(files):
        (COPY / rel).unlink(missing_ok=True)
    manifest.write_text("\n".join(files) + "\n")
    # The tests read the meshes beside the tree (SUITE_SOURCE_DIR/../shared/meshes): the copy's
    # neighbour is the same folder.
    shared = ROOT.parent / "shared"
    if shared.is_dir() and not (WORK / "shared").exists():
        (WORK / "shared").symlink_to(shared)
    return len(files), written


def run_logged(cmd, log, cwd=None, env=None):
    """Runs `cmd` with its output in `log`; its exit status."""
    with open(log, "w") as out:
        return subprocess.run(cmd, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT).returncode


def tail(log, n=25):
    lines = Path(log).read_text(errors="replace").splitlines()
    return "\n".join("    " + line for line in lines[-n:])


def configure():
    cmd = ["cmake", "-S", str(COPY), "-B", str(BUILD), "-DCMAKE_BUILD_TYPE=Release", f"-DSUITE_ARCH={os.environ.get('ARCH', 'native')}"]
    cmd += shlex.split(os.environ.get("CMAKE_FLAGS", ""))
    return run_logged(cmd, LOGS / "configure.log") == 0


def build(targets, log):
    """Builds `targets` of the copy (None: everything); True when it built."""
    cmd = ["nice", "-n", "10", "cmake", "--build", str(BUILD), "-j", JOBS]
    if targets:
        cmd += ["--target", *targets]
    return run_logged(cmd, log) == 0


def targets_for(labels):
    return None if WHOLE_BUILD & set(labels) else ["suite", "suite_tests"]


def ctest(labels, log, exclude, stop):
    """Runs the tests of `labels`: (the names of those that failed, an error or None)."""
    failed_list = BUILD / "Testing" / "Temporary" / "LastTestsFailed.log"
    failed_list.unlink(missing_ok=True)
    cmd = ["nice", "-n", "10", "ctest", "-L", "^(" + "|".join(labels) + ")$", "-j", JOBS, "--output-on-failure", "--no-tests=error"]
    if exclude:
        cmd += ["-E", "^(" + "|".join(re.escape(name) for name in sorted(exclude)) + ")$"]
    if stop:
        cmd.append("--stop-on-failure")
    status = run_logged(cmd, log, cwd=BUILD)
    failed = [line.split(":", 1)[1] for line in failed_list.read_text().splitlines() if ":" in line] if failed_list.exists() else []
    if status != 0 and not failed:
        return [], f"ctest exited {status} without a failed test (see {log.relative_to(ROOT)})"
    return failed, None


def numa_vm(log):
    """The emulated two-node machine on the copy: (failed, skipped-reason or None)."""
    env = dict(os.environ, JOBS=JOBS, NUMA_VM_DIR=str(WORK / "numa"))
    portable = BUILD / "suite-x86-64-v3"
    if portable.exists():
        env["SUITE_PORTABLE_BINARY"] = str(portable)
    cache, ours = ROOT / "build-numa" / "kernel", WORK / "numa" / "kernel"
    if not list(ours.glob("vmlinuz-*")) and list(cache.glob("vmlinuz-*")):  # `make test-numa`'s kernel, not fetched twice
        ours.mkdir(parents=True, exist_ok=True)
        for k in cache.glob("vmlinuz-*"):
            shutil.copyfile(k, ours / k.name)
    status = run_logged(["nice", "-n", "10", str(COPY / "scripts" / "numa-vm" / "run.sh")], log, cwd=COPY, env=env)
    text = log.read_text(errors="replace")
    skipped = re.search(r"test-numa: SKIPPED: (.*)", text)
    return status != 0, skipped.group(1) if skipped else None


def print_list(mutants):
    errors = 0
    for i, m in enumerate(mutants, 1):
        _, problem = mutate(m, ROOT / m.path)
        errors += problem is not None
        print(f"{i:3}. {m.name:<24} {m.path:<36} [{','.join(m.labels)}] {m.bug}" + (f"\n     ERROR: {problem}" if problem else ""))
    print(f"{len(mutants)} mutant(s), {errors} whose sed expression does not make a one-line change of the working tree")
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0], usage=__doc__.split("usage: ")[1].split("\n")[0])
    parser.add_argument("--only", metavar="REGEX")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--keep", action="store_true")
    parser.add_argument("--all-tests", action="store_true")
    parser.add_argument("--no-baseline", action="store_true")
    parser.add_argument("--jobs")
    args = parser.parse_args()
    global JOBS
    JOBS = args.jobs or JOBS
    mutants, list_errors = read_list(LIST)
    for e in list_errors:
        print(f"mutants: ERROR: {e}")
    if args.only:
        mutants = [m for m in mutants if re.search(args.only, m.name)]
        if not mutants:
            print(f"mutants: no mutant's name matches {args.only!r} (--list shows them)", file=sys.stderr)
            return 2
    if args.list:
        return 1 if print_list(mutants) or list_errors else 0

    WORK.mkdir(exist_ok=True)
    LOGS.mkdir(exist_ok=True)
    lock = open(WORK / "lock", "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        print("mutants: another run holds build-mutants/ (build-mutants/lock)", file=sys.stderr)
        return 2
    start = time.monotonic()
    files, written = sync_copy()
    if not configure():
        print(f"mutants: the configure of the copy failed:\n{tail(LOGS / 'configure.log')}", file=sys.stderr)
        return 2
    print(f"mutants: {files} files in build-mutants/src ({written} written); building the copy", flush=True)
    if not build(None, LOGS / "build.log"):
        print(f"mutants: the unchanged copy does not build:\n{tail(LOGS / 'build.log')}", file=sys.stderr)
        return 2
    print(f"mutants: copy built in {time.monotonic() - start:.0f} s", flush=True)

    labels = sorted({label for m in mutants for label in m.ctest_labels()})
    exclude, numa_ok = set(), True
    if not args.no_baseline:
        t0 = time.monotonic()
        failed, error = ctest(labels, LOGS / "baseline.log", set(), False) if labels else ([], None)
        if error:
            print(f"mutants: the unchanged copy: {error}", file=sys.stderr)
            return 2
        exclude = set(failed)
        for name in failed:
            print(f"mutants: WARNING: {name} fails without any mutant; it cannot kill one and is left out")
        if any(NUMA in m.labels for m in mutants):
            broke, skipped = numa_vm(LOGS / "baseline-numa-vm.log")
            numa_ok = not broke and not skipped
            if not numa_ok:
                print(f"mutants: WARNING: the emulated NUMA machine {'is skipped: ' + skipped if skipped else 'fails without any mutant'}; left out")
        print(f"mutants: the unchanged copy passes labels {','.join(labels)} in {time.monotonic() - t0:.0f} s", flush=True)

    results = []  # (mutant, verdict, detail, seconds)
    try:
        for i, m in enumerate(mutants, 1):
            t0 = time.monotonic()
            verdict, detail = run_mutant(m, exclude, numa_ok, not args.all_tests)
            seconds = time.monotonic() - t0
            results.append((m, verdict, detail, seconds))
            shown = {"killed": f"killed by {detail}", "SURVIVED": "SURVIVED" + (f" ({detail})" if detail else ""), "ERROR": f"ERROR: {detail}"}
            print(f"[{i}/{len(mutants)}] {m.name}: {shown[verdict]} ({seconds:.0f} s)", flush=True)
    finally:
        # The files are back; the build too, so that a kept copy is the working tree's.
        if args.keep:
            build(None, LOGS / "build.log")
        else:
            shutil.rmtree(COPY, ignore_errors=True)
            (WORK / "manifest.txt").unlink(missing_ok=True)
    return summary(results, list_errors, time.monotonic() - start)


def run_mutant(m, exclude, numa_ok, stop):
    """(verdict, detail): killed and the tests that failed, SURVIVED, or ERROR and why."""
    file = COPY / m.path
    text, problem = mutate(m, file)
    if problem:
        return "ERROR", problem
    original = file.read_bytes()
    log = LOGS / f"{m.name}.log"
    try:
        file.write_text(text)
        if not build(targets_for(m.labels), LOGS / f"{m.name}.build.log"):
            return "ERROR", f"does not compile (a mutant must be a plausible bug that builds; see build-mutants/logs/{m.name}.build.log)"
        killers = []
        if m.ctest_labels():
            failed, error = ctest(m.ctest_labels(), log, exclude, stop)
            if error:
                return "ERROR", error
            killers += failed
        note = ""
        if NUMA in m.labels and (not killers or not stop):
            if not numa_ok:
                note = "the emulated NUMA machine was left out"
            else:
                broke, skipped = numa_vm(LOGS / f"{m.name}.numa-vm.log")
                killers += ["numa-vm"] if broke else []
                note = f"numa-vm skipped: {skipped}" if skipped else ""
        return ("killed", ", ".join(killers)) if killers else ("SURVIVED", note)
    finally:
        file.write_bytes(original)  # a new time: the next build compiles the original again


def summary(results, list_errors, seconds):
    killed = [r for r in results if r[1] == "killed"]
    survived = [r for r in results if r[1] == "SURVIVED"]
    errors = [r for r in results if r[1] == "ERROR"]
    print(f"\nmutants: {len(results)} run in {seconds / 60:.1f} min: {len(killed)} killed, {len(survived)} survived, "
          f"{len(errors) + len(list_errors)} error(s) of the list")
    if survived:
        print("survivors (add a test that fails on them, or say in docs/development.md why the mutant is equivalent):")
        for m, _, detail, _ in survived:
            print(f"  {m.name} ({m.path}, labels {','.join(m.labels)}): {m.bug}" + (f" [{detail}]" if detail else ""))
    if errors or list_errors:
        print("errors of the list (tests/mutants/mutants.txt):")
        for e in list_errors:
            print(f"  {e}")
        for m, _, detail, _ in errors:
            print(f"  line {m.line}, {m.name}: {detail}")
    return 1 if survived or errors or list_errors else 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        print("\nmutants: interrupted; every mutated file is back as it was", file=sys.stderr)
        sys.exit(130)
