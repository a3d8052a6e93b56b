#!/usr/bin/python3
"""Figures from suite result files.

Usage: plots/plot.py RESULT.json [MORE.json ...] --out DIR [--svg]

Writes PNG (and SVG with --svg) into DIR and prints each file's path:
  bandwidth_vs_footprint   GB/s (log y) against the footprint of all arrays (log x), one line per
                           kernel/pattern/variant, one panel per thread count. Dotted markers at
                           the cache capacities the team has: the sizes the cache probe measured
                           (context.caches_measured, labelled "measured") where there is one,
                           else hwloc's reported sizes (labelled "reported"); a per-core cache
                           counts once per thread up to its instance count, a shared one once.
                           The 1-thread panel also shows the probe's fine bandwidth sweep (the
                           load kernel, 1 thread) as a thin grey line, so that a sweep of three
                           sizes still shows where the caches end.
  latency_vs_footprint     ns per dependent load (log y) against the footprint, for the latency
                           kernel; cache markers as above, the probe's latency sweep (pointer
                           chase, 1 thread) in the 1-thread panel
  threads_scaling          bandwidth (log y) and speed-up over 1 thread against threads, at the
                           largest size measured with 1 and more threads, with the ideal line
  patterns                 sequential, random, strided side by side as grouped bars per size
                           (log y, the value on each bar), fewest threads measured (orderings:
                           natural, morton, hilbert, ... in `orderings`)
  counters                 each counted event per element against the footprint, one panel per
                           event; titled by what was counted (hardware or software events)
  energy                   nJ per byte by RAPL domain against the footprint, where recorded
Every figure has a title, axes with units, a legend, and in its lower right corner the host, CPU,
date of each run and the suite version and git revision. Points flagged unstable by the suite
(record.stability.unstable) are drawn hollow ("hollow: unstable (noise)" in the legend).

Several files from different machines: the same figures with one line per machine, labelled by
host and CPU (and the -march, else the compiler, when two builds of one machine are compared).
Records are never merged across contexts: records with a different huge-pages setting (or
pinning, placement, kernel parameters), and different runs of one machine (another date or
command line) where they measured the same kernel and pattern, stay separate series, labelled by
what differs ("[huge pages thp]", "[run 2026-11-24 07:32]"). The same run given twice (same date
and command line) counts once. Records that failed
verification are left out (and said so).

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
UNSTABLE_NOTE = "hollow: unstable (noise)"
STAMP_GID = "run-stamp"  # the gid of the corner text naming the runs (tests look for it)


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


def cache_markers(ax, machine, threads, color=None, tag="", drawn=None):
    """Vertical markers at the cache capacity a team of `threads` has: one instance per thread
    up to the number of instances (private caches add up, a shared one does not). Threads are
    taken to fill an instance's PUs before the next (compact pinning). `drawn`: the markers already
    on these axes (two builds of one host have the same caches), not drawn again."""
    drawn = set() if drawn is None else drawn
    for name, size, instances, per, source in cache_levels(machine):
        used = min(instances, max(1, -(-threads // per)))
        total = size * used
        label = f"{tag}{name} {human_bytes(total)} {source}" + (f" (x{used})" if used > 1 else "")
        if (total, label) in drawn:
            continue
        drawn.add((total, label))
        ax.axvline(total, color=color or "0.5", linestyle=":", linewidth=1)
        ax.text(total, 0.98, label, rotation=90, va="top", ha="right", fontsize=7, color=color or "0.3",
                transform=ax.get_xaxis_transform(), bbox=dict(facecolor="white", edgecolor="none", alpha=0.75, pad=1))


def probe_kernel(probe, what, default):
    """The kernel the probe used for `what` ('latency', 'bandwidth'), read from its method note."""
    m = re.search(what + r": the ([\w-]+) kernel( \([^)]*\))?", str(probe.get("method") or ""))
    return (m.group(1) + " kernel" + (m.group(2) or "")) if m else default


def probe_line(ax, m, field, value_key, what, default, linestyle, label_of):
    """The probe's fine sweep as a thin grey line; False where the context has none."""
    probe = m.probe or {}
    pts = sorted((p["size_bytes"], p[value_key]) for p in probe.get(field) or []
                 if isinstance(p, dict) and p.get("size_bytes") and p.get(value_key))
    if len(pts) < 2:
        return False
    text = f"cache probe, 1 thread:\n{probe_kernel(probe, what, default)}"
    ax.plot([p[0] for p in pts], [p[1] for p in pts], color="0.6", linewidth=0.9, linestyle=linestyle, zorder=1,
            label=label_of(text))
    return True


