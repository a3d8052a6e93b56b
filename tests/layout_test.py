#!/usr/bin/env python3
"""The include rules of harness/README.md and app/README.md, checked on the source tree.

Every project #include of every C++ file under app/, harness/, stream/, kernels/ and rapl/ is
looked up in ALLOWED: a folder may include only the folders listed for it. Between the top-level
folders the graph must have no arrow back up: the engine (harness/) sees none of stream/,
kernels/, rapl/ or app/; the kernels and rapl see only the engine; app/ sees everything and
nothing includes it. Also: no source file sits directly in harness/ or app/ (each lives in the
folder of its concern or program), every top-level source folder and every harness and app folder
has its README, no source file is longer than 400 lines unless its first lines say why, and the
engine names no kernel: no string literal in harness/ code is the name of a kernel the kernels
register by a literal. And the mesh orderings are declared once: outside their tables
(ORDERING_TABLES), no string literal in code is an ordering's name, and none lists three of them;
likewise the names of --pin, --placement, --format and --energy outside their tables (OPTION_TABLES).

usage: layout_test.py SOURCE_DIR        exit 0 clean, 1 with one line per violation
"""
import re
import sys
from pathlib import Path

ORDER = ["common", "kernel", "machine", "instruments", "measure", "results"]
PROGRAMS = ["suite", "suite-mpi"]
ENGINE = {"harness/" + f for f in ORDER}
ALLOWED = {
    "harness/common": {"harness/common"},
    "harness/kernel": {"harness/common", "harness/kernel"},
    "harness/machine": {"harness/common", "harness/kernel", "harness/machine"},
    "harness/instruments": {"harness/common", "harness/instruments"},
    "harness/measure": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "harness/measure"},
    "harness/results": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "harness/measure", "harness/results"},
    # Energy implements the instruments' interface; the program wires it in.
    "rapl": {"harness/common", "harness/instruments", "rapl"},
    # Kernels see only their contract.
    "stream": {"harness/common", "harness/kernel", "stream"},
    "kernels": {"harness/common", "harness/kernel", "kernels"},
    # The programs see everything; suite-mpi also takes suite's options and frame.
    "app/suite": ENGINE | {"stream", "kernels", "rapl", "app/suite"},
    "app/suite-mpi": ENGINE | {"stream", "kernels", "rapl", "app/suite", "app/suite-mpi"},
}
# The top-level floors: an include may point to its own floor or one below, never above.
FLOOR = {"harness": 0, "stream": 1, "kernels": 1, "rapl": 1, "app": 2}
MAX_LINES = 400
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
LITERAL = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
# A record's metric is called "latency" as the latency kernel is: the results read and write it.
NOT_A_KERNEL = {("harness/results", "latency")}

# The mesh orderings' table, and `suite matrix`'s that extends it: the one place each name is written.
ORDERING_TABLES = ["kernels/sfc/orderings.cpp", "kernels/fem/ordering_study.cpp"]
# Literals that are an ordering's name but not the ordering: the access pattern "random" (its
# table, and the default sweep's), and the AMD library in the records' list of library versions.
NOT_AN_ORDERING = {
    ("harness/kernel/patterns.cpp", "random"),  # the access patterns' own table
    ("app/suite/defaults.cpp", "random"),
    ("kernels/fem/sparse_libs.cpp", "amd"),
}

# The tables of --pin, --placement, --format and --energy: the one place each of their names is
# written. Words other options and the records use for themselves too (--counters=none,
# --hugepages=none, compare's --format=table, "json" for a file's kind, ...) are not looked for.
OPTION_TABLES = ["harness/machine/team.cpp", "harness/machine/placement.cpp",
                 "harness/measure/output_formats.cpp", "harness/instruments/energy.cpp"]
SHARED_WORDS = {"none", "auto", "json", "table", "node"}


def option_names(root: Path) -> set:
    """The names the option tables declare, less the words shared with other uses."""
    names = set()
    for rel in OPTION_TABLES:
        names.update(re.findall(r'\{"([\w-]+)",\s*"', (root / rel).read_text()))
    return names - SHARED_WORDS


def ordering_names(root: Path) -> set:
    """The names the ordering tables declare: each entry starts {"name", "help" ..."""
    names = set()
    for rel in ORDERING_TABLES:
        names.update(re.findall(r'\{"([\w-]+)",\s*"', (root / rel).read_text()))
    return names


def ordering_literals(rel: str, code: str, names: set) -> list:
    """Why `code` (comments removed) of file `rel` names orderings by hand: one line a literal."""
    out = []
    alternation = "|".join(sorted((re.escape(n) for n in names), key=len, reverse=True))
    listed = re.compile(rf"(?<![\w-])({alternation})(?:, | \| |\|| or )({alternation})(?:, | \| |\|| or )({alternation})(?![\w-])")
    for literal in LITERAL.findall(code):
        if literal in names and (rel, literal) not in NOT_AN_ORDERING:
            out.append(f'{rel}: the ordering "{literal}" as a literal; read it from the table (kernels/sfc/orderings.hpp)')
        elif listed.search(literal):
            out.append(f'{rel}: lists orderings by hand ("{literal[:60]}"); take the list from the table (accepted(), listed())')
    return out


