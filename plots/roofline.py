#!/usr/bin/python3
"""The roofline of a machine, from the ceilings `suite roofline` measured, with the points of a run
placed on it.

Usage: plots/roofline.py CEILINGS.json [--place PLACED.json] --out FIGURE.png

CEILINGS.json: `suite roofline --out CEILINGS.json`; PLACED.json: `suite roofline --place
RESULT.json --ceilings CEILINGS.json --out PLACED.json`. Example:
  plots/roofline.py results/roofline.json --place results/placed.json --out roofline.png

One row of panels per thread count, log-log: x the arithmetic intensity (flop per byte, the bytes
the kernel's arrays declare: STREAM convention), y GFLOP/s. A horizontal line at the peak (labelled
with the ISA that reached it), fainter ones at the narrower ISAs' peaks; one diagonal per memory
level, y = min(peak, x * GB/s), labelled "L1 210 GB/s", with a dot at its ridge point (where it
meets the peak; its intensity written above it). With --place, each placed record of that thread
count is a numbered marker: shape by kernel group (stream, fem, mpm, ...), colour by the memory
level its footprint falls in (the colour of that level's diagonal), hollow where the record was not
verified; the legend beside the row names each number and its fraction of its ceiling. Kernels
without flops go into a second panel of the row, at their GB/s against the level's ceiling. Records
the placement could not place are listed under the figure with the reason. The title names the
machine and the date of the ceilings. The placement's ceilings_file need not name CEILINGS.json:
the ceilings given are the ones drawn.

The figure's format follows the extension of --out (png, svg, pdf). Needs matplotlib (Debian:
python3-matplotlib); run with /usr/bin/python3.
Exit status: 0 written; 2 bad usage or input (missing or unreadable file, not JSON, another kind of
file, a schema_version other than 1, no ceilings, an output the suite may not write), one line on
stderr and the output left as it was; 3 matplotlib is missing.
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import UnsafeOutput, check_target, identify, save_figure  # noqa: E402
from results_model import human_bytes, short_date  # noqa: E402
from roofline_model import drawable, fail, load_ceilings, load_placement  # noqa: E402  (what the files say)

# gids of the figure's parts: tests find them by these.
PEAK, ISA, DIAGONAL, RIDGE, POINT, BW_CEILING, STAMP = ("roofline-peak", "roofline-isa", "roofline-diagonal", "roofline-ridge",
                                                       "roofline-point", "roofline-bandwidth-ceiling", "run-stamp")
HOLLOW_NOTE = "hollow: not verified"
MARKERS = {"stream": "o", "fem": "s", "mpm": "^", "compute": "D", "sfc": "v", "mesh": "P", "latency": "X"}
SPARE_MARKERS = ["*", "h", "<", ">", "p", "d", "8"]
LEVEL_COLORS = {"L1": "tab:blue", "L2": "tab:green", "L3": "tab:orange", "DRAM": "tab:red"}
SPARE_COLORS = ["tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "tab:gray"]


def pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text in SVG
        import matplotlib.pyplot as plt
    except ImportError as e:
        print(f"roofline.py: error: matplotlib is missing ({e}); install it (Debian: apt-get install python3-matplotlib) "
              "and run with /usr/bin/python3", file=sys.stderr)
        sys.exit(3)
    return plt


def styles(ceilings, placement):
    """{level: colour} and {group: marker}, fixed for the whole figure."""
    points = placement.points if placement else []
    levels = list(ceilings.levels) + sorted({p.level for p in points} - set(ceilings.levels))
    spare = iter(SPARE_COLORS * 4)
    colors = {lv: LEVEL_COLORS.get(lv) or next(spare) for lv in levels}
    groups = sorted({p.group for p in points})
    spare = iter(SPARE_MARKERS * 4)
    markers = {g: MARKERS.get(g) or next(spare) for g in groups}
    return colors, markers


def ridge(ceiling, b):
    return ceiling.peak_gflops / b.gbps if drawable(ceiling.peak_gflops) else None


def limits(ceilings, points):
    """The x and y ranges every roofline panel shares (so that thread counts compare at a glance):
    every ridge and point with room around it, at least 1/16 to 16 flop/byte."""
    xs, ys = [1 / 16, 16], []
    for c in ceilings.by_threads.values():
        xs += [x for b in c.diagonals() if ridge(c, b) for x in (ridge(c, b) / 32, ridge(c, b) * 8)]
        ys += [g * 2.5 for g in [c.peak_gflops] + [g for _, g in c.narrower()] if drawable(g)]
    for p in points:
        xs += [p.intensity / 2, p.intensity * 2]
        ys += [p.gflops / 2, p.gflops * 2]
    x0, x1 = min(xs), max(xs)
    for c in ceilings.by_threads.values():
        for b in c.diagonals():
            ys.append(x0 * b.gbps)  # where the diagonal enters on the left
            if not drawable(c.peak_gflops):
                ys.append(x1 * b.gbps)  # no peak: it runs to the right edge
    ys = ys or [0.1, 100]
    return (x0, x1), (min(ys), max(ys))


def plain_log(ax, axis):
    """A log axis labelled in plain numbers (0.01, 1, 100)."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    getattr(ax, f"set_{axis}scale")("log")
    a = getattr(ax, f"{axis}axis")
    a.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    a.set_minor_formatter(NullFormatter())


