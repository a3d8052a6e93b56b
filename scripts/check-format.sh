#!/usr/bin/env bash
# The tree stays formatted as .clang-format says: every tracked C++ file, checked with the
# clang-format of the version the tree was formatted with (another version breaks lines
# differently, so it would flag code that is formatted). Exit 0 clean, 1 with the files that
# are not, 77 (CTest's skip) where that clang-format is missing.
#
# usage: scripts/check-format.sh [SOURCE_DIR]      fix with: clang-format -i FILE...
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
want=14
tool=""
for t in clang-format-$want clang-format; do
    if command -v "$t" > /dev/null && "$t" --version | grep -q "version $want\."; then tool=$t; break; fi
done
if [ -z "$tool" ]; then
    echo "skipped: clang-format $want is not installed (scripts/install-deps.sh test installs it)"
    exit 77
fi
if [ -d .git ] || git rev-parse --git-dir > /dev/null 2>&1; then
    mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
    mapfile -t files < <(find app harness kernels stream rapl tests gbench bench -name '*.cpp' -o -name '*.hpp' -o -name '*.h' | sort)
fi
bad=()
for f in "${files[@]}"; do
    "$tool" --dry-run --Werror "$f" > /dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
    echo "format: ${#bad[@]} of ${#files[@]} C++ file(s) differ from what $tool makes of them (clang-format -i FILE):"
    printf '  %s\n' "${bad[@]}"
    exit 1
fi
echo "format: ${#files[@]} C++ files formatted as .clang-format says"