def kernel_names(root: Path) -> set:
    """The kernels' names a reader can find as literals: those the kernels register by one."""
    names = set()
    for path in list((root / "stream").rglob("*.cpp")) + list((root / "kernels").rglob("*.cpp")):
        names.update(re.findall(r'info\.name\s*=\s*"([\w-]+)"', path.read_text()))
        names.update(re.findall(r'constexpr const char\* name = "([\w-]+)"', path.read_text()))
    return names


def folder_of(rel: str) -> str:
    """The rule's key for a path relative to the source root: 'harness/measure', 'app/suite', 'kernels', ..."""
    parts = rel.split("/")
    if parts[0] in ("harness", "app"):
        return "/".join(parts[:2]) if len(parts) > 2 else parts[0]
    return parts[0]


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        return 2
    root = Path(sys.argv[1])
    problems = []
    checked = 0
    edges = set()  # (from, to) between top-level folders
    sources = [p for d in FLOOR for p in sorted((root / d).rglob("*")) if p.suffix in (".cpp", ".hpp")]
    names = kernel_names(root)
    orderings = ordering_names(root)
    if not {"natural", "hilbert", "amd"} <= orderings:
        problems.append(f"found only these ordering names to look for: {sorted(orderings)}; the test is looking in the wrong place")
    options = option_names(root)
    if not {"compact", "interleave", "gbench", "sysfs"} <= options:
        problems.append(f"found only these option names to look for: {sorted(options)}; the test is looking in the wrong place")
    if not {"copy", "latency", "peak-flops"} <= names:
        problems.append(f"found only these kernel names to look for: {sorted(names)}; the test is looking in the wrong place")
    for path in sources:
        rel = path.relative_to(root).as_posix()
        here = folder_of(rel)
        if here in ("harness", "app"):
            where = ", ".join(ORDER) if here == "harness" else ", ".join(PROGRAMS)
            problems.append(f"{rel}: a source file directly in {here}/; put it in the folder of its concern ({where})")
            continue
        allowed = ALLOWED.get(here)
        if allowed is None:
            problems.append(f"{rel}: folder {here} has no include rule in tests/layout_test.py (and its README)")
            continue
        text = path.read_text()
        if here != "stream" and rel not in ORDERING_TABLES:
            problems.extend(ordering_literals(rel, COMMENT.sub("", text), orderings))
        if rel not in OPTION_TABLES:
            for name in sorted(set(LITERAL.findall(COMMENT.sub("", text))) & options):
                problems.append(f'{rel}: the option value "{name}" as a literal; read it from its table ({", ".join(OPTION_TABLES)})')
        if here.startswith("harness/"):
            for name in sorted(set(LITERAL.findall(COMMENT.sub("", text))) & names):
                if (here, name) not in NOT_A_KERNEL:
                    problems.append(f'{rel}: names the kernel "{name}"; the engine takes kernels from the program (app/suite/defaults)')
        for target in INCLUDE.findall(text):
            if "/" not in target:
                continue  # a header beside the file, e.g. "process.hpp"
            there = folder_of(target)
            if there not in ALLOWED and there not in ("harness", "app"):
                continue  # not a project folder (generated files, system headers in quotes)
            checked += 1
            edges.add((rel.split("/")[0], target.split("/")[0]))
            if there not in allowed:
                problems.append(f"{rel}: includes {target}, but {here} may include only {', '.join(sorted(allowed))}")
        lines = text.count("\n")
        if lines > MAX_LINES and "lines" not in "\n".join(text.splitlines()[:6]):
            problems.append(f"{rel}: {lines} lines; split it, or say at its top why it is one idea")
    # The same rule seen from above: no arrow between top-level folders points to a higher floor.
    for a, b in sorted(edges):
        if FLOOR[b] > FLOOR[a]:
            problems.append(f"{a}/ includes {b}/, a floor above it: the include graph between top-level folders runs back up")
    for folder in ["harness/" + f for f in ORDER] + ["app/" + p for p in PROGRAMS] + ["app", "harness", "stream", "kernels", "rapl"]:
        if not (root / folder / "README.md").is_file():
            problems.append(f"{folder}/README.md is missing: each folder says what lives there and what it may include")
    for p in problems:
        print("layout: " + p)
    graph = ", ".join(f"{a}->{b}" for a, b in sorted(edges) if a != b)
    print(f"layout: top-level includes: {graph}")
    print(f"layout: {len(sources)} files, {checked} project includes checked, {len(problems)} violation(s)")
    if not checked:
        print("layout: no include was checked; the test is looking in the wrong place")
        return 1
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
