#!/usr/bin/python3
"""The README and docs/ hold together: every relative link of README.md and docs/*.md names a file
that exists and, after '#', a heading of that file (GitHub's anchors); every docs page is linked from
the README; the README stays short enough to read on a screen or two (issue 17: ~200 lines).

usage: docs_test.py SOURCE_DIR        exit 0 clean, 1 with one line per problem
"""

import re
import sys
from pathlib import Path

README_MAX_LINES = 220
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")


def anchor(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path: Path) -> set:
    found, seen, in_code = set(), {}, False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("#"):
            continue
        a = anchor(line.lstrip("#"))
        n = seen.get(a, 0)
        seen[a] = n + 1
        found.add(a if n == 0 else f"{a}-{n}")
    return found


def links_of(path: Path):
    in_code = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        for target in LINK.findall(line):
            yield number, target


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = Path(sys.argv[1]).resolve()
    readme = root / "README.md"
    pages = sorted((root / "docs").glob("*.md"))
    problems = []
    lines = len(readme.read_text(encoding="utf-8").splitlines())
    if lines > README_MAX_LINES:
        problems.append(f"README.md: {lines} lines; keep it under {README_MAX_LINES} and move reference material to docs/")
    linked = set()
    for page in [readme] + pages:
        for number, target in links_of(page):
            if re.match(r"^[a-z]+:", target):  # http:, https:, mailto:
                continue
            file_part, _, frag = target.partition("#")
            dest = page if not file_part else (page.parent / file_part).resolve()
            rel = page.relative_to(root)
            if not dest.exists():
                problems.append(f"{rel}:{number}: link to {target}: no such file")
                continue
            if page == readme:
                linked.add(dest)
            if frag and dest.suffix == ".md" and frag not in anchors_of(dest):
                problems.append(f"{rel}:{number}: link to {target}: {dest.relative_to(root)} has no heading with anchor '{frag}'")
    for page in pages:
        if page.resolve() not in linked:
            problems.append(f"docs/{page.name}: not linked from README.md")
    if not pages:
        problems.append("docs/: no pages; the reference material lives there")
    for p in problems:
        print(p)
    print(f"docs_test: README {lines} lines, {len(pages)} docs pages, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
