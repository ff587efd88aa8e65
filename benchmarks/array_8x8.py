"""An 8 x 8 PZT array in 3D (robot-skin size, 64 floating electrodes): unknowns,
peak memory, time, the pressed taxels' voltages and the 64 x 64 capacitance matrix.

The thesis taxel (4 mm PZT, 0.127 mm, 3 mm gap, 1 mm Ecoflex above and below,
3 mm margin: a 59 mm square) pressed by a 2 mm radius flat indenter (1 N,
uniform pressure) centred between the four middle taxels, so the scene is
symmetric about x = 0 and y = 0 and model.symmetry = "auto" solves a quarter
(16 taxels, four symmetry classes for the full capacitance matrix, fem.static).
The mesh is `thesis-pzt-3x3-3d`'s at 2 mm, 0.8 mm at the taxels, two elements
through the PZT (MESH: its error on the 3x3 array against benchmarks/reference_3d.py's
value is stated there).

Writes docs/capacitance_8x8.csv (pF, rows and columns taxel_r_c) and prints the
numbers. Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/array_8x8.py [--full]
[--n 16] [--cap-gb 12] [--estimate-only]
(--full solves the whole array instead, for the comparison; it needs about 4x the memory;
--n 16: the 16 x 16 array (256 electrodes, 123 mm square, the indenter again between the
middle four). Before meshing, the tool's own estimate of the unknowns and the solve's
memory (taxel.meshing.cost.solve_cost) is printed, and the run stops there when it exceeds
--cap-gb (default 12: the machine is shared).)
"""

from __future__ import annotations

import csv
import logging
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import solve_static
from taxel.scene import load
from taxel.schema import electrode_name

OUT = Path(__file__).resolve().parents[1] / "docs" / "capacitance_8x8.csv"


# The mesh: thesis-pzt-3x3-3d's with 2 mm far and 0.8 mm at the taxels (two elements
# through the PZT). On the 3x3 array's pressed taxel against docs/reference_3d.json's
# four-chain 3x3 reference (-0.82234 V, +-0.46 %; benchmarks/array_mesh_error.py prints
# these, the quarter model): +0.067 % at 32 926 unknowns, against +0.239 % at 51 018 for
# the example's 1.5 mm / 0.6 mm; one element through the PZT -1.49 % and -1.17 %,
# 2.5 mm / 1 mm +4.25 %.
MESH = {"mesh.size": "2 mm", "mesh.piezo_size": "0.8 mm", "mesh.piezo_layers": 2}


def scene(symmetry="auto", n=8):
    return load("thesis-pzt-3x3-3d").replace(**{
        **MESH, "array.rows": n, "array.cols": n, "model.symmetry": symmetry,
        "load.kind": "probe", "load.radius": "2 mm", "load.taxel": [n // 2, n // 2 - 1],
        "load.offset": ["3.5 mm", "3.5 mm"]})


def arg(name, default):
    return type(default)(sys.argv[sys.argv.index(name) + 1]) if name in sys.argv else default


class Phases(logging.Handler):
    """Prints each step the solver logs (assembly, PARDISO's analysis and factorizations)
    with the wall and CPU time since the start, the resident memory and its peak."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.t0, self.c0 = time.perf_counter(), time.process_time()

    def emit(self, record):
        from taxel.fem.linalg import resident_memory
        rss = resident_memory()
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
        print(f"  [{time.perf_counter() - self.t0:7.1f} s wall, {time.process_time() - self.c0:7.1f} s CPU, "
              f"RSS {rss / 1e9:.2f} GB, peak {peak:.2f} GB, load {os.getloadavg()[0]:.1f}] {record.getMessage()}",
              flush=True)


def main():
    full = "--full" in sys.argv
    n, cap = arg("--n", 8), arg("--cap-gb", 12.0)
    from taxel.fem import linalg
    linalg.set_memory_cap(cap * 1e9)         # a factorization that would not fit goes out of core
    for name in ("taxel.fem.assembly", "taxel.fem.linalg"):
        logging.getLogger(name).setLevel(logging.INFO)
        logging.getLogger(name).addHandler(Phases())
    sc = scene("full" if full else "auto", n)
    from taxel.analyses import check, layout
    from taxel.meshing.cost import estimated_unknowns, solve_cost
    lay = layout(sc, check(sc))
    krylov = sc.model.silicone == "linear" and linalg.resolve("auto", estimated_unknowns(lay, sc.mesh.order),
                                                                iterative=True, dim=3) == "krylov"
    c = solve_cost(lay, sc.mesh.order, krylov)
    unknowns, need = c.unknowns, c.bytes
    print(f"{n}x{n} array: the tool's estimate before meshing: {unknowns:.3g} unknowns, {need / 1e9:.3g} GB "
          f"for the solve (cap {cap:g} GB)", flush=True)
    if need > cap * 1e9 or "--estimate-only" in sys.argv:
        print("not solved" + (f": over the {cap:g} GB cap" if need > cap * 1e9 else ""))
        return
    t0, c0 = time.perf_counter(), time.process_time()
    res = solve_static(sc)
    total, cpu = time.perf_counter() - t0, time.process_time() - c0
    sol = res.solution
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    lay = sol.mesh.layout
    print(f"{n}x{n} 3D array, {'full' if full else 'symmetric'} model (cut planes {lay.planes}), "
          f"{len(lay.taxels)} taxels modelled, {sum(k.startswith('taxel_') for k in sol.electrodes)} reported")
    print(f"unknowns {sol.unknowns}, solver {sol.solver}, residual {sol.residual:.1e}")
    print("time: " + ", ".join(f"{k} {v:.1f} s" for k, v in res.times.items()) + f" (total {total:.1f} s wall, {cpu:.1f} s CPU; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    print(f"peak memory (RSS) {peak:.2f} GB")
    v = np.array([[sol.electrodes[electrode_name(r, c)].voltage for c in range(n)] for r in range(n)])
    print(f"open-circuit voltages (mV), rows 0-{n - 1}:")
    for r in range(n):
        print("  " + " ".join(f"{1e3 * x:8.2f}" for x in v[r]))
    names, C = sol.capacitance_names, sol.capacitance_matrix
    taxels = [k for k in names if k.startswith("taxel_")]
    at = [names.index(k) for k in taxels]
    Ct = C[np.ix_(at, at)]
    off = Ct[~np.eye(len(Ct), dtype=bool)]
    print(f"capacitance matrix {Ct.shape[0]} x {Ct.shape[1]}: diagonal {1e12 * Ct.diagonal().min():.2f} to "
          f"{1e12 * Ct.diagonal().max():.2f} pF, largest mutual {1e12 * np.abs(off).max():.3g} pF, "
          f"symmetric to {np.abs(Ct - Ct.T).max() / np.abs(Ct).max():.1e}")
    if not full and n == 8:
        with OUT.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["pF"] + taxels)
            for k, row in zip(taxels, Ct):
                w.writerow([k] + [f"{1e12 * x:.6g}" for x in row])
        print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
