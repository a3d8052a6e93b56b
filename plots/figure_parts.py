"""The parts every figure of plots/plot.py is made of: cache markers, the probe's sweep, series
and their labels, legends, axes, the corner stamp naming the runs, the panel grid.
"""

import re

from results_model import access, cache_levels, human_bytes, short_date, squash

UNSTABLE_NOTE = "hollow: unstable (noise)"
STAMP_GID = "run-stamp"  # the gid of the corner text naming the runs (tests look for it)


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
