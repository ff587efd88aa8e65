"""An 8 x 8 PZT array in 3D (robot-skin size, 64 floating electrodes): unknowns,
peak memory, time, the pressed taxels' voltages and the 64 x 64 capacitance matrix.

The thesis taxel (4 mm PZT, 0.127 mm, 3 mm gap, 1 mm Ecoflex above and below,
3 mm margin: a 59 mm square) pressed by a 2 mm radius flat indenter (1 N,
uniform pressure) centred between the four middle taxels, so the scene is
symmetric about x = 0 and y = 0 and model.symmetry = "auto" solves a quarter
(16 taxels, four symmetry classes for the full capacitance matrix, fem.symmetry).
The mesh is the one of `thesis-pzt-3x3-3d` (1.5 mm, 0.6 mm at the taxels, two
elements through the PZT); that mesh's error on the 3x3 array is measured by
benchmarks/taxel_3d.py against benchmarks/reference_3d.py.

Writes docs/capacitance_8x8.csv (pF, rows and columns taxel_r_c) and prints the
numbers. Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/array_8x8.py [--full]
(--full solves the whole array instead, for the comparison; it needs about 4x the memory).
"""

from __future__ import annotations

import csv
import resource
import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import solve_static
from taxel.scene import load
from taxel.schema import electrode_name

OUT = Path(__file__).resolve().parents[1] / "docs" / "capacitance_8x8.csv"


def scene(symmetry="auto"):
    return load("thesis-pzt-3x3-3d").replace(**{
        "array.rows": 8, "array.cols": 8, "model.symmetry": symmetry,
        "load.kind": "indenter", "load.radius": "2 mm", "load.taxel": [4, 3], "load.offset": ["3.5 mm", "3.5 mm"]})


def main():
    full = "--full" in sys.argv
    t0 = time.perf_counter()
    res = solve_static(scene("full" if full else "auto"))
    total = time.perf_counter() - t0
    sol = res.solution
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    lay = sol.mesh.layout
    print(f"8x8 3D array, {'full' if full else 'symmetric'} model (cut planes {lay.planes}), "
          f"{len(lay.taxels)} taxels modelled, {sum(k.startswith('taxel_') for k in sol.electrodes)} reported")
    print(f"unknowns {sol.unknowns}, solver {sol.solver}, residual {sol.residual:.1e}")
    print("time: " + ", ".join(f"{k} {v:.1f} s" for k, v in res.times.items()) + f" (total {total:.1f} s)")
    print(f"peak memory (RSS) {peak:.2f} GB")
    v = np.array([[sol.electrodes[electrode_name(r, c)].voltage for c in range(8)] for r in range(8)])
    print("open-circuit voltages (mV), rows 0-7:")
    for r in range(8):
        print("  " + " ".join(f"{1e3 * x:8.2f}" for x in v[r]))
    names, C = sol.capacitance_names, sol.capacitance_matrix
    taxels = [k for k in names if k.startswith("taxel_")]
    at = [names.index(k) for k in taxels]
    Ct = C[np.ix_(at, at)]
    off = Ct[~np.eye(len(Ct), dtype=bool)]
    print(f"capacitance matrix {Ct.shape[0]} x {Ct.shape[1]}: diagonal {1e12 * Ct.diagonal().min():.2f} to "
          f"{1e12 * Ct.diagonal().max():.2f} pF, largest mutual {1e12 * np.abs(off).max():.3g} pF, "
          f"symmetric to {np.abs(Ct - Ct.T).max() / np.abs(Ct).max():.1e}")
    if not full:
        with OUT.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["pF"] + taxels)
            for k, row in zip(taxels, Ct):
                w.writerow([k] + [f"{1e12 * x:.6g}" for x in row])
        print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
