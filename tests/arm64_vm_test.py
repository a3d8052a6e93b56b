#!/usr/bin/python3
"""The judge of make test-arm64 (scripts/arm64-vm/check.py and disassembly.py) on made-up guest
output, here on any host: the loop finder reads NEON and SVE loops right, and each counter claim
fails when what it guards is wrong (a multiplexed count 10 % off, an unavailable event given a
number, instructions per element that miss the loop, an event that does not say it was
multiplexed).

Usage: arm64_vm_test.py SOURCE_DIR
"""

import contextlib
import copy
import io
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(sys.argv[1] if len(sys.argv) > 1 else ".", "scripts", "arm64-vm"))
import check  # noqa: E402
import disassembly  # noqa: E402

FN = "suite::stream::StreamKernel<suite::stream::(anonymous namespace)::{op}>::sequential_loop(double*, double const*, double const*, long, int) [clone ._omp_fn.0]"

# The shape GCC 12 gives the sequential loop for NEON: an unrolled body of 32 elements (16 q
# stores here shortened to 4 stores of 16 B and the pointer steps: 8 elements), a scalar tail
# loop, the loop over calls around both, and a jump back to the shared return.
NEON = """
0000000000000000 <{fn}>:
  38:	mov	x2, x4
  40:	cmp	x7, #0x1f
  44:	b.le	1a0 <x>
  50:	ldr	q3, [x2]
  54:	add	x0, x0, #0x40
  58:	ldur	q1, [x0, #-64]
  5c:	fmla	v1.2d, v3.2d, v0.2d
  60:	stur	q1, [x1, #-64]
  64:	stp	q1, q2, [x1, #-48]
  68:	str	q1, [x1, #-16]
  6c:	add	x1, x1, #0x40
  70:	cmp	x0, x6
  74:	b.ne	50 <x>
  1a0:	ldr	d3, [x4, x0, lsl #3]
  1a4:	str	d1, [x5, x0, lsl #3]
  1a8:	add	x0, x0, #0x1
  1ac:	cmp	x0, x7
  1b0:	b.ne	1a0 <x>
  1b4:	add	w9, w9, #0x1
  1b8:	cmp	w13, w9
  1bc:	b.ne	38 <x>
  1c0:	ret
  1c4:	ldr	q3, [x4, x1]
  1c8:	str	q1, [x5, x1]
  1cc:	b	1c0 <x>
"""

SVE = """
0000000000000100 <{fn}>:
  178:	ld1d	{{z1.d}}, p0/z, [x4, x0, lsl #3]
  17c:	ld1d	{{z0.d}}, p0/z, [x3, x0, lsl #3]
  180:	fmad	z0.d, p1/m, z2.d, z1.d
  184:	st1d	{{z0.d}}, p0, [x1, x0, lsl #3]
  188:	incd	x0
  18c:	whilelo	p0.d, x0, x2
  190:	b.ne	178 <x>
  194:	ret
"""


def dump(op="Triad"):
    fn = FN.format(op=op)
    return NEON.format(fn=fn) + SVE.format(fn=fn.replace("sequential_loop", "sequential_loop_sve"))


failures = []


