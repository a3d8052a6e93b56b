"""What suite's result files say, for plots/plot.py: reading and checking them, the machines and
runs they come from, and each record's figures (bandwidth, latency, footprint, caches). No drawing
here; plot.py draws. Exit status 2 (via fail) for a file that cannot be used.
"""

import json
import os
import re
import sys


KNOWN_SCHEMA_VERSIONS = {1, 2}  # 2: a named parameter is its name; 1: its index (shown as the number)


def fail(message):
    print(f"plot.py: error: {message}", file=sys.stderr)
    sys.exit(2)


def load(path):
    try:
        with open(path, "rb") as f:
            doc = json.loads(f.read().decode("utf-8"))
    except FileNotFoundError:
        fail(f"{path}: no such file")
    except (OSError, UnicodeDecodeError) as e:
        fail(f"{path}: cannot read it: {e}")
    except json.JSONDecodeError as e:
        fail(f"{path}: not valid JSON (truncated or not a result file?): {e}")
    if not isinstance(doc, dict) or "results" not in doc or "context" not in doc:
        fail(f"{path}: not a suite result file (suite writes an object with schema_version, context and results)")
    version = doc.get("schema_version")
    if version not in KNOWN_SCHEMA_VERSIONS:
        fail(f"{path}: schema_version {version!r} is not one this script knows ({sorted(KNOWN_SCHEMA_VERSIONS)}); "
             "use the plots/ of the suite version that wrote it")
    if not isinstance(doc["results"], list) or not isinstance(doc["context"], dict):
        fail(f"{path}: 'results' must be a list and 'context' an object")
    return doc


def squash(text):
    """Runs of whitespace as one space, none at the ends (hwloc pads CPU model names)."""
    return " ".join(str(text).split())


def machine_key(doc):
    c = doc["context"]
    return (squash(c.get("host") or "?"), squash(c.get("cpu_model") or "") or "unknown CPU",
            squash(c.get("compiler_flags") or ""), squash(c.get("compiler") or ""))


def march(flags):
    m = re.search(r"-march=(\S+)", flags)
    return m.group(1) if m else "default -march"


def short_date(date, seconds=False):
    """'2026-11-24T07:32:47Z' as '2026-11-24 07:32' (or with seconds); anything else as it is."""
    m = re.match(r"(\d{4}-\d\d-\d\d)[T ](\d\d:\d\d)(:\d\d)?", date)
    if not m:
        return date or "undated"
    return f"{m.group(1)} {m.group(2)}{(m.group(3) or '') if seconds else ''}"


def hugepages(r):
    """The huge-pages setting a record asked for ('system', 'thp', 'none'); '' where unrecorded."""
    hp = r.get("hugepages")
    if isinstance(hp, dict):
        hp = hp.get("requested")
    return hp if isinstance(hp, str) else ""


def settings(r):
    """What a record was measured under besides kernel, pattern, size and threads, as
    ((name, value), ...): huge pages, pinning, placement, and the kernel's parameters if any."""
    out = [("huge pages", hugepages(r) or "unrecorded"), ("pin", str(r["pin"]["requested"])),
           ("placement", str(r["placement"]["requested"]))]
    params = r.get("parameters")
    if isinstance(params, dict):
        out += [(f"{k}=", f"{v:g}" if isinstance(v, (int, float)) else str(v)) for k, v in sorted(params.items())]
    return tuple(out)


def unstable(r):
    """True where the suite flagged the record unstable (record.stability.unstable); absent: not flagged."""
    st = r.get("stability")
    return isinstance(st, dict) and st.get("unstable") is True


class Run:
    """One invocation of suite: its context and the file it came from."""

    def __init__(self, path, context, index):
        self.path, self.context, self.index = path, context, index
        self.date = str(context.get("date") or "")
        self.tag = ""  # how its series are labelled when runs must be told apart (Machine.finish)


def run_identity(path, context):
    date, line = context.get("date"), context.get("command_line")
    if date:
        return (str(date), json.dumps(line, sort_keys=True))
    return ("file", os.path.realpath(path))


