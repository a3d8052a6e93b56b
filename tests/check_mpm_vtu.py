#!/usr/bin/python3
"""Reads `suite mpm --out=DIR` snapshots back with meshio and checks them against mpm.json.

Usage: check_mpm_vtu.py DIR [OTHER_DIR]
Every particles_*.vtu of DIR: meshio reads it; it has mpm.json's particle count of points, one
vertex cell each, ids that are a permutation of 0..n-1, velocity (n x 3), stress (n x 6),
volume and mass; masses equal, id by id, those of the first snapshot. particles.pvd lists exactly
the snapshots of mpm.json, with their times. With OTHER_DIR: the last snapshots of the two runs
hold the same particles at the same positions, matched by id, to 1e-9 of the largest coordinate.
Exit 0 when all hold, 1 naming the first that does not, 3 when meshio is missing.
"""
import glob
import json
import os
import sys
import xml.etree.ElementTree as ET

try:
    import meshio
    import numpy as np
except ImportError as e:
    print(f"check_mpm_vtu.py: {e.name} is not installed (Debian: python3-meshio)")
    sys.exit(3)


def fail(message):
    print(f"check_mpm_vtu.py: {message}")
    sys.exit(1)


def by_id(mesh):
    """Positions and masses reordered by particle id."""
    order = np.argsort(mesh.point_data["id"].ravel(), kind="stable")
    return mesh.points[order], mesh.point_data["mass"].ravel()[order]


def check_run(directory):
    with open(os.path.join(directory, "mpm.json")) as f:
        doc = json.load(f)
    n = doc["counts"]["particles"]
    files = sorted(glob.glob(os.path.join(directory, "particles_*.vtu")))
    listed = [s["file"] for s in doc["snapshots"]]
    if [os.path.basename(f) for f in files] != listed:
        fail(f"{directory}: the .vtu files {[os.path.basename(f) for f in files]} are not mpm.json's snapshots {listed}")
    first_mass = None
    for path in files:
        name = os.path.basename(path)
        m = meshio.read(path)
        if m.points.shape != (n, 3):
            fail(f"{name}: points of shape {m.points.shape}, not ({n}, 3) as mpm.json's particle count says")
        cells = [(c.type, len(c.data)) for c in m.cells]
        if cells != [("vertex", n)]:
            fail(f"{name}: cells {cells}, not {n} vertices")
        ids = m.point_data["id"].ravel()
        if not np.array_equal(np.sort(ids), np.arange(n)):
            fail(f"{name}: the ids are not a permutation of 0..{n - 1}")
        shapes = {"velocity": (n, 3), "stress": (n, 6), "volume": (n,), "mass": (n,)}
        for field, shape in shapes.items():
            got = m.point_data[field].shape if field in m.point_data else None
            if got is None or got[0] != shape[0] or int(np.prod(got)) != int(np.prod(shape)):
                fail(f"{name}: point data {field} has shape {got}, not {shape}")
            if not np.all(np.isfinite(m.point_data[field])):
                fail(f"{name}: point data {field} is not all finite")
        _, mass = by_id(m)
        if first_mass is None:
            first_mass = mass
        elif not np.array_equal(mass, first_mass):
            fail(f"{name}: the particles' masses differ from the first snapshot's")
    root = ET.parse(os.path.join(directory, "particles.pvd")).getroot()
    sets = [(d.get("file"), float(d.get("timestep"))) for d in root.iter("DataSet")]
    expected = [(s["file"], s["time"]) for s in doc["snapshots"]]
    if sets != expected:
        fail(f"{directory}/particles.pvd lists {sets}, mpm.json {expected}")
    return files


def main(argv):
    if len(argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    files = check_run(argv[1])
    if len(argv) == 3:
        other = check_run(argv[2])
        a, _ = by_id(meshio.read(files[-1]))
        b, _ = by_id(meshio.read(other[-1]))
        if a.shape != b.shape:
            fail(f"the last snapshots hold {len(a)} and {len(b)} particles")
        worst = float(np.max(np.abs(a - b)))
        scale = float(np.max(np.abs(a)))
        if not worst <= 1e-9 * scale:
            fail(f"the last snapshots' positions differ by up to {worst:.3g} (at most {1e-9 * scale:.3g} allowed)")
        print(f"check_mpm_vtu.py: {len(files)} + {len(other)} snapshots read back; the last agree to {worst:.3g}")
        return 0
    print(f"check_mpm_vtu.py: {len(files)} snapshots read back and agree with mpm.json")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
