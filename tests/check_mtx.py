#!/usr/bin/python3
"""Reads `suite matrix --export=mtx` files back with SciPy and checks them against matrix.json.

Usage: check_mtx.py DIR ORDERING...   (DIR holds matrix.json and natural.mtx)
For each ORDERING.mtx: SciPy's Matrix Market reader takes it; it is square, symmetric, has
matrix.json's nonzeros and the ordering's bandwidth; and it is the natural-order matrix
renumbered: the same multiset of values, the same sorted row sums, the same Frobenius norm.
Exit 0 when all hold, 1 naming the first that does not, 3 when SciPy is missing.
"""
import json
import os
import sys

try:
    import numpy as np
    import scipy.io
except ImportError as e:
    print(f"check_mtx.py: {e.name} is not installed (Debian: python3-scipy)")
    sys.exit(3)

directory, names = sys.argv[1], sys.argv[2:]
with open(os.path.join(directory, "matrix.json")) as f:
    doc = json.load(f)
by_name = {o["ordering"]: o for o in doc["orderings"]}
base = scipy.io.mmread(os.path.join(directory, "natural.mtx")).tocsr()
base_values = np.sort(base.data)
base_rows = np.sort(np.asarray(base.sum(axis=1)).ravel())
for name in names:
    a = scipy.io.mmread(os.path.join(directory, name + ".mtx")).tocsr()
    coo = a.tocoo()
    checks = {
        "square with matrix.json's rows": a.shape == (doc["rows"], doc["rows"]),
        "matrix.json's nonzeros": a.nnz == doc["nonzeros"],
        "symmetric": abs(a - a.T).max() == 0,
        "the ordering's bandwidth": int(np.abs(coo.row - coo.col).max()) == by_name[name]["bandwidth"],
        "the natural matrix's values": np.array_equal(np.sort(a.data), base_values),
        "the natural matrix's row sums": np.allclose(np.sort(np.asarray(a.sum(axis=1)).ravel()), base_rows, rtol=1e-12, atol=1e-12),
    }
    for what, ok in checks.items():
        if not ok:
            print(f"check_mtx.py: {name}.mtx does not have {what}")
            sys.exit(1)
print(f"check_mtx.py: {', '.join(names)} read back and agree")