def draw_ceilings(ax, ceiling, colors, xlim):
    """The peak lines, the diagonals and their ridge points of one thread count. Labels go where
    no line runs: the peak's above it at the left (the diagonals are below it there), the ridge
    intensities above the peak, the narrower ISAs' under their lines at the right (past the ridges)
    and the diagonals' along them near the left edge (left of the intensities kernels have)."""
    x0, x1 = xlim
    peak = ceiling.peak_gflops if drawable(ceiling.peak_gflops) else None
    for isa, g in ceiling.narrower():
        ax.plot([x0, x1], [g, g], color="0.55", linestyle="--", linewidth=0.9, alpha=0.7, gid=ISA, zorder=1)
        ax.text(x1 / 1.15, g / 1.05, f"{isa} {g:.3g} GFLOP/s", fontsize=6.5, color="0.4", ha="right", va="top")
    if peak:
        isa = ceiling.peak_isa()
        ax.plot([x0, x1], [peak, peak], color="black", linewidth=1.8, gid=PEAK, zorder=2)
        ax.text(x0 * 1.15, peak * 1.06, f"{isa + ' ' if isa else ''}peak {peak:.3g} GFLOP/s", fontsize=7.5, ha="left",
                va="bottom", fontweight="bold")
    for b in sorted(ceiling.diagonals(), key=lambda b: -b.gbps):
        end = ridge(ceiling, b) or x1  # without a peak the diagonal runs to the edge
        color = colors[b.level]
        ax.plot([x0, end], [x0 * b.gbps, end * b.gbps], color=color, linewidth=1.6, gid=DIAGONAL, zorder=2,
                label=f"{b.level} {b.gbps:.3g} GB/s")
        # Rotated by the line's slope in data coordinates, which matplotlib turns into its angle
        # on the log axes wherever the layout puts them.
        at = x0 * 1.3
        ax.text(at, at * b.gbps * 1.1, f"{b.level} {b.gbps:.3g} GB/s", color=color, fontsize=7, ha="left", va="bottom",
                rotation=math.degrees(math.atan(b.gbps)), transform_rotates_text=True, rotation_mode="anchor",
                bbox=dict(facecolor="white", edgecolor="none", alpha=0.7, pad=0.5))
        if peak:
            ax.plot([end], [peak], marker="o", markersize=4.5, color=color, markeredgecolor="black", gid=RIDGE, zorder=4,
                    linestyle="none")
            ax.text(end, peak * 1.06, f"{end:.2g}", fontsize=6.5, color=color, ha="center", va="bottom")


def marker_style(p, colors, markers):
    color = colors[p.level]
    return dict(marker=markers[p.group], markersize=7, markeredgecolor=color, markeredgewidth=1.3,
                markerfacecolor=color if p.verified else "none", color=color, linestyle="none")


def numbered(ax, placed, colors, markers, xy):
    """Each point a marker with its number beside it. The number of a point within ~a marker of an
    earlier one (3% of the axes either way) is stacked above that one's instead of over it."""
    to_axes = ax.transScale + ax.transLimits  # data to axes fraction under the limits already set
    taken = []
    for n, p in placed:
        x, y = xy(p)
        ax.plot([x], [y], gid=POINT, zorder=5, **marker_style(p, colors, markers))
        fx, fy = to_axes.transform((x, y))
        k = sum(1 for tx, ty in taken if abs(tx - fx) < 0.03 and abs(ty - fy) < 0.03)
        taken.append((fx, fy))
        ax.annotate(str(n), (x, y), xytext=(5, 2 + 8 * k), textcoords="offset points", fontsize=6.5, color=colors[p.level],
                    fontweight="bold", zorder=6)  # over a neighbour's marker, not under it


def point_label(n, p):
    share = f" - {p.fraction:.0%} of its ceiling" if p.fraction is not None else ""
    return f"{n}  {p.label}{share}" + ("" if p.verified else " (not verified)")