def expect(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def test_loops():
    neon = disassembly.loop_of(dump(), "Triad", 16, False)
    expect(neon is not None and neon["address"] == "50" and neon["instructions"] == 10 and neon["elements"] == 8,
           f"NEON: the unrolled loop, 10 instructions storing 8 elements (not the tail, the calls loop or the jump to ret): {neon}")
    sve = disassembly.loop_of(dump(), "Triad", 32, True)
    expect(sve is not None and sve["address"] == "178" and sve["instructions"] == 7 and sve["elements"] == 4,
           f"SVE at 256 bits: the predicated loop, 7 instructions storing 4 elements: {sve}")
    expect(disassembly.loop_of(dump(), "Copy", 16, False) is None, "no Copy function, no loop")
    for m, ops, vb, want in (("st1", "{v0.2d-v3.2d}, [x0]", 16, 64), ("st1", "{v0.2d, v1.2d}, [x0]", 16, 32),
                             ("stnp", "q0, q1, [x0]", 16, 32), ("stp", "d0, d1, [x0]", 16, 16), ("str", "x1, [x0]", 16, 8),
                             ("stnt1d", "{z0.d}, p0, [x0]", 64, 64), ("ldr", "q0, [x0]", 16, 0)):
        expect(disassembly.store_bytes(m, ops, vb) == want, f"{m} {ops}: {want} B stored")


def record(name_values, units=4096, size=98304):
    events = [{"name": n, "canonical": n, "kind": "hardware", "available": v is not None, "reason": None if v is not None else "absent",
               "per_call": None if v is None else {"median": v, "min": v, "max": v}, "per_element": None if v is None else v / units,
               "per_byte": None, "multiplexed": mux, "running_fraction": frac}
              for n, v, mux, frac in name_values]
    return {"size": {"units": units, "footprint_bytes": size}, "threads": 1, "verification": {"passed": True},
            "repetitions": {"batch": 1, "counted": 5},
            "counters": {"available": True, "events": events}}


def sections(items):
    return {k: (json.dumps(v) if not isinstance(v, str) else v) for k, v in items.items()}


def claims(fn, *args):
    c = check.numa.Checker()
    with contextlib.redirect_stdout(io.StringIO()):  # the claims' own lines; the results are returned
        fn(c, *args)
    return c.results


def test_ipe():
    dis = dump()
    # 10 instructions per 8 elements = 1.25; 4096 and 32768 elements, 300 instructions per call besides.
    good = {"ipe-triad/status": "0", "ipe-triad/json": {"results": [
        record([("INST_RETIRED:u", 1.25 * n + 300, False, 1.0), ("INST_RETIRED", 1.252 * n + 900, False, 1.0)], units=n)
        for n in (4096, 32768)]}}
    for k in ("copy", "add"):
        good[f"ipe-{k}/status"] = "1"
    report = []
    res = [r for r in claims(check.check_ipe, "n1", sections(good), dis, 16, report) if "triad" in r[1]]
    expect(res and all(r[0] for r in res), f"triad at exactly the loop's 1.25 per element holds: {res}")
    expect(any("INST_RETIRED:u" in line and "+0.000%" in line and "besides the loop 300" in line for line in report) and
           any("INST_RETIRED:" in line and "+0.160%" in line for line in report), f"the report states both errors and the overhead: {report}")
    bad = copy.deepcopy(good)
    bad["ipe-triad/json"]["results"][1]["counters"]["events"][1]["per_call"]["median"] = 1.3 * 32768 + 900
    res = [r for r in claims(check.check_ipe, "n1", sections(bad), dis, 16, []) if "triad" in r[1]]
    expect([r[2].split(":")[0] for r in res if not r[0]] == ["INST_RETIRED"], "instructions per element 4 % above the loop fail")
    batched = copy.deepcopy(good)
    batched["ipe-triad/json"]["results"][0]["repetitions"]["batch"] = 2
    res = [r for r in claims(check.check_ipe, "n1", sections(batched), dis, 16, []) if "triad" in r[1]]
    expect(any(not r[0] and "one call a repetition" in r[2] for r in res), "a size timed two calls a repetition fails")


def test_mux():
    names = ["instructions", "INST_RETIRED", "arm_n1::INST_RETIRED", "PERF_COUNT_HW_INSTRUCTIONS", "INST_RETIRED:u",
             "cycles", "CPU_CYCLES", "arm_n1::CPU_CYCLES", "PERF_COUNT_HW_CPU_CYCLES", "CPU_CYCLES:u"]
    alone_a = {"results": [record([(n, 4.0e7, False, 1.0) for n in names[:5]])]}
    alone_b = {"results": [record([(n, 4.0e7, False, 1.0) for n in names[5:]])]}
    mux = {"results": [record([(n, 4.0e7 * 1.001, True, 0.5) for n in names])]}
    mux["results"][0]["repetitions"] = {"counted": 5}
    for e in mux["results"][0]["counters"]["events"]:
        e.update(repetitions_counted=4, repetitions_not_counted=1)
    data = {"mux-10/json": mux, "mux-5a/json": alone_a, "mux-5b/json": alone_b}
    res = claims(check.check_mux, sections(data), [])
    expect(res and all(r[0] for r in res), f"ten multiplexed events within 0.1 % hold: {[r for r in res if not r[0]]}")
    off = copy.deepcopy(data)
    off["mux-10/json"]["results"][0]["counters"]["events"][3]["per_call"]["median"] = 4.4e7
    expect(any(not r[0] and "within 5%" in r[2] for r in claims(check.check_mux, sections(off), [])), "a scaled count 10 % off fails")
    silent = copy.deepcopy(data)
    silent["mux-10/json"]["results"][0]["counters"]["events"][0].update(multiplexed=False, running_fraction=1.0)
    expect(any(not r[0] and "says it was multiplexed" in r[2] for r in claims(check.check_mux, sections(silent), [])),
           "an event that does not say it was multiplexed fails")
    lost = copy.deepcopy(data)
    lost["mux-10/json"]["results"][0]["counters"]["events"][2].update(repetitions_counted=4, repetitions_not_counted=0)
    expect(any(not r[0] and "how many of the 5 repetitions" in r[2] for r in claims(check.check_mux, sections(lost), [])),
           "repetition counts that do not add up to the repetitions fail")


def test_absent():
    pmu = "armv8_pmuv3 cpu_cycles event=0x0011\narmv8_pmuv3 inst_retired event=0x0008\n"
    r = record([("INST_RETIRED", 5000.0, False, 1.0), ("L1D_CACHE_REFILL", None, False, None), ("L1-dcache-load-misses", None, False, None)])
    r["counters"]["events"][1]["reason"] = "the CPU's PMU (armv8_pmuv3) does not implement event 0x03: ..."
    r["counters"]["events"][2]["reason"] = "no hardware PMU offers this event (perf_event_open: No such file or directory)"
    data = {"guest/pmu": pmu, "absent/json": {"results": [r]}}
    res = claims(check.check_absent, sections(data))
    expect(res and all(x[0] for x in res), f"unavailable with the reason holds: {[x for x in res if not x[0]]}")
    zero = copy.deepcopy(data)
    zero["absent/json"]["results"][0]["counters"]["events"][1].update(available=True, reason=None, per_call={"median": 0, "min": 0, "max": 0})
    expect(any(not x[0] for x in claims(check.check_absent, sections(zero))), "an unimplemented event reported as 0 fails")


def test_quiet():
    ok = record([("cpu-migrations", 0.0, False, 1.0), ("page-faults", 0.0, False, 1.0)])
    moved = copy.deepcopy(ok)
    moved["counters"]["events"][0]["per_call"]["max"] = 1.0
    res = claims(check.check_quiet, sections({"quiet1/json": {"results": [ok]}, "quiet2/json": {"results": [moved]}}))
    expect([x[0] for x in res] == [True, True, False, True], f"a migration in one repetition fails, the rest hold: {res}")


def test_console_sections():
    with tempfile.NamedTemporaryFile("w", suffix=".log", delete=False) as f:
        f.write("[    0.1] boot\r\narm64-vm guest: init\r\n@@begin guest/verdict@@\r\n0\r\n\r\n@@end guest/verdict@@\r\n")
    try:
        expect(check.numa.sections(f.name).get("guest/verdict", "").strip() == "0", "sections read from a console log with CR LF")
    finally:
        os.unlink(f.name)


for t in (test_loops, test_ipe, test_mux, test_absent, test_quiet, test_console_sections):
    t()
print(f"arm64_vm_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
