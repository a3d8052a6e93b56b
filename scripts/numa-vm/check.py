#!/usr/bin/python3
"""Judges what the emulated NUMA machine (init.sh) sent back: the suite's topology and, for each
placement scenario, the result file's pinning and page histograms against where the running
suite's pages really were (numa_maps and pagemap snapshots taken by the guest).

Usage: check.py DATA.txt    (the guest's second serial port, written by run.sh)
Prints one line per claim, "ok" or "FAIL" with the numbers, then a summary line.
Exit status: 0 every claim holds, 1 at least one does not (or the data is missing).
"""

import json
import os
import re
import sys

# What each scenario of init.sh asks for, and what must then be true. `threads`: (cpu, node) of
# each thread in order. `layout`: "split" (thread k's block of every array on thread k's node),
# ("node", N) (every page on N), "interleave" (pages alternate over nodes 0 and 1).
SCENARIOS = {
    "local2": dict(thp="never", threads=[(0, 0), (1, 1)], placement="local", layout="split", policy="default"),
    "node1": dict(thp="never", threads=[(0, 0)], placement="node:1", node=1, layout=("node", 1), policy="bind:1"),
    "remote": dict(thp="never", threads=[(0, 0)], placement="remote", node=1, layout=("node", 1), policy="bind:1"),
    "interleave": dict(thp="never", threads=[(0, 0)], placement="interleave", layout="interleave", policy="interleave:0-1"),
    "pin1": dict(thp="never", threads=[(1, 1)], placement="local", layout=("node", 1), policy="default"),
    "thp-local2": dict(thp="always", threads=[(0, 0), (1, 1)], placement="local", layout="split", policy="default"),
    "thp-interleave": dict(thp="always", threads=[(0, 0)], placement="interleave", layout="interleave", policy="interleave:0-1"),
}
DISTANCES = [[10, 21], [21, 10]]  # as run.sh configures QEMU
MAX_OTHER = 64  # pages of other data the kernel may merge into the arrays' mappings


class Checker:
    def __init__(self):
        self.results = []

    def claim(self, scenario, text, ok, detail=""):
        self.results.append((bool(ok), scenario, text, detail))
        print(f"  {'ok  ' if ok else 'FAIL'}  {scenario:<15} {text}" + (f": {detail}" if detail else ""))
        return bool(ok)


def sections(path):
    out, name, lines = {}, None, []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.rstrip("\r\n")
            m = re.fullmatch(r"@@(begin|end) (.+)@@", line)
            if m and m.group(1) == "begin":
                name, lines = m.group(2), []
            elif m and name == m.group(2):
                out[name] = "\n".join(lines)
                name = None
            elif name is not None:
                lines.append(line)
    return out