def bandwidth_panel(ax, ceiling, placed, colors, markers, levels, ylim):
    """Kernels without flops: each at its GB/s in the column of its level, under the level's ceiling."""
    plain_log(ax, "y")
    ax.set_ylim(*ylim)
    ax.set_xlim(-0.6, len(levels) - 0.4)
    ax.set_xticks(range(len(levels)), levels)
    for i, lv in enumerate(levels):
        b = next((b for b in (ceiling.diagonals() if ceiling else []) if b.level == lv), None)
        if b:
            ax.plot([i - 0.42, i + 0.42], [b.gbps, b.gbps], color=colors[lv], linewidth=1.8, gid=BW_CEILING, zorder=2)
            ax.text(i - 0.42, b.gbps * 1.04, f"{b.gbps:.3g} GB/s", color=colors[lv], fontsize=6.5, ha="left", va="bottom")
    column = {lv: [q for q in placed if q[1].level == lv] for lv in levels}

    def xy(p):
        mine = column[p.level]
        j = next(i for i, q in enumerate(mine) if q[1] is p)
        return levels.index(p.level) - 0.1 + 0.45 * (j + 0.5) / len(mine), p.gbps  # right of the ceiling's label

    numbered(ax, placed, colors, markers, xy)
    if not placed:
        ax.text(0.5, 0.5, "none at this thread count", transform=ax.transAxes, ha="center", va="center", fontsize=8,
                color="0.4")
    ax.set_ylabel("GB/s (STREAM convention)")
    ax.grid(True, which="major", axis="y", alpha=0.3)


def layout(ceilings, placement):
    """The thread counts (one row each), and each row's points: (number, point) on the roofline
    and on the bandwidth panel, numbered across the figure."""
    points = placement.points if placement else []
    threads = sorted(set(ceilings.by_threads) | {p.threads for p in points})
    rows, n = [], 0
    for t in threads:
        roof = [p for p in points if p.threads == t and p.on_roofline()]
        flat = [p for p in points if p.threads == t and p.on_bandwidth()]
        roof = [(n + i + 1, p) for i, p in enumerate(roof)]
        n += len(roof)
        flat = [(n + i + 1, p) for i, p in enumerate(flat)]
        n += len(flat)
        rows.append((t, roof, flat))
    return rows


def key_handles(colors, markers, rows, any_hollow, capacity):
    from matplotlib.lines import Line2D

    used_levels = {p.level for _, roof, flat in rows for _, p in roof + flat}  # the diagonals have their own labels
    handles = [Line2D([], [], marker=m, color="0.3", linestyle="none", markersize=6, label=g) for g, m in markers.items()]
    handles += [Line2D([], [], color=c, linewidth=3, label=f"{lv} ({human_bytes(capacity[lv])})" if capacity.get(lv) else lv)
                for lv, c in colors.items() if lv in used_levels]
    if any_hollow:
        handles.append(Line2D([], [], marker="o", markerfacecolor="none", markeredgecolor="0.3", linestyle="none",
                              markersize=6, label=HOLLOW_NOTE))
    return handles


def title_of(ceilings):
    date = short_date(ceilings.date) + (" UTC" if ceilings.date.endswith("Z") else "") if ceilings.date else "undated"
    title = f"Roofline of {ceilings.host} ({ceilings.cpu}), ceilings measured {date}"
    if not ceilings.complete:
        title += "\nincomplete: the run that measured the ceilings did not finish; missing ceilings are not drawn"
    return title


def stamp_of(ceilings, placement):
    parts = [f"ceilings: {ceilings.path}"]
    if ceilings.fingerprint:
        parts.append(f"fingerprint {ceilings.fingerprint}")
    if ceilings.seconds is not None:
        parts.append(f"measured in {ceilings.seconds:.0f} s")
    if placement:
        parts.append(f"points: {placement.path}" + (f" (from {placement.result_file})" if placement.result_file else ""))
    return " | ".join(parts)


def notes_of(placement, limit=6):
    """The records the figure does not show, with why: not placed by suite, or nothing to draw."""
    if not placement:
        return []
    missing = placement.not_placed + placement.not_drawn
    lines = [f"not placed: {label}: {reason}" for label, reason in missing[:limit]]
    if len(missing) > limit:
        lines.append(f"and {len(missing) - limit} more records not placed")
    return lines


