"""Why the frictionless 3D press stops short of 1 N: the same press with one thing changed
at a time, in one run.

The thesis taxel pressed by the rig's probe (thesis-pzt-probe-3d: a 4 mm flat punch,
0.2 mm edge radius, Yeoh silicone), friction = "frictionless", force control to 1 N in one
target. The default press mesh (P2 displacement / P1 pressure tetrahedra, a quarter) is
benchmarks/press_3d.py --frictionless's row; here one thing is changed at a time:

- the full model (model.symmetry = "full"): is the stop an artefact of the symmetry planes?
- a 4.5 mm taxel: the 4 mm square piezo's edge lies under the punch's rim on the symmetry
  planes (the axisymmetric model's equal-area disk, r = 2.26 mm, does not); is the
  silicone pinched between the two?
- MINI tetrahedra (mesh.order = 1: P1 + bubble / P1), at the default sizes and halved,
  sticking and frictionless: does a lower-order element pass, and at what accuracy (the
  sticking press against its nested reference, docs/press_3d_reference.json)?

The rows in docs/guide/silicone-and-contact.md were measured before 2026-11-25 (the rim a plan
curve, the edge midpoints as contact points); benchmarks/press_3d.py --frictionless has the
default and sizes x 2 rows since.

First the silicone's displacement unknowns per pressure unknown on each model's probe mesh
(--unknowns: only that), then per row the force reached, the travel, V/F at the last state and
the stop's cause.
Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/frictionless_3d.py [--unknowns]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from press_3d import OUT, layout, run, stop  # noqa: E402

from taxel.analyses import check, checked_layout, problem  # noqa: E402
from taxel.fem.assembly import assemble
from taxel.meshing.build import build  # noqa: E402
from taxel.scene import load  # noqa: E402


def scene(friction="frictionless", **edit):
    return load("thesis-pzt-probe-3d").replace(**{"load.friction": friction, **edit})


ROWS = {      # the default P2 quarter: benchmarks/press_3d.py --frictionless
    "MINI, quarter, sticking": (scene("sticking", **{"mesh.order": 1}), 1.0),
    "MINI, quarter": (scene(**{"mesh.order": 1}), 1.0),
    "MINI, quarter, sizes / 2, sticking": (scene("sticking", **{"mesh.order": 1}), 2.0),
    "MINI, quarter, sizes / 2": (scene(**{"mesh.order": 1}), 2.0),
    "P2, quarter, 4.5 mm taxel": (scene(**{"array.taxel_width": 4.5e-3}), 1.0),
    "P2, full model": (scene(**{"model.symmetry": "full"}), 1.0),
}


def unknowns_per_pressure():
    """The silicone's displacement unknowns per pressure unknown on each model's probe mesh
    (the examples' own meshes; 3D: the default press mesh): how many displacement modes the
    P1 pressures leave the volume free in."""
    print("| mesh | silicone displacement unknowns | pressure unknowns | ratio |\n|---|---|---|---|")
    for name in ("thesis-pzt-probe-3d", "thesis-pzt-probe-axisymmetric", "thesis-pzt-probe-2d"):
        sc = load(name).replace(**{"load.friction": "frictionless"})
        sy = assemble(problem(sc, tagged_mesh=build(checked_layout(sc, check(sc)))))
        nu = len(np.unique(sy.ubases["silicone"].element_dofs))
        npr = len(np.unique(sy.pbases["silicone"].element_dofs))
        print(f"| {name} | {nu} | {npr} | {nu / npr:.1f} |", flush=True)


def main():
    unknowns_per_pressure()
    if "--unknowns" in sys.argv:
        return
    ref = json.loads(OUT.read_text())["VF"]
    print(f"sticking reference (P2, nested meshes): V/F {ref:.5f} V/N")
    print("| press | unknowns | force reached (N) | travel (mm) | V/F (V/N) | sticking: error | stop | CPU s |\n"
          "|---|---|---|---|---|---|---|---|")
    for name, (sc, k) in ROWS.items():
        r = run(sc, layout(sc, k))
        F, d, vf, cause = stop(r)
        err = f"{100 * (vf / ref - 1):+.1f} %" if "sticking" in name and F == 1.0 else ""
        print(f"| {name} | {r['n']} | {F:.3f} | {1e3 * d:.3f} | {vf:.4f} | {err} | {cause} | {r['cpu']:.0f} |",
              flush=True)


if __name__ == "__main__":
    main()