class Machine:
    """The guest kernel's view: CPUs, distances and memory blocks of each node."""

    def __init__(self, text):
        self.cpus, self.distance, self.block_node, self.facts = {}, {}, {}, {}
        for line in text.splitlines():
            m = re.match(r"node(\d+) cpus=(\S*) distance=(\S*) blocks=(.*)", line)
            if m:
                node = int(m.group(1))
                self.cpus[node] = m.group(2)
                self.distance[node] = [int(d) for d in m.group(3).split(",") if d]
                for block in m.group(4).split():
                    self.block_node[int(block.removeprefix("memory"))] = node
            elif "=" in line:
                key, value = line.split("=", 1)
                self.facts[key] = value
        self.block_size = int(self.facts.get("block_size_bytes", "0"), 16)
        self.huge_pages = int(self.facts.get("hpage_pmd_size", "2097152")) // 4096

    def node_of_frame(self, pfn):
        return self.block_node.get(pfn * 4096 // self.block_size, -1) if self.block_size else -1


def pagemap_nodes(text, machine):
    """Node of every present page of the snapshot's large anonymous mappings, in address order;
    how many were not present; and the mappings whose dump is short."""
    nodes, absent, short, expected, seen, lo = [], 0, [], 0, 0, None

    def close():
        if lo is not None and seen != expected:
            short.append(f"{lo}: {seen} of {expected} pages")

    for line in text.splitlines():
        if line.startswith("vma "):
            close()
            _, lo, hi = line.split()
            expected, seen = (int(hi, 16) - int(lo, 16)) // 4096, 0
            continue
        for word in line.split():
            entry = int(word, 16)
            seen += 1
            if entry >> 63:
                nodes.append(machine.node_of_frame(entry & ((1 << 55) - 1)))
            else:
                absent += 1
    close()
    return nodes, absent, short


def runs(seq):
    out = []
    for x in seq:
        if out and out[-1][0] == x:
            out[-1][1] += 1
        else:
            out.append([x, 1])
    return out


def numa_maps_lines(numa_maps, pagemap):
    """The numa_maps lines of the mappings whose pages were dumped (the arrays)."""
    starts = {int(line.split()[1], 16) for line in pagemap.splitlines() if line.startswith("vma ")}
    return [line.split() for line in numa_maps.splitlines() if line.split() and int(line.split()[0], 16) in starts]


def load_json(c, scenario, data, key):
    """The JSON document sent as `key`, or None after a failed claim saying why."""
    try:
        return json.loads(data[key])
    except (KeyError, ValueError) as e:
        c.claim(scenario, f"{key} received and valid JSON", False, "missing" if isinstance(e, KeyError) else str(e))
        return None


def check_topology(c, data, machine):
    c.claim("kernel", "guest kernel sees 2 NUMA nodes with distance 21", sorted(machine.distance) == [0, 1] and
            [machine.distance[0], machine.distance[1]] == DISTANCES, f"{machine.distance}")
    c.claim("kernel", "automatic NUMA balancing is off, so pages stay where first placed",
            machine.facts.get("numa_balancing") == "0", machine.facts.get("numa_balancing", "missing"))
    info = load_json(c, "info", data, "info/json")
    if info is None:
        return
    nodes = info.get("numa_nodes", [])
    c.claim("info", "2 NUMA nodes, node 0 with CPU 0 and node 1 with CPU 1",
            [(n["os_index"], n["cpus"]) for n in nodes] == [(0, [0]), (1, [1])], f"{[(n['os_index'], n['cpus']) for n in nodes]}")
    c.claim("info", "distances 10/21 as configured and as the kernel reports", info.get("numa_distances") == DISTANCES,
            f"{info.get('numa_distances')}")
    c.claim("info", "CPU 0 on node 0, CPU 1 on node 1",
            sorted((p["os_index"], p["numa_node"]) for p in info.get("pu_map", [])) == [(0, 0), (1, 1)],
            f"(cpu, node) {sorted((p['os_index'], p['numa_node']) for p in info.get('pu_map', []))}")


def schema_validator():
    """The validator of the result schema of this tree (results/schema/v2.json)."""
    import jsonschema
    from jsonschema.validators import validator_for
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "results", "schema", "v2.json")
    with open(path, encoding="utf-8") as f:
        schema = json.load(f)
    return validator_for(schema, default=jsonschema.Draft202012Validator)(schema)


def check_record(c, name, want, record, doc, slack):
    c.claim(name, "one record, verified, document complete", record.get("verification", {}).get("passed") is True and
            doc.get("complete") is True)
    thp = doc["context"].get("transparent_hugepages", {}).get("value")
    c.claim(name, f"context: transparent huge pages '{want['thp']}', 2 NUMA nodes",
            thp == want["thp"] and doc["context"].get("numa_node_count") == 2, f"thp {thp}, nodes {doc['context'].get('numa_node_count')}")
    got = [(t["cpu"], t["numa_node"], t["allowed_cpus"]) for t in record["pin"]["threads"]]
    c.claim(name, "each thread on its CPU and node: " + ", ".join(f"thread {k} cpu {cpu} node {n}" for k, (cpu, n) in enumerate(want["threads"])),
            got == [(cpu, n, [cpu]) for cpu, n in want["threads"]], f"observed (cpu, node, allowed) {got}")
    c.claim(name, "pinning held during the run", record["pin"]["held_during_run"] is True, f"{record['pin']['held_during_run']}")
    p = record["placement"]
    c.claim(name, f"placement '{want['placement']}' recorded" + (f" on node {want['node']}" if "node" in want else ""),
            p["requested"] == want["placement"] and p["node"] == want.get("node") and
            p["interleave_nodes"] == ([0, 1] if want["layout"] == "interleave" else []), f"{p['requested']} node {p['node']} {p['interleave_nodes']}")
    for a in p["arrays"]:
        hist = {int(k): v for k, v in a["pages_per_node"].items()}
        n0, n1 = hist.get(0, 0), hist.get(1, 0)
        whole = a["pages_not_present"] == 0 and "error" not in a and sum(hist.values()) == a["pages"]
        text = f"histogram of '{a['array']}': all {a['pages']} pages, "
        if want["layout"] == "split":
            c.claim(name, text + f"half on each thread's node (within {slack['split']})",
                    whole and abs(n0 - a["pages"] / 2) <= slack["split"], f"node 0: {n0}, node 1: {n1}")
        elif want["layout"] == "interleave":
            c.claim(name, text + f"as many on each node (within {slack['interleave']})",
                    whole and abs(n0 - n1) <= slack["interleave"], f"node 0: {n0}, node 1: {n1}")
        else:
            c.claim(name, text + f"every one on node {want['layout'][1]}", whole and hist == {want["layout"][1]: a["pages"]}, f"{hist}")