def make_figure(plt, ceilings, placement=None):
    """The roofline figure of `ceilings` (roofline_model.Ceilings), with `placement`'s points."""
    from matplotlib.lines import Line2D

    colors, markers = styles(ceilings, placement)
    rows = layout(ceilings, placement)
    points = [p for _, roof, _ in rows for _, p in roof]
    flat_points = [p for _, _, flat in rows for _, p in flat]
    xlim, ylim = limits(ceilings, points)
    flat_levels = [lv for lv in colors if any(p.level == lv for p in flat_points)]
    bw_values = [p.gbps for p in flat_points] + [b.gbps for c in ceilings.by_threads.values() for b in c.diagonals()
                                                 if b.level in flat_levels]
    bw_ylim = (min(bw_values) / 2, max(bw_values) * 2) if bw_values else None
    per_row = max([len(roof) + len(flat) for _, roof, flat in rows] + [0])
    row_height = max(4.4, 0.15 * per_row + 1.2)
    ratios = [6.5] + ([3.0] if flat_levels else [])
    notes = notes_of(placement)
    any_hollow = any(not p.verified for p in points + flat_points)
    key = key_handles(colors, markers, rows, any_hollow, ceilings.capacity) if placement else []
    key_rows = -(-len(key) // 10)
    title = title_of(ceilings)
    top_in = 0.22 * (title.count("\n") + 1)
    bottom_in = 0.12 * (len(notes) + 1) + 0.28 * key_rows + 0.12
    width = sum(ratios) + (3.6 if per_row else 0.4)
    height = row_height * len(rows) + top_in + bottom_in
    fig = plt.figure(figsize=(width, height))
    grid = fig.add_gridspec(len(rows), len(ratios), width_ratios=ratios)
    for r, (t, roof, flat) in enumerate(rows):
        ax = fig.add_subplot(grid[r, 0])
        plain_log(ax, "x")
        plain_log(ax, "y")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ceiling = ceilings.by_threads.get(t)
        name = f"{t} thread{'s' if t > 1 else ''}"
        if ceiling and ceiling.has_any():
            draw_ceilings(ax, ceiling, colors, xlim)
            ax.set_title(name)
        else:
            ax.set_title(f"{name}: no ceilings measured")
        numbered(ax, roof, colors, markers, lambda p: (p.intensity, p.gflops))
        ax.set_xlabel("arithmetic intensity (flop/byte, STREAM-convention bytes)")
        ax.set_ylabel("GFLOP/s")
        ax.grid(True, which="major", alpha=0.25)
        last = ax
        if flat_levels:
            last = fig.add_subplot(grid[r, 1])
            bandwidth_panel(last, ceiling, flat, colors, markers, flat_levels, bw_ylim)
            last.set_title(f"{name}: kernels without flops", fontsize=10)
        if roof or flat:
            handles = [Line2D([], [], label=point_label(n, p), **marker_style(p, colors, markers)) for n, p in roof + flat]
            last.legend(handles=handles, fontsize=6.5, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0,
                        handletextpad=0.4, title="placed records", title_fontsize=7)
    fig.suptitle(title, y=1 - 0.12 / height, va="top", fontsize=11)
    fig.tight_layout(rect=(0, bottom_in / height, 1, 1 - top_in / height))
    if key:
        fig.legend(handles=key, loc="lower center", ncol=min(len(key), 10), fontsize=7, frameon=False,
                   bbox_to_anchor=(0.5, (0.12 * (len(notes) + 1) + 0.06) / height),
                   title="marker: kernel group; colour: memory level of the footprint", title_fontsize=7)
    if notes:
        fig.text(0.005, 0.14 / height, "\n".join(notes), ha="left", va="bottom", fontsize=6.5, color="0.3")
    fig.text(0.995, 0.02 / height, stamp_of(ceilings, placement), ha="right", va="bottom", fontsize=6.5, color="0.35",
             gid=STAMP)
    return fig


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, as for bad input (argparse would print the usage too)
        fail(f"{message} (usage: plots/roofline.py CEILINGS.json [--place PLACED.json] --out FIGURE.png)")


def main(argv):
    parser = Parser(usage="plots/roofline.py CEILINGS.json [--place PLACED.json] --out FIGURE.png",
                    description=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("ceilings", metavar="CEILINGS.json", help="ceilings file written by suite roofline --out")
    parser.add_argument("--place", metavar="PLACED.json", help="placement file written by suite roofline --place RESULT.json")
    parser.add_argument("--out", required=True, metavar="FIGURE.png",
                        help="the figure to write (its extension picks the format: png, svg, pdf)")
    args = parser.parse_args(argv)
    ceilings = load_ceilings(args.ceilings)
    placement = load_placement(args.place) if args.place else None
    inputs = identify([p for p in (args.ceilings, args.place) if p])  # no figure may be written over one of them
    try:
        check_target(args.out, inputs)  # now, not after the figure is drawn; save_figure checks again
    except UnsafeOutput as e:
        fail(f"--out: {e}")
    plt = pyplot()
    fmt = os.path.splitext(args.out)[1].lstrip(".").lower()
    supported = plt.figure().canvas.get_supported_filetypes()
    plt.close("all")
    if fmt not in supported:
        fail(f"--out {args.out}: '{fmt or 'no extension'}' is not a figure format matplotlib writes "
             f"({', '.join(sorted(supported))})")
    fig = make_figure(plt, ceilings, placement)
    try:
        save_figure(fig, args.out, inputs, dpi=120, bbox_inches="tight")
    except UnsafeOutput as e:
        fail(f"--out: {e}")
    except OSError as e:
        fail(f"--out {args.out}: cannot write it: {e}")
    plt.close(fig)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
