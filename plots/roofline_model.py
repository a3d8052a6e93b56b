"""What the files of `suite roofline` say, for plots/roofline.py: a ceilings file (kind
suite-roofline) and a placement file (kind suite-roofline-placement), read and checked into plain
objects. No drawing here. A file that cannot be used ends the script with one line on stderr and
exit status 2 (via fail), before any output is touched.
"""

import json
import math
import sys

SCHEMA_VERSION = 1
CEILINGS_KIND = "suite-roofline"
PLACEMENT_KIND = "suite-roofline-placement"


def fail(message):
    print("roofline.py: error: " + " ".join(str(message).split()), file=sys.stderr)  # one line, always
    sys.exit(2)


def squash(text):
    """Runs of whitespace as one space, none at the ends (hwloc pads CPU model names)."""
    return " ".join(str(text).split())


def read_json(path):
    try:
        with open(path, "rb") as f:
            return json.loads(f.read().decode("utf-8"))
    except FileNotFoundError:
        fail(f"{path}: no such file")
    except (OSError, UnicodeDecodeError) as e:
        fail(f"{path}: cannot read it: {e}")
    except json.JSONDecodeError as e:
        fail(f"{path}: not valid JSON (truncated, or not a file of suite roofline?): {e}")


def check_header(path, doc, kind, other_kind, other_hint):
    """The kind and schema_version every file of suite roofline starts with."""
    if not isinstance(doc, dict):
        fail(f"{path}: not a file of suite roofline (it writes an object with kind '{kind}')")
    if doc.get("kind") == other_kind:
        fail(f"{path}: kind '{other_kind}' where '{kind}' was expected: {other_hint}")
    if doc.get("kind") != kind:
        fail(f"{path}: kind {doc.get('kind')!r} is not '{kind}' (not a file of suite roofline)")
    if doc.get("schema_version") != SCHEMA_VERSION:
        fail(f"{path}: schema_version {doc.get('schema_version')!r} is not one this script knows ([{SCHEMA_VERSION}]); "
             "use the plots/ of the suite version that wrote it")


def number(value, where):
    """A measured value: a finite number, or None where it was not measured (null or absent).
    Anything else is a malformed file: 'not measured' is null, never a string or 0 (STYLE 7)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        fail(f"{where}: expected a number or null, got {value!r}")
    return float(value)


def drawable(value):
    """True for a value a log axis can show."""
    return value is not None and value > 0


def text(value, where, default=None):
    if value is None and default is not None:
        return default
    if not isinstance(value, str) or not value:
        fail(f"{where}: expected a non-empty string, got {value!r}")
    return value


def thread_count(value, where):
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        fail(f"{where}: 'threads' must be a whole number of at least 1, got {value!r}")
    return value


def listed(doc, key, where):
    value = doc.get(key)
    if value is None:
        return []
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        fail(f"{where}: '{key}' must be a list of objects")
    return value


class Bandwidth:
    """The bandwidth ceiling of one memory level at one thread count (STREAM-convention GB/s)."""

    def __init__(self, entry, where):
        self.level = text(entry.get("level"), f"{where}: level")
        self.gbps = number(entry.get("gbps"), f"{where} ({self.level}): gbps")
        self.hardware_gbps = number(entry.get("hardware_gbps"), f"{where} ({self.level}): hardware_gbps")
        self.kernel = entry.get("kernel") if isinstance(entry.get("kernel"), str) else None


class Ceiling:
    """The ceilings of one thread count: the peak of each ISA and a bandwidth per level."""

    def __init__(self, entry, where):
        self.threads = thread_count(entry.get("threads"), where)
        where = f"{where} (threads {self.threads})"
        self.peak_gflops = number(entry.get("peak_gflops"), f"{where}: peak_gflops")
        self.isas = []  # (isa, gflops), as measured; None where not measured
        for i, p in enumerate(listed(entry, "peak", where)):
            self.isas.append((text(p.get("isa"), f"{where}: peak[{i}].isa"), number(p.get("gflops"), f"{where}: peak[{i}].gflops")))
        self.bandwidth = [Bandwidth(b, f"{where}: bandwidth[{i}]") for i, b in enumerate(listed(entry, "bandwidth", where))]

    def peak_isa(self):
        """The ISA whose peak is peak_gflops (the widest that reached it); None if the list does not say."""
        if not drawable(self.peak_gflops):
            return None
        best = [isa for isa, g in self.isas if g is not None and math.isclose(g, self.peak_gflops, rel_tol=1e-6)]
        return best[-1] if best else None

    def narrower(self):
        """The other ISAs' peaks below the top one: (isa, gflops), drawable ones only."""
        top = self.peak_isa()
        return [(isa, g) for isa, g in self.isas if drawable(g) and isa != top and g < self.peak_gflops]

    def diagonals(self):
        """The bandwidth ceilings a diagonal can be drawn for (a measured, positive GB/s)."""
        return [b for b in self.bandwidth if drawable(b.gbps)]

    def has_any(self):
        return drawable(self.peak_gflops) or bool(self.diagonals())