def check_snapshot(c, name, want, record, data, machine, slack):
    """The running process's pages, as the kernel shows them, against the layout and the histogram."""
    missing = [f for f in ("maps", "numa_maps", "pagemap", "thp", "tasks") if f"{name}/{f}" not in data]
    if not c.claim(name, "snapshot of the running suite received", not missing, f"missing {missing}" if missing else ""):
        return
    # The kernel's word on pinning, independent of what the suite read back: one task per thread,
    # each allowed exactly its CPU and last seen running there.
    tasks = sorted((w[1], int(w[2])) for w in (line.split() for line in data[f"{name}/tasks"].splitlines()) if len(w) == 3)
    c.claim(name, "kernel: the process's threads are allowed only, and run on, CPUs " + ",".join(str(cpu) for cpu, _ in want["threads"]),
            tasks == sorted((str(cpu), cpu) for cpu, _ in want["threads"]), f"(allowed, last cpu) {tasks}")
    arrays = record["placement"]["arrays"]
    total = sum(a["pages"] for a in arrays)
    nodes, absent, short = pagemap_nodes(data[f"{name}/pagemap"], machine)
    if not c.claim(name, "pagemap read whole for every mapping of the arrays' size", nodes and not short,
                   f"{short}" if short else ("" if nodes else "nothing read")):
        return
    extra = len(nodes) - total
    if not c.claim(name, f"pagemap: all {total} array pages resident, every frame on a known node",
                   extra >= 0 and -1 not in nodes, f"{len(nodes)} resident, {absent} not, {nodes.count(-1)} unknown frames"):
        return
    count = {k: nodes.count(k) for k in (0, 1)}
    hist = {k: sum(int(a["pages_per_node"].get(str(k), 0)) for a in arrays) for k in (0, 1)}
    c.claim(name, "pagemap agrees with the suite's histogram", all(abs(count[k] - hist[k]) <= extra + slack["drift"] for k in (0, 1)),
            f"pagemap {count}, histogram {hist}, {extra} other pages")
    lines = numa_maps_lines(data[f"{name}/numa_maps"], data[f"{name}/pagemap"])
    policies = sorted({line[1] for line in lines})
    per_node = {k: sum(int(w[len(f"N{k}="):]) for line in lines for w in line if w.startswith(f"N{k}=")) for k in (0, 1)}
    c.claim(name, f"numa_maps: the arrays' mappings have policy {want['policy']}", policies == [want["policy"]], f"{policies}")
    c.claim(name, "numa_maps: N0=/N1= agree with pagemap", all(abs(per_node[k] - count[k]) <= slack["drift"] for k in (0, 1)),
            f"numa_maps {per_node}, pagemap {count}")
    thp = re.search(r"(\d+)", data[f"{name}/thp"])
    thp_kb = int(thp.group(1)) if thp else -1
    c.claim(name, "huge pages in use" if want["thp"] == "always" else "no huge pages in use",
            thp_kb > 0 if want["thp"] == "always" else thp_kb == 0, f"AnonHugePages {thp_kb} kB")
    # The arrays are consecutive mappings, so their pages are one stretch of `total` resident
    # pages; the kernel may have merged a few other pages (touched by the main thread before it
    # was pinned) into the same mapping at either end. Every placement of that stretch that
    # leaves at most MAX_OTHER pages outside is tried; the claim holds if one fits.
    if not c.claim(name, f"the arrays' mappings hold at most {MAX_OTHER} other pages", extra <= MAX_OTHER, f"{extra} other pages"):
        return
    layout = want["layout"]
    if layout == "split":
        # In address order every array is [thread 0's block][thread 1's block]: runs 0,1,0,1,...
        half = arrays[0]["pages"] / 2

        def fits(r):
            return [x[0] for x in r] == [0, 1] * len(arrays) and all(abs(length - half) <= slack["split"] for _, length in r)
        text = f"pagemap: in every array thread 0's block on node 0, then thread 1's on node 1 (runs of {half:.0f} pages within {slack['split']})"
    elif layout == "interleave":
        def fits(r):
            return max(length for _, length in r) <= slack["run"] and abs(
                sum(n for x, n in r if x == 0) - sum(n for x, n in r if x == 1)) <= slack["interleave"] * len(arrays)
        text = f"pagemap: pages alternate between the nodes (no run longer than {slack['run']} pages, as many on each)"
    else:
        def fits(r):
            return [x[0] for x in r] == [layout[1]]
        text = f"pagemap: every array page on node {layout[1]}"
    tried = [runs(nodes[o:o + total]) for o in range(extra + 1)]
    good = [r for r in tried if fits(r)]
    r = (good or tried)[0]
    c.claim(name, text, good, f"{len(r)} runs (node, pages) {[tuple(x) for x in r[:8]]}{' ...' if len(r) > 8 else ''}")


