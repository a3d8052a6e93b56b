#!/usr/bin/env python3
"""The dam's front against time, from the files `./suite mpm --out=DIR` wrote.

Usage: python3 plots/mpm_front.py DIR

Reads DIR/front.csv (step, time, front, kinetic_energy, and the order columns) and, for the column's initial width and
the run's description, DIR/mpm.json; writes DIR/front.png: the front (the largest x of any
particle) against simulated time, the initial column width as a dashed line, the box's wall at
x = 1 as a dotted one, and the kinetic energy on a second axis.
Exit status: 0, 1 when a file cannot be read, 2 for bad usage, 3 when matplotlib is missing.
"""
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import identify, save_figure  # noqa: E402


def read_front(path):
    """Columns of front.csv as lists of floats: time, front, kinetic energy, and the particles'
    order (mean curve gap, share in one element; empty lists for a front.csv without them)."""
    time, front, kinetic, gap, same = [], [], [], [], []
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"step", "time", "front", "kinetic_energy"} - set(reader.fieldnames or [])
        if missing:
            raise ValueError(f"{path}: no column {', '.join(sorted(missing))}; is it a front.csv of ./suite mpm?")
        ordered = {"mean_curve_gap", "same_element"} <= set(reader.fieldnames or [])
        for row in reader:
            time.append(float(row["time"]))
            front.append(float(row["front"]))
            kinetic.append(float(row["kinetic_energy"]))
            if ordered:
                gap.append(float(row["mean_curve_gap"]))
                same.append(float(row["same_element"]))
    if not time:
        raise ValueError(f"{path}: no rows")
    return time, front, kinetic, gap, same


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: mpm_front.py DIR (a directory written by ./suite mpm)", file=sys.stderr)
        return 2
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        print(f"matplotlib is missing for {sys.executable} ({e.name}): install python3-matplotlib", file=sys.stderr)
        return 3
    directory = argv[1]
    csv_path, json_path = os.path.join(directory, "front.csv"), os.path.join(directory, "mpm.json")
    try:
        time, front, kinetic, gap, same = read_front(csv_path)
        summary = {}
        if os.path.exists(json_path):
            with open(json_path) as f:
                summary = json.load(f)
    except (OSError, ValueError) as e:
        print(f"mpm_front.py: {e}", file=sys.stderr)
        return 1
    settings = summary.get("settings", {})
    width = summary.get("front", {}).get("column_width", front[0])

    if gap:
        fig, (ax, order) = plt.subplots(2, 1, figsize=(7, 7), dpi=100, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    else:
        fig, ax = plt.subplots(figsize=(7, 4.5), dpi=100)
    ax.plot(time, front, color="tab:blue", label="front (largest particle x)")
    ax.axhline(width, color="grey", linestyle="--", linewidth=1, label=f"initial column width {width:g} m")
    ax.axhline(1.0, color="black", linestyle=":", linewidth=1, label="the box's far wall")
    ax.set_ylabel("front position x (m)")
    ax.set_ylim(0, 1.05)
    energy = ax.twinx()
    energy.plot(time, kinetic, color="tab:orange", linewidth=0.8, alpha=0.7, label="kinetic energy")
    energy.set_ylabel("kinetic energy (J)", color="tab:orange")
    lines = ax.get_legend_handles_labels()
    more = energy.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], loc="lower right", fontsize=8)
    if gap:
        order.plot(time, gap, color="tab:green", label="mean distance along the curve between neighbours' elements")
        order.set_yscale("log")
        order.set_ylabel("curve distance (elements)")
        share = order.twinx()
        share.plot(time, [100 * v for v in same], color="tab:purple", linewidth=0.8, label="neighbours in one element")
        share.set_ylabel("in one element (%)", color="tab:purple")
        share.set_ylim(0, 100)
        lines, more = order.get_legend_handles_labels(), share.get_legend_handles_labels()
        order.legend(lines[0] + more[0], lines[1] + more[1], loc="upper left", fontsize=7)
        order.set_title(f"the particles' order ({settings.get('particles', '?')}): how far it has decayed", fontsize=9)
        order.set_xlabel("simulated time (s)")
    else:
        ax.set_xlabel("simulated time (s)")
    case = settings.get("case", "dam-collapse")
    title = f"{case}: the front against time"
    if settings:
        material = (f"c = {settings['sound_speed']:g} m/s, η = {settings['viscosity']:g} Pa s" if settings.get("sound_speed") is not None
                    else f"E = {settings.get('young', 0):g} Pa, ν = {settings.get('poisson', 0):g}")
        title += (f"\n{settings.get('mesh', '?')}, {settings.get('ordering', '?')} grid, "
                  f"{summary.get('counts', {}).get('particles', '?')} particles, {material}")
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, os.path.join(directory, "front.png"), identify([csv_path, json_path]))
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
