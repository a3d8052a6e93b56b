#!/usr/bin/python3
"""Figures from suite result files.

Usage: plots/plot.py RESULT.json [MORE.json ...] --out DIR [--svg]

Writes PNG (and SVG with --svg) into DIR and prints each file's path:
  bandwidth_vs_footprint   GB/s against the footprint (log x), one line per kernel/pattern/variant,
                           one panel per thread count, the caches of the context as labelled markers
  latency_vs_footprint     ns per load against the footprint, for the latency kernel
  threads_scaling          bandwidth and speed-up against threads, at the largest size measured
                           with more than one thread count
  patterns                 sequential, random, strided side by side as grouped bars (orderings:
                           natural, morton, hilbert, ... in `orderings`)
  counters, energy         hardware counters per element and energy in nJ per byte, where recorded
Several files from different machines: the same figures with one line per machine, labelled by
host and CPU (and the -march when two builds of one machine are compared). Files of one machine
and build are merged. Records that failed verification are left out (and said so).

Needs matplotlib (Debian: python3-matplotlib); run with /usr/bin/python3.
Exit status: 0 figures written; 2 bad input (missing file, not JSON, not a suite result, a
schema_version this script does not know, nothing to plot).
"""

import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import UnsafeOutput, check_directory, identify, save_figure  # noqa: E402

KNOWN_SCHEMA_VERSIONS = {1}


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


def machine_key(doc):
    c = doc["context"]
    return (str(c.get("host", "?")), str(c.get("cpu_model", "") or "unknown CPU"), str(c.get("compiler_flags", "")))


def march(flags):
    m = re.search(r"-march=(\S+)", flags)
    return m.group(1) if m else "default -march"


class Machine:
    """The records of one machine and build, with its caches, from one or more files."""

    def __init__(self, doc):
        c = doc["context"]
        self.host, self.cpu, self.flags = machine_key(doc)
        self.label = f"{self.host} ({self.cpu})"
        self.caches = []
        for cache in (c.get("topology") or {}).get("caches") or []:
            if cache.get("type") in ("data", "unified") and cache.get("size_bytes"):
                self.caches.append(cache)
        self.records = []
        self.keys = set()
        self.skipped = 0

    def add(self, doc):
        for r in doc["results"]:
            try:
                key = (r["name"], access(r), r["size"]["requested"], r["threads"], r["pin"]["requested"], r["placement"]["requested"])
                if not r["verification"]["passed"]:
                    self.skipped += 1
                    continue
            except (KeyError, TypeError):
                fail(f"a record of {self.label} lacks name/size/threads/pin/placement/verification: not a suite result record")
            if key not in self.keys:
                self.keys.add(key)
                self.records.append(r)


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


