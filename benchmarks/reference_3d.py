"""Converged 3D references for the pressed-taxel voltage (1 N, linear silicone):
Richardson extrapolation over nested uniform refinements of a coarse quarter
model (model.symmetry = "quarter", fem.symmetry; TaggedMesh.refined keeps the
named facets of tetrahedral meshes, so the meshes are nested).

For each case: the voltages of 3 levels (each refinement halves every size, 8x
the elements), the observed order p = log2(d1 / d2), and the extrapolated value
v2 + (v2 - v1) / (2^p - 1). Several coarse meshes per case (one and two elements
through the piezo), so the spread of the extrapolations shows how far the reference
itself can be trusted; the reference is their mean (one chain for the 3x3 array: a
finer coarse mesh's third level does not fit in 10 GB). Writes docs/reference_3d.json
(read by benchmarks/taxel_3d.py, default_mesh.py --3d, estimator_coverage.py --types
and tests/test_error_estimate.py, which take the largest error against any chain).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/reference_3d.py [single] [3x3]
(single: four chains, the finest levels 117k-177k unknowns, peak 4.9 GB; about 20 min
at load average 15 on 2 cores)
"""

from __future__ import annotations

import json
import resource
import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import mesh
from taxel.analyses import solve_static as solve
from taxel.scene import load

OUT = Path(__file__).resolve().parents[1] / "docs" / "reference_3d.json"
CASES = {
    # coarse meshes sized so the finest level (64x the unknowns) stays under 200k unknowns (131k:
    # 3.4 GB): since the 3D edge fix every coarse mesh is refined at the taxel edges (2 mm / 1 mm:
    # 2 224 unknowns, was 1 256), so the old 1.5 mm / 0.6 mm chain (450k at its finest) no longer fits.
    # Chains from one and from two elements through the piezo: the through-thickness error
    # and the in-plane (edge) error have opposite signs, so the chains come from both sides.
    "single": ("thesis-pzt-single-3d", "taxel_0_0", [("2 mm", "1 mm", 1), ("2.5 mm", "1.2 mm", 1),
                                                     ("2 mm", "1 mm", 2), ("3 mm", "1.5 mm", 2)]),
    # one chain, measured before the 3D edge fix and not re-measured: since the fix its 4 mm / 2 mm
    # base has 4 526 unknowns (290k at the third level), and a 6 mm / 3 mm base (3 998, levels
    # -0.85468, -0.83523 V) did not reach its third level in the time the machine allowed
    "3x3": ("thesis-pzt-3x3-3d", "taxel_1_1", [("4 mm", "2 mm", 1)]),
}


def nested(scene, pressed, levels=3):
    tm = mesh(scene)
    rows = []
    for k in range(levels):
        t0 = time.perf_counter()
        sol = solve(scene, tagged_mesh=tm.refined(k) if k else tm)
        rows.append((sol.unknowns, sol.voltages()[pressed], time.perf_counter() - t0))
        print(f"  level {k}: {rows[-1][0]:>7} unknowns  V = {rows[-1][1]:.7f}  {rows[-1][2]:.1f} s  "
              f"peak {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6:.2f} GB", flush=True)
    v = np.array([r[1] for r in rows])
    p = float(np.log2(abs(v[0] - v[1]) / abs(v[1] - v[2])))
    return rows, p, float(v[2] + (v[2] - v[1]) / (2 ** p - 1))


def main():
    out = json.loads(OUT.read_text()) if OUT.exists() else {}
    for case, (name, pressed, bases) in CASES.items():
        if len(sys.argv) > 1 and case not in sys.argv[1:]:
            continue
        fits = []
        for size, piezo, layers in bases:
            scene = load(name).replace(**{"model.symmetry": "quarter", "mesh.size": size, "mesh.piezo_size": piezo,
                                          "mesh.piezo_layers": layers})
            print(f"{case}: coarse mesh {size} / {piezo} at the taxel / {layers} through the piezo", flush=True)
            rows, p, ref = nested(scene, pressed)
            print(f"  observed order {p:.2f}, Richardson {ref:.7f} V", flush=True)
            fits.append(dict(size=size, piezo_size=piezo, piezo_layers=layers, unknowns=[r[0] for r in rows],
                             voltages=[r[1] for r in rows], order=p, reference=ref))
        refs = [f["reference"] for f in fits]
        out[case] = dict(scene=name, pressed=pressed, reference=float(np.mean(refs)),
                         spread=float(np.ptp(refs) / abs(np.mean(refs))), fits=fits)
        print(f"{case}: reference {out[case]['reference']:.7f} V, the extrapolations "
              f"{100 * out[case]['spread']:.3f} % apart", flush=True)
        OUT.write_text(json.dumps(out, indent=1) + "\n")
        print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
