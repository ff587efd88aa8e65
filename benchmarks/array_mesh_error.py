"""The error of benchmarks/array_8x8.py's mesh (MESH) on the 3x3 array's pressed taxel,
the figure its comment states, against docs/reference_3d.json's "3x3" reference
(benchmarks/reference_3d.py: Richardson over nested refinements of coarse quarter
meshes; the mean of its chains, and the largest error against any chain, as the
error-estimate checks count it).

thesis-pzt-3x3-3d, the quarter model (fem.static), 1 N on the middle taxel, linear
silicone; the pressed taxel's open-circuit voltage at: MESH (2 mm far, 0.8 mm at the
taxels, two elements through the PZT), the example's own mesh (1.5 mm / 0.6 mm, two
through), each with one element through, and 2.5 mm / 1 mm. Prints unknowns, voltage,
the errors, wall and CPU time and the peak memory (RSS) so far.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/array_mesh_error.py
"""

from __future__ import annotations

import json
import os
import resource
import sys
import time
from pathlib import Path

from taxel.analyses import solve_static
from taxel.scene import load

sys.path.insert(0, str(Path(__file__).parent))
from array_8x8 import MESH  # noqa: E402

REFERENCE = Path(__file__).resolve().parents[1] / "docs" / "reference_3d.json"
EXAMPLE = {"mesh.size": "1.5 mm", "mesh.piezo_size": "0.6 mm", "mesh.piezo_layers": 2}
MESHES = [("array_8x8.MESH", MESH),
          ("the example's", EXAMPLE),
          ("array_8x8.MESH, one through", {**MESH, "mesh.piezo_layers": 1}),
          ("the example's, one through", {**EXAMPLE, "mesh.piezo_layers": 1}),
          ("2.5 mm / 1 mm, two through", {"mesh.size": "2.5 mm", "mesh.piezo_size": "1 mm", "mesh.piezo_layers": 2})]


def main():
    ref = json.loads(REFERENCE.read_text())["3x3"]
    chains = [f["reference"] for f in ref["fits"]]
    print(f"3x3 reference {ref['reference']:.6f} V (mean of {len(chains)} chain(s): "
          f"{', '.join(f'{c:.6f}' for c in chains)}; spread {100 * ref['spread']:.2f} %)")
    print(f"{'mesh':<30} {'size / at taxels':>16} {'through':>7} {'unknowns':>8} {'V pressed':>11} "
          f"{'vs mean %':>9} {'vs chains %':>16} {'wall s':>7} {'cpu s':>6} {'peak GB':>7}")
    for label, mesh in MESHES:
        scene = load(ref["scene"]).replace(**{"model.symmetry": "quarter", **mesh})
        t0, c0 = time.perf_counter(), time.process_time()
        res = solve_static(scene)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        v = res.voltages()[ref["pressed"]]
        errs = [100 * (v / c - 1) for c in chains]
        print(f"{label:<30} {mesh['mesh.size'] + ' / ' + mesh['mesh.piezo_size']:>16} {mesh['mesh.piezo_layers']:>7} "
              f"{res.unknowns:>8} {v:>11.6f} {100 * (v / ref['reference'] - 1):>+9.3f} "
              f"{min(errs):>+7.3f}..{max(errs):>+7.3f} {wall:>7.1f} {cpu:>6.1f} "
              f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6:>7.2f}", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
