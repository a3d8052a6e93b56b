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
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import UnsafeOutput, check_directory, identify, save_figure  # noqa: E402
from results_model import (  # noqa: E402  (what the files say; this script draws it)
    access,
    bandwidth,
    fail,
    footprint,
    gather,
    human_bytes,
    latency,
    load,
    unstable,
)
from figure_parts import (  # noqa: E402  (the parts the figures are made of)
    cache_markers,
    probe_line,
    series_label,
    palette,
    draw_series,
    legend,
    log_y,
    footprint_axis,
    finish,
    panels,
    series_colors,
)


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