class Machine:
    """The records of one machine and build (host, CPU, compiler and flags), from one or more runs.
    Each record keeps its run (`_run`); a series never mixes runs or huge-pages settings."""

    def __init__(self, doc):
        c = doc["context"]
        self.host, self.cpu, self.flags, self.compiler = machine_key(doc)
        self.label = f"{self.host} ({self.cpu})"
        self.caches = []
        for cache in (c.get("topology") or {}).get("caches") or []:
            if cache.get("type") in ("data", "unified") and cache.get("size_bytes"):
                self.caches.append(cache)
        self.runs = []
        self.run_index = {}
        self.records = []
        self.keys = set()
        self.skipped = 0
        self.split_runs, self.varying = False, set()
        self.probe = None

    def add(self, doc, path):
        rid = run_identity(path, doc["context"])
        if rid not in self.run_index:
            self.run_index[rid] = len(self.runs)
            self.runs.append(Run(path, doc["context"], len(self.runs)))
        run = self.run_index[rid]
        for r in doc["results"]:
            try:
                key = (run, r["name"], access(r), r["size"]["requested"], r["threads"]) + settings(r)
                if not r["verification"]["passed"]:
                    self.skipped += 1
                    continue
            except (KeyError, TypeError, AttributeError):
                fail(f"a record of {self.label} lacks name/size/threads/pin/placement/verification: not a suite result record")
            if key not in self.keys:
                self.keys.add(key)
                self.records.append(dict(r, _run=run))

    def finish(self):
        """Decides what labels must say: the run where one kernel and pattern came from several
        runs, a setting (huge pages, pin, ...) where records of one kernel differ in it; picks
        the probe to draw."""
        runs_of, values = {}, {}
        for r in self.records:
            runs_of.setdefault((r["name"], access(r)), set()).add(r["_run"])
            for name, value in settings(r):
                values.setdefault((r["name"], name), set()).add(value)
        self.split_runs = any(len(s) > 1 for s in runs_of.values())
        self.varying = {name for (_, name), v in values.items() if len(v) > 1}
        for tag in (lambda run: "run " + short_date(run.date), lambda run: "run " + short_date(run.date, seconds=True),
                    lambda run: "file " + os.path.basename(run.path), lambda run: f"run {run.index + 1}"):
            tags = [tag(run) for run in self.runs]
            if len(set(tags)) == len(tags):
                break
        for run, t in zip(self.runs, tags):
            run.tag = t
        probed = [run for run in self.runs if isinstance(run.context.get("caches_measured"), dict)]
        if probed:  # the latest probe: several runs each probed, their findings vary a little
            self.probe = max(probed, key=lambda run: run.date).context["caches_measured"]

    def variant(self, r):
        """What, besides kernel and pattern, separates series: (run, settings)."""
        return (r["_run"], settings(r))

    def variant_text(self, run, setting):
        """'[huge pages thp, run 2026-11-24 07:32]': what differs, empty where nothing does."""
        parts = [name + ("" if name.endswith("=") else " ") + value for name, value in setting if name in self.varying]
        if self.split_runs:
            parts.append(self.runs[run].tag)
        return f"[{', '.join(parts)}]" if parts else ""


def gather(docs):
    """[(path, doc)] -> the machines, records grouped, labels told apart. Exits 2 when nothing verified is left."""
    machines = {}
    for path, doc in docs:
        key = machine_key(doc)
        if key not in machines:
            machines[key] = Machine(doc)
        machines[key].add(doc, path)
    machines = list(machines.values())
    same = {}
    for m in machines:
        same.setdefault(m.label, []).append(m)
    for group in same.values():
        if len(group) < 2:
            continue
        marches = [march(m.flags) for m in group]
        compilers = [m.compiler for m in group]
        for m, arch, comp in zip(group, marches, compilers):
            if len(set(marches)) == len(group):
                m.label += f" [{arch}]"
            elif len(set(compilers)) == len(group):
                m.label += f" [{comp}, {arch}]"
            else:
                m.label += f" [{comp} {m.flags}]"
    for m in machines:
        m.finish()
        if m.skipped:
            print(f"plot.py: note: {m.skipped} record(s) of {m.label} failed verification and are left out", file=sys.stderr)
    if not any(m.records for m in machines):
        fail("no verified record to plot in " + ", ".join(p for p, _ in docs))
    return machines


def access(r):
    return r.get(r.get("axis", "pattern"), "?")


def footprint(r):
    s = r["size"]
    return s.get("footprint_bytes") or s["requested"]


def bandwidth(r):
    bw = r.get("bandwidth_gbps")
    return bw["stream"]["best"] if bw and bw.get("stream") and bw["stream"].get("best") else None


def latency(r):
    lat = r.get("latency_ns")
    return lat["best"] if lat and lat.get("best") else None


def human_bytes(n):
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if n < 1024 or unit == "TiB":
            return f"{n:.0f}{unit}" if float(n).is_integer() else f"{n:.3g}{unit}"
        n /= 1024.0


def cache_levels(m):
    """[(name, bytes per instance, instances, PUs per instance, source)] for the markers: each
    level's measured capacity (what one thread gets of one instance) where the probe found one,
    else hwloc's reported size. Instances and sharing come from the reported topology."""
    reported = {}
    for c in m.caches:
        reported.setdefault(c.get("level"), c)
    measured = {}
    for lvl in (m.probe or {}).get("levels") or []:
        if isinstance(lvl, dict) and isinstance(lvl.get("level"), int) and lvl.get("capacity_bytes"):
            measured[lvl["level"]] = lvl
    out = []
    for level in sorted(k for k in set(reported) | set(measured) if isinstance(k, int)):
        rep = reported.get(level) or {}
        name = f"L{level}{'d' if rep.get('type') == 'data' else ''}"
        if level in measured:
            size = measured[level]["capacity_bytes"]
            source = "measured" + (", partial" if measured[level].get("partial") else "")
        else:
            size, source = rep["size_bytes"], "reported"
        out.append((name, size, rep.get("instances") or 1, max(1, rep.get("pus_per_instance") or 1), source))
    return out