def series_label(machines, m, *parts):
    text = " ".join(p for p in parts if p)
    return f"{m.label}: {text}" if len(machines) > 1 else text


def palette(plt, n):
    import matplotlib

    cmap = matplotlib.colormaps["tab10" if n <= 10 else "tab20"]
    return [cmap(i % cmap.N) for i in range(max(n, 1))]


def draw_series(ax, pts, color, linestyle="-", label=None, markersize=3.5):
    """pts: [(x, y, unstable)] sorted by x. A line with filled markers, unstable points hollow
    (a white marker with the series' edge drawn over them). True if any was unstable."""
    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=markersize, linestyle=linestyle,
            color=color, label=label)
    shaky = [p for p in pts if p[2]]
    if shaky:
        ax.plot([p[0] for p in shaky], [p[1] for p in shaky], linestyle="none", marker="o", markersize=markersize + 1,
                markerfacecolor="white", markeredgecolor=color, markeredgewidth=1.2, zorder=3)
    return bool(shaky)


def legend(ax, hollow, fontsize=7, handles=None):
    """The legend right of the axes; with UNSTABLE_NOTE (a hollow marker, or a hollow bar when the
    handles are bars) once where `hollow`."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = list(handles) if handles is not None else ax.get_legend_handles_labels()[0]
    if hollow and any(isinstance(h, Patch) for h in handles):
        handles.append(Patch(facecolor="white", edgecolor="0.3", linewidth=1.2, label=UNSTABLE_NOTE))
    elif hollow:
        handles.append(Line2D([], [], linestyle="none", marker="o", markersize=5, markerfacecolor="white",
                              markeredgecolor="0.3", markeredgewidth=1.2, label=UNSTABLE_NOTE))
    if handles:
        ax.legend(handles=handles, fontsize=fontsize, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)


def log_y(ax):
    """A log y axis labelled in plain numbers (0.1, 1, 10), with labelled minor ticks when it spans
    less than two decades (else a short range would show one label or none)."""
    from matplotlib.ticker import FuncFormatter, LogFormatter

    ax.set_yscale("log")
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 0.5)))
    ax.tick_params(axis="y", which="minor", labelsize=7)
    ax.grid(True, which="minor", axis="y", alpha=0.1)


def footprint_axis(ax, plt, label="footprint of all arrays (bytes, log scale)"):
    ax.set_xscale("log", base=2)
    ax.xaxis.set_major_formatter(plt.FuncFormatter(lambda x, _: human_bytes(x)))
    ax.tick_params(axis="x", labelsize=8)
    ax.set_xlabel(label)


def stamp_lines(machines):
    """One line per run: host, CPU, date, suite version and git revision (at most four lines)."""
    lines = []
    for m in machines:
        for run in m.runs:
            c = run.context
            rev = squash(c.get("git_revision") or "")
            line = (f"{m.host} | {m.cpu} | run {short_date(run.date)}{' UTC' if run.date.endswith('Z') else ''} | "
                    f"suite {squash(c.get('suite_version') or '?')}" + (f" ({rev})" if rev else ""))
            if line not in lines:
                lines.append(line)
    return lines if len(lines) <= 4 else lines[:3] + [f"and {len(lines) - 3} more runs"]


def widen_for_legends(fig, room=1.9):
    """Legends sit right of their axes; panels() leaves about `room` inches each. Where a row's
    legends need more (long labels: runs, huge pages, machines), the figure grows by the excess
    instead of squeezing the axes."""
    renderer = fig.canvas.get_renderer()
    rows = {}
    for ax in fig.axes:
        leg = ax.get_legend()
        if ax.get_visible() and leg is not None:
            rows.setdefault(round(ax.get_position().y0, 3), []).append(leg.get_window_extent(renderer).width / fig.dpi)
    excess = max((sum(w) - room * len(w) for w in rows.values()), default=0)
    if excess > 0.1:
        fig.set_figwidth(fig.get_figwidth() + excess)


def finish(fig, machines, title=None):
    """Title, the runs in small text in the lower right corner, layout leaving room for both."""
    height = fig.get_figheight() * 72  # points
    top, sup = 1.0, None
    if title:  # its room is kept here: tight_layout would count a suptitle of several lines twice
        sup = fig.suptitle(title, y=1 - 4 / height, va="top")
        sup.set_in_layout(False)
        top = 1 - ((title.count("\n") + 1) * 12 * 1.25 + 6) / height
    widen_for_legends(fig)
    lines = stamp_lines(machines)
    bottom = (len(lines) * 6.5 * 1.35 + 8) / height
    fig.tight_layout(rect=(0, bottom, 1, top))
    if sup is not None:
        sup.set_in_layout(True)  # inside the saved bounding box
    fig.text(0.995, 0.004, "\n".join(lines), ha="right", va="bottom", fontsize=6.5, color="0.35", gid=STAMP_GID)


def panels(plt, n, width=6.0, height=4.2):
    cols = min(n, 2)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    flat = [a for row in axes for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def series_colors(plt, machines, select):
    """A color per (kernel, pattern, run, huge pages) that keeps it across panels."""
    keys = sorted({(r["name"], access(r)) + m.variant(r) for m in machines for r in m.records if select(r)})
    return dict(zip(keys, palette(plt, len(keys))))


def vs_footprint(plt, machines, value, ylabel, title, probe):
    threads = sorted({r["threads"] for m in machines for r in m.records if value(r) is not None})
    if not threads:
        return None
    fig, axes = panels(plt, len(threads))
    colors = series_colors(plt, machines, lambda r: value(r) is not None)
    for ax, t in zip(axes, threads):
        hollow, drawn = False, set()
        for mi, m in enumerate(machines):
            groups = {}
            for r in m.records:
                if r["threads"] == t and value(r) is not None:
                    groups.setdefault((r["name"], access(r)) + m.variant(r), []).append((footprint(r), value(r), unstable(r)))
            style = ["-", "--", "-.", ":"][mi % 4]
            for key, pts in sorted(groups.items()):
                kname, acc, run, setting = key
                hollow |= draw_series(ax, sorted(pts), colors[key], style,
                                      series_label(machines, m, kname, acc, m.variant_text(run, setting)))
            if t == 1:
                probe_line(ax, m, *probe, style, lambda text: series_label(machines, m, text))
            cache_markers(ax, m, t, color=None if len(machines) == 1 else "C%d" % (mi + 7),
                          tag="" if len(machines) == 1 else f"{m.host} ", drawn=drawn)
        footprint_axis(ax, plt)
        log_y(ax)
        ax.set_ylabel(ylabel)
        ax.set_title(f"{t} thread{'s' if t > 1 else ''}")
        ax.grid(True, which="major", alpha=0.3)
        legend(ax, hollow)
    finish(fig, machines, title + (" - " + ", ".join(m.label for m in machines) if len(machines) > 1 else f" - {machines[0].label}"))
    return fig


def threads_scaling(plt, machines):
    lines = []
    for m in machines:
        by = {}
        for r in m.records:
            if bandwidth(r) is not None:
                key = ((r["name"], access(r)) + m.variant(r), r["size"]["requested"])
                by.setdefault(key, {})[r["threads"]] = (bandwidth(r), unstable(r))
        best = {}
        for (series, size), pts in by.items():
            if len(pts) >= 2 and 1 in pts and size >= best.get(series, (0, None))[0]:
                best[series] = (size, pts)
        for series, (size, pts) in sorted(best.items()):
            lines.append((m, series, size, sorted(pts.items())))
    if not lines:
        return None
    fig, (a_bw, a_su) = plt.subplots(1, 2, figsize=(12, 4.5))
    colors = palette(plt, len(lines))
    counts = set()
    hollow = False
    for i, (m, (kname, acc, run, setting), size, pts) in enumerate(lines):
        label = series_label(machines, m, kname, acc, m.variant_text(run, setting), human_bytes(size))
        xs = [p[0] for p in pts]
        counts.update(xs)
        base, base_shaky = pts[0][1]
        hollow |= draw_series(a_bw, [(t, bw, u) for t, (bw, u) in pts], colors[i], label=label, markersize=5)
        draw_series(a_su, [(t, bw / base, u or base_shaky) for t, (bw, u) in pts], colors[i], label=label, markersize=5)
    top = max(counts)
    a_su.plot([1, top], [1, top], color="0.6", linestyle=":", label="ideal (linear)")
    a_bw.set_title("bandwidth against threads")
    a_bw.set_ylabel("bandwidth (GB/s, log scale)\nSTREAM convention, best")
    log_y(a_bw)
    a_su.set_title("speed-up over 1 thread")
    a_su.set_ylabel("speed-up (x, bandwidth / 1-thread bandwidth)")
    for a in (a_bw, a_su):
        a.set_xlabel("threads")
        a.set_xticks(sorted(counts))
        a.grid(True, alpha=0.3)
    legend(a_su, hollow)
    title = "Thread scaling at the largest size measured with several thread counts"
    finish(fig, machines, title + (f" - {machines[0].label}" if len(machines) == 1 else ""))
    return fig


def grouped_bars(plt, machines, axis, title):
    """One panel per machine and kernel: sizes as groups, one bar per pattern (or ordering)."""
    from matplotlib.patches import Patch

    panels_data = []
    for m in machines:
        t = min((r["threads"] for r in m.records if r.get("axis") == axis), default=None)
        kernels = {}
        for r in m.records:
            if r.get("axis") == axis and r["threads"] == t:
                v = bandwidth(r) if bandwidth(r) is not None else r.get("units_per_second_best")
                kernels.setdefault(r["name"], {}).setdefault((access(r),) + m.variant(r), {})[r["size"]["requested"]] = (v, unstable(r))
        for kname, accs in sorted(kernels.items()):
            if len(accs) >= 2:
                panels_data.append((m, t, kname, accs))
    if not panels_data:
        return None
    fig, axes = panels(plt, len(panels_data), width=6.5, height=4.0)
    for ax, (m, t, kname, accs) in zip(axes, panels_data):
        sizes = sorted({s for vals in accs.values() for s in vals})
        width = 0.8 / len(accs)
        colors = palette(plt, len(accs))
        handles, hollow = [], False
        label_bars = len(accs) * len(sizes) <= 24
        for i, ((acc, run, setting), vals) in enumerate(sorted(accs.items())):
            for k, s in enumerate(sizes):
                v, shaky = vals.get(s, (None, False))
                if not v or v <= 0:
                    continue
                x = k + (i - (len(accs) - 1) / 2) * width
                ax.bar([x], [v], width=width, log=True, facecolor="white" if shaky else colors[i], edgecolor=colors[i],
                       linewidth=1.2 if shaky else 0.5)
                hollow |= shaky
                if label_bars:
                    ax.text(x, v, f"{v:.3g}", ha="center", va="bottom", fontsize=6, color="0.25")
            handles.append(Patch(facecolor=colors[i], edgecolor=colors[i], label=" ".join(p for p in (acc, m.variant_text(run, setting)) if p)))
        log_y(ax)
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi * 1.6)  # room for the values over the bars
        ax.set_xticks(range(len(sizes)))
        ax.set_xticklabels([human_bytes(s) for s in sizes], rotation=30, fontsize=8)
        ax.set_xlabel("footprint requested (bytes)")
        is_bw = any(bandwidth(r) is not None for r in m.records if r["name"] == kname)
        ax.set_ylabel(("bandwidth (GB/s, best" if is_bw else "units per second (best") + "; log scale)")
        ax.set_title(series_label(machines, m, kname, f"{t} thread{'s' if t > 1 else ''}"), fontsize=10)
        ax.grid(True, axis="y", alpha=0.3)
        legend(ax, hollow, fontsize=8, handles=handles)
    finish(fig, machines, title + (f" - {machines[0].label}" if len(machines) == 1 else ""))
    return fig


def event_kinds(machines, seen):
    """event name -> 'hardware' / 'software' / None: the records' `kind`, else the context's
    instruments.perf_counters.events[].hardware."""
    declared = {}
    for m in machines:
        for run in m.runs:
            perf = (run.context.get("instruments") or {}).get("perf_counters") or {}
            for e in perf.get("events") or []:
                if isinstance(e, dict) and isinstance(e.get("hardware"), bool):
                    declared.setdefault(e.get("name"), set()).add("hardware" if e["hardware"] else "software")
    kinds = {}
    for name, from_records in seen.items():
        k = from_records or declared.get(name) or set()
        kinds[name] = next(iter(k)) if len(k) == 1 else None
    return kinds


def hardware_missing(machines):
    """Why the context says hardware events could not be read, shortened; '' where it does not say."""
    for m in machines:
        for run in m.runs:
            hw = ((run.context.get("instruments") or {}).get("perf_counters") or {}).get("hardware")
            if isinstance(hw, dict) and hw.get("available") is False and hw.get("reason"):
                reason = str(hw["reason"]).split(" (perf_event_open")[0]
                return reason if len(reason) <= 110 else reason[:107] + "..."
    return ""


def counters_title(kinds, machines):
    hw = sorted(e for e, k in kinds.items() if k == "hardware")
    sw = sorted(e for e, k in kinds.items() if k == "software")
    other = sorted(e for e, k in kinds.items() if k is None)
    if hw and not sw and not other:
        title = f"Hardware counters ({', '.join(hw)})"
    else:
        parts = [f"{what}: {', '.join(names)}" for what, names in
                 (("hardware events", hw), ("software events", sw), ("events", other)) if names]
        title = f"Counters ({'; '.join(parts)})"
    title += "\nper element: median count per call / elements"
    missing = hardware_missing(machines) if not hw else ""
    return title + (f"\nno hardware events here: {missing}" if missing else "")


def counters(plt, machines):
    series, seen = {}, {}
    for m in machines:
        for r in m.records:
            block = r.get("counters") or {}
            if not block.get("available"):
                continue
            for e in block.get("events") or []:
                if e.get("available") and e.get("per_element") is not None:
                    key = (m.label, r["name"], access(r)) + m.variant(r) + (r["threads"],)
                    series.setdefault(e["name"], {}).setdefault(key, (m, []))[1].append((footprint(r), e["per_element"], unstable(r)))
                    kinds = seen.setdefault(e["name"], set())
                    if e.get("kind") in ("hardware", "software"):
                        kinds.add(e["kind"])
    if not series:
        return None
    kinds = event_kinds(machines, seen)
    keys = sorted({k[:5] for groups in series.values() for k in groups})
    colors = dict(zip(keys, palette(plt, len(keys))))
    fig, axes = panels(plt, len(series))
    for ax, (event, groups) in zip(axes, sorted(series.items())):
        hollow, values = False, []
        for key, (m, pts) in sorted(groups.items()):
            _, kname, acc, run, setting, t = key
            values += [p[1] for p in pts]
            hollow |= draw_series(ax, sorted(pts), colors[key[:5]], ["-", "--", "-.", ":"][(t - 1) % 4] if t >= 1 else "-",
                                  series_label(machines, m, kname, acc, m.variant_text(run, setting), f"t={t}"))
        footprint_axis(ax, plt, "footprint of all arrays (bytes, log scale)")
        unit = " (ns)" if event in ("task-clock", "cpu-clock") else ""
        ax.set_ylabel(f"{event} per element{unit}")
        ax.set_title(event + (f" ({kinds[event]} event)" if kinds.get(event) else ""))
        if values and not any(values):
            ax.text(0.5, 0.7, "zero at every point", transform=ax.transAxes, ha="center", va="center", fontsize=9, color="0.4")
        ax.grid(True, alpha=0.3)
        legend(ax, hollow)
    finish(fig, machines, counters_title(kinds, machines))
    return fig


def energy(plt, machines):
    groups = {}
    for m in machines:
        for r in m.records:
            block = r.get("energy") or {}
            if not block.get("available"):
                continue
            for d in block.get("domains") or []:
                if d.get("nj_per_byte") is not None:
                    dom = d["domain"] + ("" if d.get("socket") is None else f"-{d['socket']}")
                    key = (m.label, r["name"], access(r)) + m.variant(r) + (dom, r["threads"])
                    groups.setdefault(key, (m, []))[1].append((footprint(r), d["nj_per_byte"], unstable(r)))
    if not groups:
        return None
    fig, ax = plt.subplots(figsize=(8, 4.5))
    colors = palette(plt, len({k[:6] for k in groups}))
    color_of = dict(zip(sorted({k[:6] for k in groups}), colors))
    hollow = False
    for key, (m, pts) in sorted(groups.items()):
        _, kname, acc, run, setting, dom, t = key
        hollow |= draw_series(ax, sorted(pts), color_of[key[:6]], ["-", "--", "-.", ":"][(t - 1) % 4] if t >= 1 else "-",
                              series_label(machines, m, kname, acc, m.variant_text(run, setting), f"t={t}", dom))
    footprint_axis(ax, plt)
    ax.set_ylabel("energy (nJ per byte moved, STREAM bytes)")
    ax.set_title("by RAPL domain", fontsize=10)
    ax.grid(True, alpha=0.3)
    legend(ax, hollow)
    finish(fig, machines, "Energy per byte" + (f" - {machines[0].label}" if len(machines) == 1 else ""))
    return fig


def make_figures(plt, machines):
    """[(name, figure)] in the order they are written."""
    figures = [
        ("bandwidth_vs_footprint", vs_footprint(plt, machines, bandwidth, "bandwidth (GB/s, log scale)\nSTREAM convention, best",
                                                "Bandwidth against footprint", ("bandwidth_sweep", "gbps", "bandwidth", "load kernel"))),
        ("latency_vs_footprint", vs_footprint(plt, machines, latency, "latency (ns, log scale)\nper dependent load, best",
                                              "Latency against footprint", ("latency_sweep", "ns", "latency", "latency kernel"))),
        ("threads_scaling", threads_scaling(plt, machines)),
        ("patterns", grouped_bars(plt, machines, "pattern", "Access patterns side by side (fewest threads measured)")),
        ("orderings", grouped_bars(plt, machines, "ordering", "Data orderings side by side (fewest threads measured)")),
        ("counters", counters(plt, machines)),
        ("energy", energy(plt, machines)),
    ]
    return [(name, fig) for name, fig in figures if fig is not None]


def pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text in SVG
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail(f"matplotlib is missing ({e}); install it (Debian: apt-get install python3-matplotlib) and run with /usr/bin/python3")
    return plt


def save(plt, fig, out, name, svg, inputs, written):
    for ext in ["png"] + (["svg"] if svg else []):
        path = os.path.join(out, f"{name}.{ext}")
        try:
            save_figure(fig, path, inputs, dpi=110, bbox_inches="tight")
        except UnsafeOutput as e:
            fail(f"--out: {e}")
        written.append(path)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description="Figures from suite result files (PNG, and SVG with --svg).")
    parser.add_argument("files", nargs="+", help="result files written by suite --out=FILE.json")
    parser.add_argument("--out", required=True, help="directory for the figures (created if missing)")
    parser.add_argument("--svg", action="store_true", help="also write SVG")
    args = parser.parse_args(argv)
    docs = [(p, load(p)) for p in args.files]
    plt = pyplot()
    machines = gather(docs)
    try:
        check_directory(args.out)
        os.makedirs(args.out, exist_ok=True)
    except (UnsafeOutput, OSError) as e:
        fail(f"--out {args.out}: {e}")
    inputs = identify(args.files)  # the result files being plotted: no figure may be written over one of them
    written = []
    for name, fig in make_figures(plt, machines):
        save(plt, fig, args.out, name, args.svg, inputs, written)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