def cache_markers(ax, machine, threads, color=None, tag=""):
    """Vertical markers at the cache capacity a team of `threads` has: one instance per thread
    up to the number of instances (private caches add up, a shared one does not)."""
    for cache in machine.caches:
        per = max(1, cache.get("pus_per_instance") or 1)
        used = min(cache.get("instances") or 1, max(1, -(-threads // per)))
        size = cache["size_bytes"] * used
        name = f"L{cache['level']}{'d' if cache['type'] == 'data' else ''}"
        label = f"{tag}{name} {human_bytes(size)}" + (f" (x{used})" if used > 1 else "")
        ax.axvline(size, color=color or "0.5", linestyle=":", linewidth=1)
        ax.text(size, 0.98, " " + label, rotation=90, va="top", ha="right", fontsize=7, color=color or "0.3",
                transform=ax.get_xaxis_transform())


def series_label(machines, m, *parts):
    text = " ".join(p for p in parts if p)
    return f"{m.label}: {text}" if len(machines) > 1 else text


# The result files being plotted: no figure may be written over one of them.
INPUTS = []


def save(fig, out, name, svg, written):
    for ext in ["png"] + (["svg"] if svg else []):
        path = os.path.join(out, f"{name}.{ext}")
        try:
            save_figure(fig, path, INPUTS, dpi=110, bbox_inches="tight")
        except UnsafeOutput as e:
            fail(f"--out: {e}")
        written.append(path)
    import matplotlib.pyplot as plt
    plt.close(fig)


def panels(plt, n, width=6.0, height=4.2):
    cols = min(n, 2)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    flat = [a for row in axes for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def vs_footprint(plt, machines, value, ylabel, title, name, args, written, log_y=False):
    threads = sorted({r["threads"] for m in machines for r in m.records if value(r) is not None})
    if not threads:
        return
    fig, axes = panels(plt, len(threads))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, t in zip(axes, threads):
        for mi, m in enumerate(machines):
            groups = {}
            for r in m.records:
                if r["threads"] == t and value(r) is not None:
                    groups.setdefault((r["name"], access(r)), []).append((footprint(r), value(r)))
            style = ["-", "--", "-.", ":"][mi % 4]
            for gi, ((kname, acc), pts) in enumerate(sorted(groups.items())):
                pts.sort()
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=3, linestyle=style,
                        color=colors[gi % len(colors)], label=series_label(machines, m, kname, acc))
            cache_markers(ax, m, t, color=None if len(machines) == 1 else "C%d" % (mi + 7),
                          tag="" if len(machines) == 1 else f"{m.host} ")
        ax.set_xscale("log", base=2)
        if log_y:
            ax.set_yscale("log")
        ax.set_xlabel("footprint of all arrays (bytes, log scale)")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{t} thread{'s' if t > 1 else ''}")
        ax.xaxis.set_major_formatter(plt.FuncFormatter(lambda x, _: human_bytes(x)))
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.suptitle(title + (" - " + ", ".join(m.label for m in machines) if len(machines) > 1 else f" - {machines[0].label}"))
    fig.tight_layout()
    save(fig, args.out, name, args.svg, written)


def threads_scaling(plt, machines, args, written):
    lines = []
    for m in machines:
        by = {}
        for r in m.records:
            if bandwidth(r) is not None:
                by.setdefault((r["name"], access(r), r["size"]["requested"]), {})[r["threads"]] = bandwidth(r)
        best = {}
        for (kname, acc, size), pts in by.items():
            if len(pts) >= 2 and 1 in pts and size >= best.get((kname, acc), (0, None))[0]:
                best[(kname, acc)] = (size, pts)
        for (kname, acc), (size, pts) in sorted(best.items()):
            lines.append((m, kname, acc, size, sorted(pts.items())))
    if not lines:
        return
    fig, (a_bw, a_su) = plt.subplots(1, 2, figsize=(12, 4.5))
    top = 1
    for m, kname, acc, size, pts in lines:
        label = series_label(machines, m, kname, acc, human_bytes(size))
        xs = [p[0] for p in pts]
        a_bw.plot(xs, [p[1] for p in pts], marker="o", label=label)
        a_su.plot(xs, [p[1] / pts[0][1] for p in pts], marker="o", label=label)
        top = max(top, xs[-1])
    a_su.plot([1, top], [1, top], color="0.6", linestyle=":", label="ideal (linear)")
    a_bw.set_title("bandwidth against threads")
    a_bw.set_ylabel("bandwidth (GB/s, STREAM convention, best)")
    a_su.set_title("speed-up over 1 thread")
    a_su.set_ylabel("speed-up (x)")
    for a in (a_bw, a_su):
        a.set_xlabel("threads")
        a.grid(True, alpha=0.3)
    a_su.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.suptitle("Thread scaling at the largest size measured with several thread counts")
    fig.tight_layout()
    save(fig, args.out, "threads_scaling", args.svg, written)


def grouped_bars(plt, machines, axis, name, title, args, written):
    """One panel per machine and kernel: sizes as groups, one bar per pattern (or ordering)."""
    panels_data = []
    for m in machines:
        t = min((r["threads"] for r in m.records if r.get("axis") == axis), default=None)
        kernels = {}
        for r in m.records:
            if r.get("axis") == axis and r["threads"] == t:
                v = bandwidth(r) if bandwidth(r) is not None else r.get("units_per_second_best")
                kernels.setdefault(r["name"], {}).setdefault(access(r), {})[r["size"]["requested"]] = v
        for kname, accs in sorted(kernels.items()):
            if len(accs) >= 2:
                panels_data.append((m, t, kname, accs))
    if not panels_data:
        return
    fig, axes = panels(plt, len(panels_data), width=6.5, height=4.0)
    for ax, (m, t, kname, accs) in zip(axes, panels_data):
        sizes = sorted({s for vals in accs.values() for s in vals})
        width = 0.8 / len(accs)
        for i, (acc, vals) in enumerate(sorted(accs.items())):
            xs = [k + (i - (len(accs) - 1) / 2) * width for k in range(len(sizes))]
            ax.bar(xs, [vals.get(s, 0) or 0 for s in sizes], width=width, label=acc)
        ax.set_xticks(range(len(sizes)))
        ax.set_xticklabels([human_bytes(s) for s in sizes], rotation=30, fontsize=8)
        ax.set_xlabel("footprint requested")
        is_bw = any(bandwidth(r) is not None for r in m.records if r["name"] == kname)
        ax.set_ylabel("bandwidth (GB/s, best)" if is_bw else "units per second (best)")
        ax.set_title(series_label(machines, m, kname, f"{t} thread{'s' if t > 1 else ''}"), fontsize=10)
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.suptitle(title)
    fig.tight_layout()
    save(fig, args.out, name, args.svg, written)


def counters(plt, machines, args, written):
    series = {}
    for m in machines:
        for r in m.records:
            block = r.get("counters") or {}
            if not block.get("available"):
                continue
            for e in block.get("events") or []:
                if e.get("available") and e.get("per_element") is not None:
                    series.setdefault(e["name"], {}).setdefault((m, r["name"], access(r), r["threads"]), []).append(
                        (footprint(r), e["per_element"]))
    if not series:
        return
    fig, axes = panels(plt, len(series))
    for ax, (event, groups) in zip(axes, sorted(series.items())):
        for (m, kname, acc, t), pts in sorted(groups.items(), key=lambda kv: (kv[0][0].label, kv[0][1:])):
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=3,
                    label=series_label(machines, m, kname, acc, f"t={t}"))
        ax.set_xscale("log", base=2)
        ax.xaxis.set_major_formatter(plt.FuncFormatter(lambda x, _: human_bytes(x)))
        ax.set_xlabel("footprint (bytes, log scale)")
        ax.set_ylabel(f"{event} per element")
        ax.set_title(event)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.suptitle("Hardware counters per element (median per call / elements)")
    fig.tight_layout()
    save(fig, args.out, "counters", args.svg, written)


def energy(plt, machines, args, written):
    groups = {}
    for m in machines:
        for r in m.records:
            block = r.get("energy") or {}
            if not block.get("available"):
                continue
            for d in block.get("domains") or []:
                if d.get("nj_per_byte") is not None:
                    dom = d["domain"] + ("" if d.get("socket") is None else f"-{d['socket']}")
                    groups.setdefault((m, r["name"], access(r), r["threads"], dom), []).append((footprint(r), d["nj_per_byte"]))
    if not groups:
        return
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for (m, kname, acc, t, dom), pts in sorted(groups.items(), key=lambda kv: (kv[0][0].label, kv[0][1:])):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=3,
                label=series_label(machines, m, kname, acc, f"t={t}", dom))
    ax.set_xscale("log", base=2)
    ax.xaxis.set_major_formatter(plt.FuncFormatter(lambda x, _: human_bytes(x)))
    ax.set_xlabel("footprint (bytes, log scale)")
    ax.set_ylabel("energy (nJ per byte moved, STREAM bytes)")
    ax.set_title("Energy per byte, by RAPL domain")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.tight_layout()
    save(fig, args.out, "energy", args.svg, written)


def main(argv):
    parser = argparse.ArgumentParser(description="Figures from suite result files (PNG, and SVG with --svg).")
    parser.add_argument("files", nargs="+", help="result files written by suite --out=FILE.json")
    parser.add_argument("--out", required=True, help="directory for the figures (created if missing)")
    parser.add_argument("--svg", action="store_true", help="also write SVG")
    args = parser.parse_args(argv)
    docs = [(p, load(p)) for p in args.files]
    try:
        import matplotlib
        matplotlib.use("Agg")
        matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text in SVG
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail(f"matplotlib is missing ({e}); install it (Debian: apt-get install python3-matplotlib) and run with /usr/bin/python3")
    machines = {}
    for path, doc in docs:
        key = machine_key(doc)
        if key not in machines:
            machines[key] = Machine(doc)
        machines[key].add(doc)
    machines = list(machines.values())
    labels = [m.label for m in machines]
    for m in machines:
        if labels.count(m.label) > 1:
            m.label += f" [{march(m.flags)}]"
        if m.skipped:
            print(f"plot.py: note: {m.skipped} record(s) of {m.label} failed verification and are left out", file=sys.stderr)
    if not any(m.records for m in machines):
        fail("no verified record to plot in " + ", ".join(args.files))
    try:
        check_directory(args.out)
        os.makedirs(args.out, exist_ok=True)
    except (UnsafeOutput, OSError) as e:
        fail(f"--out {args.out}: {e}")
    INPUTS.extend(identify(args.files))
    written = []
    vs_footprint(plt, machines, lambda r: bandwidth(r), "bandwidth (GB/s, STREAM convention, best)",
                 "Bandwidth against footprint", "bandwidth_vs_footprint", args, written)
    vs_footprint(plt, machines, lambda r: latency(r), "latency (ns per dependent load, best)",
                 "Latency against footprint", "latency_vs_footprint", args, written, log_y=True)
    threads_scaling(plt, machines, args, written)
    grouped_bars(plt, machines, "pattern", "patterns", "Access patterns side by side (fewest threads measured)", args, written)
    grouped_bars(plt, machines, "ordering", "orderings", "Data orderings side by side (fewest threads measured)", args, written)
    counters(plt, machines, args, written)
    energy(plt, machines, args, written)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