class Ceilings:
    """A ceilings file of `suite roofline`: the machine, its memory levels and the ceilings per
    thread count (by_threads)."""

    def __init__(self, doc, path):
        check_header(path, doc, CEILINGS_KIND, PLACEMENT_KIND,
                     "this is a placement file; give the ceilings file first and this one with --place")
        self.path = path
        c = doc.get("context") if isinstance(doc.get("context"), dict) else {}
        self.host = squash(c.get("host") or "") or "unknown host"
        self.cpu = squash(c.get("cpu_model") or "") or "unknown CPU"
        self.date = str(c.get("date") or "")
        self.complete = doc.get("complete") is not False
        self.fingerprint = doc.get("fingerprint") if isinstance(doc.get("fingerprint"), str) else None
        self.seconds = number(doc.get("seconds"), f"{path}: seconds")
        self.levels = []  # level names in the file's order (L1, L2, L3, DRAM)
        self.capacity = {}
        for i, lv in enumerate(listed(doc, "levels", path)):
            name = text(lv.get("name"), f"{path}: levels[{i}].name")
            self.levels.append(name)
            self.capacity[name] = number(lv.get("capacity_bytes"), f"{path}: levels[{i}].capacity_bytes")
        entries = doc.get("ceilings")
        if not isinstance(entries, list) or not entries:
            fail(f"{path}: no ceilings (the 'ceilings' list is missing or empty)")
        if not all(isinstance(e, dict) for e in entries):
            fail(f"{path}: 'ceilings' must be a list of objects")
        self.by_threads = {}
        for i, e in enumerate(entries):
            ceiling = Ceiling(e, f"{path}: ceilings[{i}]")
            if ceiling.threads in self.by_threads:
                fail(f"{path}: ceilings[{i}]: threads {ceiling.threads} appears twice")
            self.by_threads[ceiling.threads] = ceiling
            for b in ceiling.bandwidth:
                if b.level not in self.levels:
                    self.levels.append(b.level)
        if not any(c.has_any() for c in self.by_threads.values()):
            fail(f"{path}: no ceilings: no thread count has a peak or a bandwidth measured")


class Point:
    """A placed record of a run: where it sits against the ceilings of its thread count."""

    def __init__(self, p, where):
        self.threads = thread_count(p.get("threads"), where)
        self.name = p.get("name") if isinstance(p.get("name"), str) else None
        self.label = squash(p.get("label") or self.name or "") or where
        self.group = p.get("group") if isinstance(p.get("group"), str) and p.get("group") else "other"
        self.level = p.get("level") if isinstance(p.get("level"), str) and p.get("level") else "unknown level"
        self.verified = p.get("verified") is True  # absent is not verified: drawn hollow too
        self.gflops = number(p.get("gflops"), f"{where}: gflops")
        self.gbps = number(p.get("gbps"), f"{where}: gbps")
        intensity = p.get("intensity")
        if intensity is not None and not isinstance(intensity, dict):
            fail(f"{where}: 'intensity' must be an object or null")
        self.intensity = number((intensity or {}).get("stream"), f"{where}: intensity.stream")
        self.fraction = number(p.get("fraction"), f"{where}: fraction")
        ceiling = p.get("ceiling") if isinstance(p.get("ceiling"), dict) else {}
        self.bound = ceiling.get("bound") if isinstance(ceiling.get("bound"), str) else None

    def on_roofline(self):
        """True where the point has flops to place at (intensity, GFLOP/s)."""
        return drawable(self.gflops) and drawable(self.intensity)

    def on_bandwidth(self):
        """True for a point with no flops (or none a log axis can show) but a bandwidth."""
        return not self.on_roofline() and drawable(self.gbps)


class Placement:
    """A placement file of `suite roofline --place`: the points, and the records not placed with
    their reasons. Its ceilings_file need not name the ceilings given: the ones given are used."""

    def __init__(self, doc, path):
        check_header(path, doc, PLACEMENT_KIND, CEILINGS_KIND,
                     "this is a ceilings file; give it first and the placement file with --place")
        self.path = path
        self.result_file = doc.get("result_file") if isinstance(doc.get("result_file"), str) else None
        if not isinstance(doc.get("points"), list):
            fail(f"{path}: no 'points' list")
        self.points = [Point(p, f"{path}: points[{i}]") for i, p in enumerate(listed(doc, "points", path))]
        self.not_placed = [(squash(n.get("label") or "?"), squash(n.get("reason") or "no reason given"))
                           for n in listed(doc, "not_placed", path)]
        self.not_drawn = [(p.label, "neither flops nor a bandwidth to draw") for p in self.points
                          if not p.on_roofline() and not p.on_bandwidth()]


def load_ceilings(path):
    return Ceilings(read_json(path), path)


def load_placement(path):
    return Placement(read_json(path), path)
