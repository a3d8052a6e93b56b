"""The loop a stream kernel runs, read from the aarch64 binary's disassembly (`objdump -d -C`):
its instructions per iteration and the elements each iteration stores, so that check.py can hold
the PMU's instruction count to it. Elements are counted from the stores (every kernel of check 3
writes each element of `a` once): the bytes the loop's store instructions write, over 8.
"""

import re

FUNCTION = re.compile(r"^[0-9a-f]+ <(.*)>:$")
INSN = re.compile(r"^\s*([0-9a-f]+):\s+(\S+)\s*(.*)$")
TARGET = re.compile(r"\b([0-9a-f]+) <")
CONDITIONAL = ("cbz", "cbnz", "tbz", "tbnz")  # and b.<cond>
REG_BYTES = {"q": 16, "d": 8, "x": 8, "s": 4, "w": 4, "h": 2, "b": 1}


def functions(text):
    """{name: [(address, mnemonic, operands)]} for every function of the dump."""
    out, name = {}, None
    for line in text.splitlines():
        m = FUNCTION.match(line)
        if m:
            name = m.group(1)
            out[name] = []
            continue
        m = INSN.match(line)
        if m and name is not None:
            out[name].append((int(m.group(1), 16), m.group(2), m.group(3).split("//")[0].strip()))
    return out


def register_count(operands):
    """Registers in the braces of an st1 list: {v0.2d, v1.2d} or {v0.2d-v3.2d} or {z0.d}."""
    inside = operands[operands.index("{") + 1:operands.index("}")]
    if "-" in inside:
        lo, hi = (int(re.search(r"\d+", r).group()) for r in inside.split("-"))
        return hi - lo + 1
    return len(inside.split(","))


def store_bytes(mnemonic, operands, vector_bytes):
    """Bytes one instruction stores; 0 for anything that is not a store."""
    if mnemonic in ("st1d", "stnt1d", "st1w", "st1b", "st1h", "stnt1w"):  # SVE: a whole vector a register
        return vector_bytes * register_count(operands)
    if mnemonic == "st1" or mnemonic.startswith("st1 "):  # NEON structure store
        lane = re.search(r"\.(\d+)([bhsd])", operands)
        width = int(lane.group(1)) * {"b": 1, "h": 2, "s": 4, "d": 8}[lane.group(2)] if lane else 16
        return width * register_count(operands)
    if mnemonic in ("str", "stur", "stp", "stnp"):
        reg = operands.split(",")[0].strip()
        size = REG_BYTES.get(reg[:1], 0)
        if reg.startswith(("xzr", "wzr")):
            size = 8 if reg[0] == "x" else 4
        return size * (2 if mnemonic in ("stp", "stnp") else 1)
    return 0


def is_sve(operands):
    return re.search(r"\b[zp]\d+\b|\bz\d+\.", operands) is not None


def innermost_loops(insns):
    """(first, last) indices of each loop closed by a backward conditional branch and holding no
    other. (An unconditional branch backwards is code laid out after its successor, such as a
    jump to the shared return, not a loop.)"""
    index = {addr: i for i, (addr, _, _) in enumerate(insns)}
    loops = []
    for i, (addr, mnem, ops) in enumerate(insns):
        if not (mnem in CONDITIONAL or mnem.startswith("b.")):
            continue
        m = TARGET.search(ops)
        if not m:
            continue
        target = int(m.group(1), 16)
        if target <= addr and target in index and not any(m == "ret" for _, m, _ in insns[index[target]:i]):
            loops.append((index[target], i))
    return [(a, b) for a, b in loops if not any((a2, b2) != (a, b) and a <= a2 and b2 <= b for a2, b2 in loops)]


def loop_of(text, op, vector_bytes, sve):
    """The main loop of the sequential kernel made of `op` (Copy, Triad, Add) on a CPU with
    `vector_bytes`-wide SVE vectors (sve True) or NEON only: among the innermost loops of the
    functions named for it, the one storing the most per iteration; on an SVE CPU an SVE loop
    where the binary has one (the kernels choose it there), never one on a CPU without SVE.
    None when there is none."""
    found = {True: None, False: None}
    for name, insns in functions(text).items():
        if f"{op}>" not in name or "sequential" not in name:
            continue
        for a, b in innermost_loops(insns):
            body = insns[a:b + 1]
            uses_sve = any(is_sve(ops) for _, _, ops in body)
            if uses_sve and not sve:
                continue
            stored = sum(store_bytes(m, ops, vector_bytes) for _, m, ops in body)
            if stored == 0:
                continue
            loop = {"function": name, "address": f"{body[0][0]:x}", "instructions": len(body), "store_bytes": stored,
                    "elements": stored / 8, "body": [f"{m} {ops}" for _, m, ops in body]}
            if found[uses_sve] is None or stored > found[uses_sve]["store_bytes"]:
                found[uses_sve] = loop
    return found[True] or found[False]