def main(argv):
    if len(argv) != 2:
        print("usage: check.py DATA.txt", file=sys.stderr)
        return 2
    try:
        data = sections(argv[1])
    except OSError as e:
        print(f"check.py: cannot read {argv[1]}: {e}", file=sys.stderr)
        return 1
    c = Checker()
    validator = schema_validator()
    machine = Machine(data.get("guest/nodes", ""))
    check_topology(c, data, machine)
    for name, want in SCENARIOS.items():
        h = machine.huge_pages if want["thp"] == "always" else 1
        # How far from the ideal a page count may be: one page at a block boundary with base pages;
        # with 2 MiB pages a huge page straddling a block boundary or an array's edge goes whole to
        # one node, so a thread's block may gain or lose up to one huge page at each of its ends.
        slack = dict(split=1 if h == 1 else 2 * h, interleave=1 if h == 1 else h + 2, run=1 if h == 1 else h + 2, drift=0 if h == 1 else h)
        status = data.get(f"{name}/status", "missing").strip()
        if not c.claim(name, "suite exited 0", status == "0",
                       "" if status == "0" else f"status {status}; stderr: {data.get(f'{name}/stderr', '').strip()[:300]}"):
            continue
        doc = load_json(c, name, data, f"{name}/result.json")
        if doc is None or not c.claim(name, "result file holds one record", len(doc.get("results", [])) == 1, f"{len(doc.get('results', []))} records"):
            continue
        errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(doc)]
        c.claim(name, "result file valid against results/schema/v2.json", not errors, "; ".join(errors[:3]))
        check_record(c, name, want, doc["results"][0], doc, slack)
        check_snapshot(c, name, want, doc["results"][0], data, machine, slack)
    c.claim("guest", "guest verdict: every run finished", data.get("guest/verdict", "").strip() == "0", data.get("guest/verdict", "missing").strip())
    failed = [r for r in c.results if not r[0]]
    if failed:
        print(f"test-numa: FAIL: {len(failed)} of {len(c.results)} claims do not hold:")
        for _, scenario, text, detail in failed:
            print(f"  {scenario}: {text}: {detail}")
        return 1
    print(f"test-numa: all {len(c.results)} claims hold (placement, pinning and topology on 2 emulated NUMA nodes)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
