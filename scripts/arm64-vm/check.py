#!/usr/bin/python3
"""Judges what the emulated aarch64 machines (init.sh) sent back: the kernels verify on each CPU,
and the counters hold to answers known exactly under QEMU's -icount (issue 48's checks 1 to 6).

Usage: check.py --disassembly SUITE.dis TAG=CONSOLE.log [TAG=CONSOLE.log ...]
TAG is the machine (n1, sve256, sve128, sve512); SUITE.dis is `objdump -d -C` of the guest's suite.
Prints one line per claim, "ok" or "FAIL" with the numbers, then the measured errors of checks 3
and 4 and a summary line. Exit status: 0 every claim holds, 1 at least one does not.
"""

import argparse
import importlib.util
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from disassembly import loop_of  # noqa: E402


def _numa_judge():
    """test-numa's judge (its sections, machine and placement claims), under a name of its own."""
    spec = importlib.util.spec_from_file_location("numa_check", os.path.join(HERE, "..", "numa-vm", "check.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


numa = _numa_judge()

# Placement scenarios of init.sh (base pages only), judged by test-numa's claims.
SCENARIOS = {k: v for k, v in numa.SCENARIOS.items() if v["thp"] == "never"}
IPE_KERNELS = {"copy": "Copy", "triad": "Triad", "add": "Add"}  # --kernel name: the Op the loop is made of
IPE_TOLERANCE = 0.01  # check 3: measured instructions per element against the loop's
MUX_TOLERANCE = 0.05  # check 4: a multiplexed event's scaled count against the same event alone


def load(c, where, data, key):
    """The JSON document sent as `key`, or None after a failed claim saying why."""
    return numa.load_json(c, where, data, key)


def event(record, name):
    for e in record.get("counters", {}).get("events", []):
        if e["name"] == name:
            return e
    return None


def check_registry(c, tag, data):
    """1. The unit tests' registry walk, every kernel, pattern, variant and choice, in this guest."""
    where = f"{tag}/kernels"
    if not c.claim(where, "the unit tests' registry walk ran (build-arm64/tests/suite_tests packed)",
                   "registry/json" in data, "no result: suite_tests missing from the build?"):
        return
    doc = load(c, where, data, "registry/json")
    kernels = load(c, where, data, "guest/kernels")
    if doc is None or kernels is None:
        return
    tests = [(s["name"], t["name"], t.get("failures", [])) for s in doc.get("testsuites", []) for t in s.get("testsuite", [])]
    failed = [f"{s}.{t}: {f[0].get('failure', '')[:160]}" for s, t, f in tests if f]
    c.claim(where, f"every one of {len(tests)} registry tests passes on this CPU", tests and not failed,
            "; ".join(failed[:4]) + (f" (+{len(failed) - 4} more)" if len(failed) > 4 else ""))
    labels = [t for s, t, _ in tests if s.endswith("/Registry")]
    wanted = [k["name"] for k in kernels if k["group"] in ("stream", "latency") or k["name"] == "peak-flops"]
    missing = [k for k in wanted
               if not any(label.split("/", 1)[-1].startswith(re.sub(r"[^A-Za-z0-9]", "_", k) + "_") for label in labels)]
    c.claim(where, f"the walk covers every stream kernel of ./suite list and peak-flops ({len(wanted)})",
            wanted and not missing, f"not run: {missing}")
    c.claim(where, "suite_tests exited 0", data.get("registry/status", "").strip() == "0",
            data.get("registry/tail", "")[-400:])


def check_ipe(c, tag, data, disassembly, vector_bytes, report):
    """3. Instructions per element from the instruction count at two sizes against the compiled
    loop: the user-mode count (the loop's own) and the count with kernel mode (timer interrupts)."""
    generic = "INST_RETIRED" if tag == "n1" else "instructions"
    for kernel, op in IPE_KERNELS.items():
        where = f"{tag}/ipe-{kernel}"
        status = data.get(f"ipe-{kernel}/status", "missing").strip()
        if not c.claim(where, "suite exited 0", status == "0", f"status {status}: {data.get(f'ipe-{kernel}/stderr', '')[:300]}"):
            continue
        doc = load(c, where, data, f"ipe-{kernel}/json")
        if doc is None:
            continue
        loop = loop_of(disassembly, op, vector_bytes, tag != "n1")
        if not c.claim(where, f"the {op} loop found in the disassembly", loop is not None and loop["elements"] > 0,
                       f"at {loop['address']} in {loop['function']}" if loop else
                       "no sequential_loop of this kernel with a store in its innermost loop"):
            continue
        want = loop["instructions"] / loop["elements"]
        for name in (generic + ":u", generic):
            points = []
            for r in doc["results"]:
                e = event(r, name)
                if not c.claim(where, f"{name} counted at {r['size']['footprint_bytes']} B", e is not None and e.get("available"),
                               (e or {}).get("reason", "absent")):
                    break
                points.append((r["size"]["units"], e["per_call"]["median"], e["multiplexed"], r["verification"]["passed"],
                               r["repetitions"]["batch"]))
            # One call a repetition at both sizes: what a repetition costs besides its calls then
            # weighs the same per call at both, and drops out of the slope.
            if not c.claim(where, f"{name}: two sizes, verified, not multiplexed, one call a repetition", len(points) == 2 and
                           all(p[3] and not p[2] and p[4] == 1 for p in points), f"(elements, count, multiplexed, verified, batch) {points}"):
                continue
            (n1, i1, *_), (n2, i2, *_) = sorted(points)
            slope = (i2 - i1) / (n2 - n1)
            overhead = i1 - slope * n1
            err = slope / want - 1
            report.append(f"{tag} {kernel} {name}: {slope:.4f} instructions per element ({int(n1)} and {int(n2)} elements), "
                          f"loop {loop['instructions']} instructions per {loop['elements']:g} elements = {want:.4f}: "
                          f"error {err:+.3%}; per call besides the loop {overhead:.0f}; per element with it "
                          f"{i1 / n1:.4f} and {i2 / n2:.4f}")
            c.claim(where, f"{name}: instructions per element = the loop's {want:.4f} within {IPE_TOLERANCE:.0%}",
                    abs(err) <= IPE_TOLERANCE, f"measured {slope:.4f} ({err:+.3%}); loop at {loop['address']}: "
                    f"{loop['instructions']} instructions, {loop['store_bytes']} B stored per iteration; {overhead:.0f} per call besides")


def check_mux(c, data, report, run="mux", label="long repetitions"):
    """4. Ten events on seven counters: each says so, and its scaled count is held to its count alone."""
    where = f"n1/{run}"
    docs = {k: load(c, where, data, f"{run}-{k}/json") for k in ("10", "5a", "5b")}
    if any(d is None for d in docs.values()):
        return
    alone = {}
    for k in ("5a", "5b"):
        for e in docs[k]["results"][0]["counters"]["events"]:
            alone[e["name"]] = e
    reps = docs["10"]["results"][0]["repetitions"]["counted"]
    events = docs["10"]["results"][0]["counters"]["events"]
    c.claim(where, "ten events asked, ten recorded", len(events) == 10, f"{[e['name'] for e in events]}")
    for e in events:
        ref = alone.get(e["name"])
        ok = e.get("available") and ref and ref.get("available")
        if not c.claim(where, f"{e['name']}: counted multiplexed and alone", ok,
                       f"{e.get('reason')} / {(ref or {}).get('reason')}"):
            continue
        c.claim(where, f"{e['name']}: alone (five events) not multiplexed", not ref["multiplexed"] and ref["running_fraction"] == 1,
                f"running fraction {ref['running_fraction']}")
        frac = e.get("running_fraction")
        c.claim(where, f"{e['name']}: says it was multiplexed, with its running fraction", e["multiplexed"] and frac is not None and 0 < frac < 1,
                f"multiplexed {e['multiplexed']}, running fraction {frac}")
        counted, missed = e.get("repetitions_counted"), e.get("repetitions_not_counted")
        c.claim(where, f"{e['name']}: says in how many of the {reps} repetitions it was counted",
                isinstance(counted, int) and isinstance(missed, int) and counted >= 1 and counted + missed == reps,
                f"counted {counted}, not counted {missed}")
        err = e["per_call"]["median"] / ref["per_call"]["median"] - 1
        report.append(f"n1 multiplexed, {label}: {e['name']}: running fraction {frac:.3f}, {e['per_call']['median']:.0f} "
                      f"per call scaled against {ref['per_call']['median']:.0f} alone: error {err:+.3%} "
                      f"({counted} of {reps} repetitions counted)")
        c.claim(where, f"{e['name']}: scaled count within {MUX_TOLERANCE:.0%} of the count alone", abs(err) <= MUX_TOLERANCE,
                f"{err:+.3%} (running fraction {frac:.3f})")


def check_absent(c, data):
    """5. An event this PMU does not implement: unavailable with the reason, never a number."""
    where = "n1/absent"
    doc = load(c, where, data, "absent/json")
    if doc is None:
        return
    r = doc["results"][0]
    pmu_events = {line.split()[1] for line in data.get("guest/pmu", "").splitlines() if len(line.split()) > 1}
    c.claim(where, "the PMU's sysfs lists inst_retired and cpu_cycles but not l1d_cache_refill",
            {"inst_retired", "cpu_cycles"} <= pmu_events and "l1d_cache_refill" not in pmu_events, f"{sorted(pmu_events)}")
    for name, says in (("L1D_CACHE_REFILL", "does not implement event 0x03"), ("L1-dcache-load-misses", "perf_event_open")):
        e = event(r, name)
        c.claim(where, f"{name}: unavailable, per_call null, with the reason", e is not None and e["available"] is False and
                e["per_call"] is None and says in (e.get("reason") or ""), f"{e}")
    e = event(r, "INST_RETIRED")
    c.claim(where, "INST_RETIRED beside them counted", e is not None and e["available"] and e["per_call"]["median"] > 0, f"{e}")


def check_quiet(c, data):
    """6. No migration under pinning, no page fault inside the timing."""
    for k in ("quiet1", "quiet2"):
        where = f"n1/{k}"
        doc = load(c, where, data, f"{k}/json")
        if doc is None:
            continue
        r = doc["results"][0]
        for name in ("cpu-migrations", "page-faults"):
            e = event(r, name)
            c.claim(where, f"{name} = 0 in every counted repetition ({r['threads']} thread(s) pinned)",
                    e is not None and e["available"] and e["per_call"]["max"] == 0, f"{e}")


def check_placement(c, data, validator):
    """2. test-numa's claims on the two emulated nodes, on the result files (the page-frame
    snapshot stays test-numa's: see init.sh)."""
    machine = numa.Machine(data.get("guest/nodes", ""))
    numa.check_topology(c, data, machine)
    slack = dict(split=1, interleave=1, run=1, drift=0)
    for name, want in SCENARIOS.items():
        status = data.get(f"{name}/status", "missing").strip()
        if not c.claim(name, "suite exited 0", status == "0", f"status {status}; stderr: {data.get(f'{name}/stderr', '')[:300]}"):
            continue
        doc = load(c, name, data, f"{name}/result.json")
        if doc is None or not c.claim(name, "result file holds one record", len(doc.get("results", [])) == 1):
            continue
        errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(doc)]
        c.claim(name, "result file valid against results/schema/v2.json", not errors, "; ".join(errors[:3]))
        numa.check_record(c, name, want, doc["results"][0], doc, slack)


def check_machine(c, tag, data, validator):
    """What the guest is, and that every result file it sent is valid."""
    cpu = dict(line.split(":", 1) if ":" in line else line.split("=", 1) for line in data.get("guest/cpu", "").splitlines() if line)
    cpu = {k.strip(): v.strip() for k, v in cpu.items()}
    vl = cpu.get("sve_default_vector_length", "none")
    if tag == "n1":
        c.claim(tag, "Neoverse N1 (implementer 0x41, part 0xd0c), no SVE", cpu.get("CPU implementer") == "0x41" and
                cpu.get("CPU part") == "0xd0c" and " sve" not in cpu.get("Features", ""), f"{cpu}")
        vector_bytes = 16
    else:
        bits = int(tag.removeprefix("sve"))
        c.claim(tag, f"SVE with {bits}-bit vectors", " sve" in " " + cpu.get("Features", "") and vl == str(bits // 8), f"{cpu}")
        vector_bytes = bits // 8
    for key, text in data.items():
        if key.endswith("/json") and key not in ("registry/json", "info/json") and text.strip():
            try:
                doc = json.loads(text)
            except ValueError as e:
                c.claim(tag, f"{key} is JSON", False, str(e))
                continue
            errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(doc)]
            c.claim(tag, f"{key} valid against results/schema/v2.json", not errors, "; ".join(errors[:3]))
    return vector_bytes


def main(argv):
    ap = argparse.ArgumentParser(description="judges the emulated aarch64 machines of make test-arm64")
    ap.add_argument("--disassembly", required=True)
    ap.add_argument("machines", nargs="+", help="TAG=CONSOLE.log")
    a = ap.parse_args(argv[1:])
    try:
        with open(a.disassembly, encoding="utf-8", errors="replace") as f:
            disassembly = f.read()
    except OSError as e:
        print(f"check.py: cannot read {a.disassembly}: {e}", file=sys.stderr)
        return 1
    c = numa.Checker()
    validator = numa.schema_validator()
    report = []
    for spec in a.machines:
        tag, _, path = spec.partition("=")
        try:
            data = numa.sections(path)
        except OSError as e:
            print(f"check.py: cannot read {path}: {e}", file=sys.stderr)
            return 1
        vector_bytes = check_machine(c, tag, data, validator)
        check_registry(c, tag, data)
        check_ipe(c, tag, data, disassembly, vector_bytes, report)
        if tag == "n1":
            check_mux(c, data, report)
            check_mux(c, data, report, "muxs", "repetitions shorter than the rotation")
            check_absent(c, data)
            check_quiet(c, data)
            check_placement(c, data, validator)
        c.claim(tag, "guest verdict: every run finished", data.get("guest/verdict", "").strip() == "0",
                data.get("guest/verdict", "missing").strip())
    print("test-arm64: measured (checks 3 and 4):")
    for line in report:
        print(f"  {line}")
    failed = [r for r in c.results if not r[0]]
    if failed:
        print(f"test-arm64: FAIL: {len(failed)} of {len(c.results)} claims do not hold:")
        for _, where, text, detail in failed:
            print(f"  {where}: {text}: {detail}")
        return 1
    print(f"test-arm64: all {len(c.results)} claims hold (kernels, placement and counters on the emulated Arm PMU)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
