#!/usr/bin/env python3
"""The aarch64 build's kernels are the instructions their names say, read from its disassembly
(the aarch64 counterpart of tests/cli/e2e_test.cpp's objdump tests, run by `make test-arm64`):

- the nt loops of copy, scale, add, triad and store stream with STNP (NEON) and their SVE twins
  with STNT1D; the plain loops use ordinary stores, and their SVE twins are SVE code;
- load's loop keeps its eight accumulators in q registers (fadd v.2d), nothing vector stored;
- peak-flops' loops are 12 independent FMAs of their width on registers, nothing else but the
  loop counter: fmadd d (scalar), fmla v.2d (neon), fmla/fmad z.d (sve).

Usage: disasm_test.py BUILD-ARM64/suite [OBJDUMP]. Exit 0: passed; 1: a check failed."""
import re
import subprocess
import sys

binary = sys.argv[1]
objdump = sys.argv[2] if len(sys.argv) > 2 else "aarch64-linux-gnu-objdump"
text = subprocess.run([objdump, "-d", "-C", "--no-show-raw-insn", binary], check=True, capture_output=True,
                      text=True).stdout

functions = {}
name = None
for line in text.splitlines():
    m = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
    if m:
        name = m.group(1)
        functions[name] = []
    elif name is not None and line.strip():
        functions[name].append(line)

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def bodies(fragment):
    """Every function (and OpenMP body) whose demangled name holds `fragment`, as one text."""
    return "\n".join("\n".join(b) for n, b in functions.items() if fragment in n)


ns = "suite::stream::(anonymous namespace)::"
for op in ("Copy", "Scale", "Add", "Triad"):
    kernel = f"StreamKernel<{ns}{op}>::"
    nt, nt_sve = bodies(kernel + "nt_store_loop("), bodies(kernel + "nt_store_loop_sve(")
    plain, plain_sve = bodies(kernel + "sequential_loop("), bodies(kernel + "sequential_loop_sve(")
    check(re.search(r"\bstnp\s+q\d+, q\d+", nt) is not None, f"{op}: nt_store_loop streams with stnp q, q")
    check("stnt1d" in nt_sve, f"{op}: nt_store_loop_sve streams with stnt1d")
    check(plain != "" and "stnp" not in plain and "stnt1" not in plain,
          f"{op}: the plain loop (found: {plain != ''}) uses ordinary stores")
    check(re.search(r"\bst1d\s", plain_sve) is not None and "stnt1" not in plain_sve,
          f"{op}: the plain loop's SVE twin stores with st1d")
store = f"{ns}Store::"
check(re.search(r"\bstnp\s+q\d+, q\d+", bodies(store + "nt_store_loop(")) is not None, "store: nt loop streams with stnp")
check("stnt1d" in bodies(store + "nt_store_loop_sve("), "store: nt loop's SVE twin streams with stnt1d")
check("stnp" not in bodies(store + "sequential_loop("), "store: the plain loop uses ordinary stores")

# The OpenMP body, where the loop is (the function around it passes its arguments on the stack).
load = "\n".join("\n".join(b) for n, b in functions.items() if f"{ns}Load::sequential_loop(" in n and "_omp_fn" in n)
accumulators = set(re.findall(r"\bfadd\s+(v\d+)\.2d, \1\.2d", load))
spills = re.findall(r"^.*\bst(?:r|p|1)\w*\s+q\d+.*$", load, re.M)
check(len(accumulators) >= 8, f"load: adds into 8 vector accumulators (found {len(accumulators)})")
check(load != "" and not spills, "load: no vector stored in the loop (64-byte GCC vectors on NEON spilled every add)"
      + ("" if not spills else f": {spills[0].strip()}"))


def loop_of(body):
    """The innermost loop: from the target of the last backward branch to that branch."""
    branch = re.compile(r"^\s*([0-9a-f]+):\s+(b\.\w+|cbnz|cbz|tbnz|tbz|b)\s+(?:\w+, )*([0-9a-f]+) <")
    last = None
    for i, line in enumerate(body):
        m = branch.match(line)
        if m and int(m.group(3), 16) < int(m.group(1), 16):
            last = (i, m.group(3))
    if last is None:
        return []
    end, target = last
    start = next((i for i in range(end) if re.match(rf"^\s*{target}:", body[i])), None)
    return body[start:end + 1] if start is not None else []


widths = {"Scalar": (r"\bfmadd\s+d\d+", "peak_loop<" + ns + "Scalar>"),
          "Neon": (r"\bfmla\s+v\d+\.2d", "peak_loop<" + ns + "Neon>"),
          "Sve": (r"\bfm(la|ad)\s+z\d+\.d", ns + "peak_loop_sve(")}
for isa, (fma, fragment) in widths.items():
    body = [line for n, b in functions.items() if fragment in n for line in b]
    loop = loop_of(body)
    if not loop:
        check(False, f"peak-flops {isa}: no loop found in {fragment}")
        continue
    fmas = [line for line in loop if re.search(fma, line)]
    memory = [line for line in loop if re.search(r"\b(ldr|str|ldp|stp|ld1|st1)\w*\s", line)]
    destinations = {re.search(r"(?:fmadd|fmla|fmad)\s+([dvz]\d+)", line).group(1) for line in fmas}
    check(len(fmas) == 12, f"peak-flops {isa}: 12 FMAs in the loop (found {len(fmas)})")
    check(len(destinations) == 12, f"peak-flops {isa}: into 12 registers (found {len(destinations)})")
    check(not memory, f"peak-flops {isa}: no load or store in the loop" + ("" if not memory else f": {memory[0]}"))
    check(len(loop) - len(fmas) <= 4, f"peak-flops {isa}: nothing but the loop counter besides ({len(loop) - len(fmas)})")

print(f"disasm_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
