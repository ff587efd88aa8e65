"""The 3D skin (from the surface map) against direct 3D solves, normal and shear.

A 2 x 2 PZT array (thesis-pzt-3x3-3d with array.rows = array.cols = 2, its 1.5 mm /
0.6 mm mesh, open circuit): its surface map (taxel.analyses.surface.surface_map) and skin
(taxel.skin.build); 1 N spread over the top-surface nodes within 1.6 mm of three
off-centre points (a quarter pitch along the diagonal, mid-gap, in the edge margin),
along x, y and z in turn. Each taxel's open-circuit voltage by direct 3D solves
(fem.static.direct_charges, V = -C^-1 Q: not by reciprocity), by the map (its bicubic
spline) and by the skin (its held output: the readout's static gain times its bilinear
W). Errors: the largest difference over the taxels, of that load's own largest |V_FEM|
and of the pressed taxel's peak (1 N pressed by the same nodes on the nearest taxel's
centre). Then the MuJoCo flat probe pressed centrally to 1 N through MujocoSkin (its
footprint's patch) against the 3D FEM's static press by the same probe. Writes
benchmarks/results/skin_3d_accuracy.json.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_3d_accuracy.py
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import taxel
from taxel.analyses.surface.surface_map import build as map_build
from taxel.skin.build import build

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from skin_3d_loads import POINTS, NodalLoads, mujoco_probe  # noqa: E402


def main():
    scene = taxel.load("thesis-pzt-3x3-3d").replace(**{"array.rows": 2, "array.cols": 2, "readout.circuit": "open",
                                                        "load.taxel": [1, 1]})
    m = map_build(scene)
    sk = build(scene, dt=1e-3, checks=0, surface_map=m)
    loads = NodalLoads(scene, m, sk)
    rows = []
    print("| point | load | skin vs FEM | map vs FEM | skin vs map | load's peak | of the pressed taxel's peak |")
    print("|---|---|---|---|---|---|---|")
    for where, at in POINTS.items():
        c = at(sk.pitch, sk.taxel_width)
        ref = loads.pressed_peak(c)
        for k in range(3):
            v, vm, V = loads.voltages(c, k)
            pk = np.abs(V).max()
            big = np.abs(V) > 0.01 * ref
            row = {"point": where, "load": "xyz"[k], "skin_fem": float(np.abs(v - V).max() / pk),
                   "map_fem": float(np.abs(vm - V).max() / pk), "skin_map": float(np.abs(v - vm).max() / pk),
                   "peak_V": float(pk), "skin_fem_of_pressed_peak": float(np.abs(v - V).max() / ref),
                   "signs_agree": bool(np.all(np.sign(v[big]) == np.sign(V[big])))}
            rows.append(row)
            print(f"| {where} | {'xyz'[k]} | {100 * row['skin_fem']:.2f} % | {100 * row['map_fem']:.2f} % | "
                  f"{100 * row['skin_map']:.2f} % | {pk:.3g} V | {100 * row['skin_fem_of_pressed_peak']:.2f} % |")
    probe = mujoco_probe(scene, sk)
    print(f"MuJoCo flat probe (2 mm), 1 N centred on taxel (1, 1): skin {probe['skin_V_per_N']:.4g} V/N, 3D FEM press "
          f"{probe['fem_V_per_N']:.4g} V/N ({100 * probe['error']:+.2f} %); its 4 rim contacts as points "
          f"{probe['rim_points_V_per_N']:.4g} V/N")
    out = Path(__file__).parent / "results" / "skin_3d_accuracy.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps({"rows": rows, "influence_error": sk.influence_error, "mujoco_probe": probe,
                               "map_info": m.info}, indent=1, default=str))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
