#!/usr/bin/env python3
"""The include rules of harness/README.md, checked on the source tree.

Every project #include of every C++ file under harness/, stream/, kernels/ and rapl/ is looked up
in ALLOWED: a folder may include only the folders listed for it. Also: no source file sits
directly in harness/ (each lives in the folder of its concern), every harness folder has its
README, and no source file is longer than 400 lines unless its first lines say why.

usage: layout_test.py SOURCE_DIR        exit 0 clean, 1 with one line per violation
"""
import re
import sys
from pathlib import Path

ORDER = ["common", "kernel", "machine", "instruments", "rapl", "measure", "results", "cli", "mpi"]
ALLOWED = {
    "harness/common": {"harness/common"},
    "harness/kernel": {"harness/common", "harness/kernel"},
    "harness/machine": {"harness/common", "harness/kernel", "harness/machine"},
    "harness/instruments": {"harness/common", "harness/instruments"},
    "rapl": {"harness/common", "harness/instruments", "rapl"},
    "harness/measure": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "rapl", "harness/measure"},
    "harness/results": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "rapl", "harness/measure",
                        "harness/results"},
    "harness/cli": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "rapl", "harness/measure",
                    "harness/results", "harness/cli", "kernels", "stream"},
    # suite-mpi's own folder: the only one that includes mpi.h, and nothing includes it.
    "harness/mpi": {"harness/common", "harness/kernel", "harness/machine", "harness/instruments", "rapl", "harness/measure",
                    "harness/results", "harness/cli", "harness/mpi"},
    # Kernels see only their contract.
    "stream": {"harness/common", "harness/kernel", "stream"},
    "kernels": {"harness/common", "harness/kernel", "kernels"},
}
MAX_LINES = 400
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def folder_of(rel: str) -> str:
    """The rule's key for a path relative to the source root: 'harness/measure', 'kernels', ..."""
    parts = rel.split("/")
    if parts[0] == "harness":
        return "/".join(parts[:2]) if len(parts) > 2 else "harness"
    return parts[0]


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        return 2
    root = Path(sys.argv[1])
    problems = []
    checked = 0
    sources = [p for d in ("harness", "stream", "kernels", "rapl") for p in sorted((root / d).rglob("*")) if p.suffix in (".cpp", ".hpp")]
    for path in sources:
        rel = path.relative_to(root).as_posix()
        here = folder_of(rel)
        if here == "harness":
            problems.append(f"{rel}: a source file directly in harness/; put it in the folder of its concern ({', '.join(ORDER)})")
            continue
        allowed = ALLOWED.get(here)
        if allowed is None:
            problems.append(f"{rel}: folder {here} has no include rule in tests/layout_test.py (and harness/README.md)")
            continue
        text = path.read_text()
        for target in INCLUDE.findall(text):
            if "/" not in target:
                continue  # a header beside the file, e.g. "process.hpp"
            there = folder_of(target)
            if there not in ALLOWED and there != "harness":
                continue  # not a project folder (generated files, system headers in quotes)
            checked += 1
            if there not in allowed:
                problems.append(f"{rel}: includes {target}, but {here} may include only {', '.join(sorted(allowed))}")
        lines = text.count("\n")
        if lines > MAX_LINES and "lines" not in "\n".join(text.splitlines()[:6]):
            problems.append(f"{rel}: {lines} lines; split it, or say at its top why it is one idea")
    for folder in ORDER:
        if folder != "rapl" and not (root / "harness" / folder / "README.md").is_file():
            problems.append(f"harness/{folder}/README.md is missing: each folder says what lives there and what it may include")
    for p in problems:
        print("layout: " + p)
    print(f"layout: {len(sources)} files, {checked} project includes checked, {len(problems)} violation(s)")
    if not checked:
        print("layout: no include was checked; the test is looking in the wrong place")
        return 1
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
