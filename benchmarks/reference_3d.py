"""Converged 3D references for the pressed-taxel voltage (1 N, linear silicone):
Richardson extrapolation over nested uniform refinements of a coarse quarter
model (model.symmetry = "quarter", fem.static; TaggedMesh.refined keeps the
named facets of tetrahedral meshes, so the meshes are nested).

For each case: the voltages of 3 levels (each refinement halves every size, 8x
the elements), the observed order p = log2(d1 / d2), and the extrapolated value
v2 + (v2 - v1) / (2^p - 1). Several coarse meshes per case (one and two elements
through the piezo), so the spread of the extrapolations shows how far the reference
itself can be trusted; the reference is their mean. A chain whose differences change
sign ("monotone": false in the JSON) has no meaningful observed order: Richardson is not
justified there, and its value is kept only because its step is small (the finest level
is then near the limit). Each level's wall and CPU time and the peak memory so far are
kept with the chain. Writes docs/reference_3d.json (read by benchmarks/taxel_3d.py,
default_mesh.py --3d, estimator_coverage.py --types, mesh_grading.py,
cheap_3d_symmetry.py, array_mesh_error.py and tests/test_error_estimate.py, which take
the largest error against any chain).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/reference_3d.py [single] [3x3]
(a case:i,j argument measures only those chains of the case, keeping the others)
(single: four chains, the finest levels 117k-177k unknowns, peak 4.9 GB; about 20 min
at load average 15 on 2 cores. 3x3: four chains, the finest levels 132k-273k unknowns,
peak 6.7 GB; about 10 min of CPU, 20 min wall at load average 4-5)
"""

from __future__ import annotations

import json
import os
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
    # since the 3D edge fix the 4 mm / 2 mm base has 4 526 unknowns (272k at the third level, 6.7 GB);
    # coarser bases keep the third level under 7 GB; 8 mm / 4 mm / 1 gives the pre-fix 4 mm / 2 mm chain's
    # unknowns and voltages (2 226 / 16 916 / 131 838; -0.82154 V)
    "3x3": ("thesis-pzt-3x3-3d", "taxel_1_1", [("4 mm", "2 mm", 1), ("8 mm", "4 mm", 2), ("8 mm", "4 mm", 1),
                                               ("6 mm", "3 mm", 1)]),
}


def nested(scene, pressed, levels=3):
    tm = mesh(scene)
    rows = []
    for k in range(levels):
        t0, c0 = time.perf_counter(), time.process_time()
        sol = solve(scene, tagged_mesh=tm.refined(k) if k else tm)
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
        rows.append((sol.unknowns, sol.voltages()[pressed], time.perf_counter() - t0, time.process_time() - c0, peak))
        print(f"  level {k}: {rows[-1][0]:>7} unknowns  V = {rows[-1][1]:.7f}  {rows[-1][2]:.1f} s wall  "
              f"{rows[-1][3]:.1f} s CPU  peak {peak:.2f} GB  load {os.getloadavg()[0]:.1f}", flush=True)
    v = np.array([r[1] for r in rows])
    p = float(np.log2(abs(v[0] - v[1]) / abs(v[1] - v[2])))
    return rows, p, float(v[2] + (v[2] - v[1]) / (2 ** p - 1))


def monotone(voltages) -> bool:
    """The level-to-level differences keep their sign (Richardson's order is meaningful)."""
    return bool(np.diff(voltages).prod() > 0)


def main():
    """Arguments: case names, or case:i,j to (re)measure only those chains of the case (by their
    index in CASES; the others are kept from docs/reference_3d.json). The file is written after
    every chain, so a chain that finishes is kept if a later one is stopped."""
    picks = dict((a.split(":") + [""])[:2] for a in sys.argv[1:])
    out = json.loads(OUT.read_text()) if OUT.exists() else {}
    for case, (name, pressed, bases) in CASES.items():
        if picks and case not in picks:
            continue
        chosen = [int(i) for i in picks[case].split(",")] if picks.get(case) else range(len(bases))
        kept = {(f["size"], f["piezo_size"], f.get("piezo_layers", 1)): f for f in out.get(case, {}).get("fits", [])}
        for i in chosen:
            size, piezo, layers = bases[i]
            scene = load(name).replace(**{"model.symmetry": "quarter", "mesh.size": size, "mesh.piezo_size": piezo,
                                          "mesh.piezo_layers": layers})
            print(f"{case}: coarse mesh {size} / {piezo} at the taxel / {layers} through the piezo", flush=True)
            rows, p, ref = nested(scene, pressed)
            print(f"  observed order {p:.2f}, Richardson {ref:.7f} V" + ("" if monotone([r[1] for r in rows]) else
                  " (not monotone: the differences change sign, so the order and the extrapolation are not "
                  "justified; the step is small when the finest level is near the limit)"), flush=True)
            kept[(size, piezo, layers)] = dict(
                size=size, piezo_size=piezo, piezo_layers=layers, unknowns=[r[0] for r in rows],
                voltages=[r[1] for r in rows], wall_s=[round(r[2], 1) for r in rows],
                cpu_s=[round(r[3], 1) for r in rows], peak_gb=[round(r[4], 2) for r in rows], order=p, reference=ref)
            # only chains of the current CASES count (a chain measured before a mesh fix is dropped)
            fits = [kept[b] for b in bases if b in kept]
            for f in fits:      # the flag, from each chain's voltages
                f["monotone"] = monotone(f["voltages"])
            refs = [f["reference"] for f in fits]
            out[case] = dict(scene=name, pressed=pressed, reference=float(np.mean(refs)),
                             spread=float(np.ptp(refs) / abs(np.mean(refs))), fits=fits)
            print(f"{case}: reference {out[case]['reference']:.7f} V from {len(fits)} chain(s), the extrapolations "
                  f"{100 * out[case]['spread']:.3f} % apart", flush=True)
            OUT.write_text(json.dumps(out, indent=1) + "\n")
            print(f"wrote {OUT}", flush=True)


if __name__ == "__main__":
    main()
