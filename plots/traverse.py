#!/usr/bin/env python3
"""PNG snapshots of a loop over a mesh, from the files `./suite traverse --out=DIR` wrote.

Usage: python3 plots/traverse.py DIR

For every .vtu listed in DIR/summary.json, writes DIR/ORDERING-tT-PPP.png after PPP = 0, 20, ...,
100 % of the loop: with one thread the visited elements are coloured by the order of the visit;
with several, by the thread that owns them, each thread having gone through PPP % of its own
block (the static split: all threads advance together). Elements not yet visited are grey.
2D meshes are drawn as filled triangles; 3D meshes as the centroids of their tetrahedra.
Exit status: 0, 2 for bad usage, 3 when matplotlib or numpy is missing.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import save_figure  # noqa: E402
import xml.etree.ElementTree as ET

PERCENTS = (0, 20, 40, 60, 80, 100)
GREY = (0.86, 0.86, 0.86, 1.0)


def read_vtu(path):
    """Points (n x 3), connectivity (cells x corners) and the cell data arrays of an ASCII .vtu."""
    import numpy as np

    root = ET.parse(path).getroot()
    piece = root.find("UnstructuredGrid/Piece")
    points = np.fromstring(piece.find("Points/DataArray").text, sep=" ").reshape(-1, 3)
    cells = {a.get("Name"): a.text for a in piece.find("Cells").findall("DataArray")}
    offsets = np.fromstring(cells["offsets"], sep=" ", dtype=np.int64)
    corners = int(offsets[0])
    conn = np.fromstring(cells["connectivity"], sep=" ", dtype=np.int64).reshape(-1, corners)
    data = {a.get("Name"): np.fromstring(a.text, sep=" ", dtype=np.int64) for a in piece.find("CellData").findall("DataArray")}
    return points, conn, data


def snapshots(directory, ordering, threads, vtu):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import PolyCollection

    points, conn, data = read_vtu(os.path.join(directory, vtu))
    visit, owner, step = data["visit"], data["thread"], data["step"]
    n = len(visit)
    block = np.bincount(owner, minlength=threads)[owner]  # each element's thread's block size
    if threads == 1:
        base = plt.get_cmap("viridis")(visit / max(n - 1, 1))
    else:
        cmap = plt.get_cmap("tab10" if threads <= 10 else "hsv")
        base = cmap(owner % 10 if threads <= 10 else owner / threads)
    two_d = conn.shape[1] == 3
    fig = plt.figure(figsize=(5, 5), dpi=100)
    if two_d:
        ax = fig.add_subplot()
        polys = PolyCollection(points[conn][:, :, :2], edgecolors="white" if n <= 5000 else "none", linewidths=0.2)
        ax.add_collection(polys)
        ax.set_xlim(points[:, 0].min(), points[:, 0].max())
        ax.set_ylim(points[:, 1].min(), points[:, 1].max())
        ax.set_aspect("equal")
        ax.set_axis_off()
    else:
        ax = fig.add_subplot(projection="3d")
        centroids = points[conn].mean(axis=1)
    written = []
    for pct in PERCENTS:
        done = step < np.ceil(block * pct / 100.0)
        colours = np.where(done[:, None], base, np.array(GREY))
        if two_d:
            polys.set_facecolors(colours)
        else:
            ax.cla()
            ax.scatter(centroids[~done, 0], centroids[~done, 1], centroids[~done, 2], s=1, c=[GREY], alpha=0.15)
            ax.scatter(centroids[done, 0], centroids[done, 1], centroids[done, 2], s=3, c=colours[done])
            ax.set_axis_off()
        label = "1 thread, colour: visit order" if threads == 1 else f"{threads} threads, colour: thread"
        ax.set_title(f"{ordering}: {pct} % of the loop ({label})", fontsize=9)
        name = f"{ordering}-t{threads}-{pct:03d}.png"
        save_figure(fig, os.path.join(directory, name))
        written.append(name)
    plt.close(fig)
    return written


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: traverse.py DIR (a directory written by ./suite traverse)", file=sys.stderr)
        return 2
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as e:
        print(f"matplotlib or numpy is missing for {sys.executable} ({e.name}): install python3-matplotlib", file=sys.stderr)
        return 3
    directory = argv[1]
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    for entry in summary["orderings"]:
        for t in entry["threads"]:
            snapshots(directory, entry["ordering"], t["threads"], t["vtu"])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
