"""The figures of `suite compare A.json B.json ... --plot DIR`: per kernel, pattern and thread count,
each file's bandwidth (or latency) against footprint on one set of axes, one colour per file, the
caches each machine measured (or reported) marked in its colour, unstable points hollow as in
plot.py's figures. "All threads" points of machines with different core counts share a figure.

Usage: compare.py DIR FILE... (suite compare runs it on the directory it claimed; the files are
checked by suite before). Exit status: 0 figures written; 2 bad input or nothing to draw.
"""

import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import UnsafeOutput, identify, save_figure  # noqa: E402
from results_model import Machine, access, bandwidth, fail, footprint, latency, load, unstable  # noqa: E402
from figure_parts import cache_markers, draw_series, finish, footprint_axis, legend, log_y, palette  # noqa: E402


def team(r, pus):
    """Which figure a record's thread count belongs to: 1, all of its machine's CPUs, or its count."""
    t = r["threads"]
    if t == 1:
        return (1, "1 thread")
    if pus and t == pus:
        return (10**6, "all threads")
    return (t, f"{t} threads")


def role(r):
    rl = (r.get("size") or {}).get("role")
    return rl.get("name") if isinstance(rl, dict) else None


def slug(text):
    return re.sub(r"[^A-Za-z0-9.-]+", "_", text).strip("_")


def figures(plt, machines):
    """{(kernel, access, team): [(machine index, [(x, y, unstable, role)], ylabel)]} drawn one figure each."""
    groups = {}
    for i, m in enumerate(machines):
        pus = m.runs[0].context.get("pus") if m.runs else None
        for r in m.records:
            value, ylabel = (bandwidth(r), "GB/s (STREAM bytes, best)") if r.get("metric") != "latency" else (
                latency(r), "ns per load (best)")
            if value is None:
                continue
            key = (r["name"], access(r)) + team(r, pus)
            groups.setdefault(key, {}).setdefault(i, (ylabel, []))[1].append((footprint(r), value, unstable(r),
                                                                             role(r), r["threads"]))
    colors = palette(plt, len(machines))
    for (name, acc, order, tname), by_machine in sorted(groups.items()):
        if len(by_machine) < 2:
            continue  # nothing to compare it with
        fig, ax = plt.subplots(figsize=(7.5, 4.6))
        hollow, ylabel = False, ""
        for i, (ylabel, pts) in sorted(by_machine.items()):
            m = machines[i]
            pts.sort()
            hollow |= draw_series(ax, [p[:3] for p in pts], colors[i], label=f"[{i + 1}] {m.name}: {m.label}")
            for x, y, _, rl, _ in pts:
                if rl:
                    ax.annotate(rl, (x, y), textcoords="offset points", xytext=(4, -10), fontsize=6.5, color=colors[i],
                                zorder=5, bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=0.5))
            cache_markers(ax, m, pts[0][4], color=colors[i], tag=f"[{i + 1}] ")
        footprint_axis(ax, plt)
        log_y(ax)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="major", alpha=0.3)
        legend(ax, hollow)
        finish(fig, machines, f"{name} {acc}, {tname}")
        yield f"compare-{slug(name)}-{slug(acc)}-{'t1' if order == 1 else 'all' if order == 10**6 else f't{order}'}", fig


def main(argv):
    if len(argv) < 3:
        fail("usage: compare.py DIR FILE FILE...")
    out, paths = argv[0], argv[1:]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail(f"matplotlib is missing ({e}); install it (Debian: apt-get install python3-matplotlib)")
    machines = []
    for path in paths:
        doc = load(path)
        m = Machine(doc)
        m.add(doc, path)
        m.finish()
        m.name = os.path.basename(path)
        machines.append(m)
    inputs = identify(paths)
    written = 0
    for name, fig in figures(plt, machines):
        try:
            save_figure(fig, os.path.join(out, name + ".png"), inputs, dpi=110, bbox_inches="tight")
        except UnsafeOutput as e:
            fail(f"--plot: {e}")
        plt.close(fig)
        written += 1
    if not written:
        fail("no kernel, pattern and thread count has a figure in two of " + ", ".join(paths))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
