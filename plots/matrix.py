#!/usr/bin/env python3
"""Spy plots of the matrix under each ordering, from DIR/matrix.json (`./suite matrix --out=DIR`).

Usage: python3 plots/matrix.py DIR

Writes DIR/spy-ORDERING.png per ordering and DIR/spy.png with all of them side by side. A matrix
of a million rows has more nonzeros than a figure has pixels, so the suite bins it: each cell of
the bins x bins grid is shaded by the share of its entries that are nonzero (log scale), white
where it has none. Under each plot: bandwidth, the Cholesky factor's nonzeros and the SpMV time.
Exit status: 0, 2 for bad usage, 3 when matplotlib or numpy is missing.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from safe_output import identify, save_figure  # noqa: E402


def caption(o, nnz):
    ch = o["cholesky"]
    fill = f"nnz(L) {ch['factor_nonzeros']:.3g} ({ch['factor_nonzeros'] / nnz:.1f}x A)"
    spmv = f"SpMV {1e3 * o['spmv']['seconds']['median']:.2f} ms"
    return f"bandwidth {o['bandwidth']}\n{fill}\n{spmv}"


def draw(ax, o, rows, nnz):
    import numpy as np
    from matplotlib.colors import LogNorm

    bins = o["spy"]["bins"]
    grid = np.array(o["spy"]["counts"], dtype=float).reshape(bins, bins)
    # Entries a cell covers: (rows / bins)^2, so the shade is a density comparable across orderings.
    density = grid / (rows / bins) ** 2
    density[grid == 0] = np.nan
    cmap = __import__("matplotlib").colormaps["viridis_r"].copy()
    cmap.set_bad("white")
    ax.imshow(density, cmap=cmap, norm=LogNorm(vmin=max(np.nanmin(density), 1e-9), vmax=1), extent=(0, rows, rows, 0), interpolation="nearest")
    ax.set_title(o["ordering"], fontsize=11)
    ax.set_xlabel(caption(o, nnz), fontsize=8)
    from matplotlib.ticker import FuncFormatter, MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):  # three ticks, in thousands: row numbers of six digits overlap
        axis.set_major_locator(MaxNLocator(3))
        axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / 1000:g}k" if rows >= 10000 else f"{v:g}"))
    ax.tick_params(labelsize=7)


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    directory = argv[1]
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy  # noqa: F401
    except ImportError as e:
        print(f"matrix.py: {e.name} is not installed (Debian: python3-matplotlib python3-numpy)", file=sys.stderr)
        return 3
    source = os.path.join(directory, "matrix.json")
    try:
        with open(source) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        print(f"matrix.py: cannot read {source}: {e}", file=sys.stderr)
        return 2
    rows, nnz = doc["rows"], doc["nonzeros"]
    title = f"A of {doc['mesh']}: {rows} rows, {nnz} nonzeros"
    for o in doc["orderings"]:
        fig, ax = plt.subplots(figsize=(4.2, 4.9))
        draw(ax, o, rows, nnz)
        fig.suptitle(f"A of {os.path.basename(doc['mesh'])}\n{rows} rows, {nnz} nonzeros", fontsize=8)
        fig.tight_layout()
        save_figure(fig, os.path.join(directory, f"spy-{o['ordering']}.png"), inputs=identify([source]), dpi=150)
        plt.close(fig)
    n = len(doc["orderings"])
    fig, axes = plt.subplots(1, n, figsize=(3.0 * n, 4.0), squeeze=False)
    for ax, o in zip(axes[0], doc["orderings"]):
        draw(ax, o, rows, nnz)
    fig.suptitle(title + " — darker: denser; white: no nonzero", fontsize=10)
    fig.tight_layout()
    save_figure(fig, os.path.join(directory, "spy.png"), inputs=identify([source]), dpi=130)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
