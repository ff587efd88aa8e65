"""The 3D skin (from the surface map) against direct 3D solves, normal and shear.

A 2 x 2 PZT array (thesis-pzt-3x3-3d with array.rows = array.cols = 2, its 1.5 mm /
0.6 mm mesh, open circuit): its surface map (taxel.analyses.surface_map) and skin
(taxel.skin.build); 1 N spread over the top-surface nodes within 1.6 mm of three
off-centre points (a quarter pitch along the diagonal, mid-gap, in the edge margin),
along x, y and z in turn. Each taxel's open-circuit voltage by direct 3D solves
(fem.static.direct_charges, V = -C^-1 Q: not by reciprocity), by the map (its bicubic
spline) and by the skin (its held output: the readout's static gain times its bilinear
W). Errors: the largest difference over the taxels, of that load's own largest |V_FEM|
and of the pressed taxel's peak (1 N pressed by the same nodes on the nearest taxel's
centre). Writes benchmarks/results/skin_3d_accuracy.json.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_3d_accuracy.py
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import taxel
from taxel.analyses.model.problem import problem
from taxel.analyses.surface_map import build as map_build, map_scene
from taxel.fem import assembly, static
from taxel.schema import electrode_name
from taxel.skin.build import build
from taxel.skin.runtime import SkinRuntime


def main():
    scene = taxel.load("thesis-pzt-3x3-3d").replace(**{"array.rows": 2, "array.cols": 2, "readout.circuit": "open",
                                                        "load.taxel": [1, 1]})
    m = map_build(scene)
    sk = build(scene, dt=1e-3, checks=0, surface_map=m)
    p = sk.pitch
    sy = assembly.assemble(problem(map_scene(scene.replace(**{"model.symmetry": "full"}))))
    driven = [k for k, s in sy.electrodes.states.items() if s != "reference"]
    ub = next(iter(sy.ubases.values()))
    top = np.unique(sy.tm.mesh.facets[:, sy.tm.facets["top"]])
    xy = sy.tm.mesh.p[:2, top].T
    shift = np.array([(sk.cols - 1) * p / 2, (sk.rows - 1) * p / 2])          # map frame -> skin frame
    gain = float((sk.Cd @ np.linalg.solve(np.eye(len(sk.Ad)) - sk.Ad, sk.Bd) + sk.Dd)[0, 0])
    rt = SkinRuntime(sk)
    order = [driven.index(electrode_name(sk.rows - 1 - r, c)) for r in range(sk.rows) for c in range(sk.cols)]
    mo = [m.index(driven[i]) for i in order]
    Cmat = m.capacitance[np.ix_(mo, mo)]

    def three(c, k):
        nodes = top[np.hypot(*(xy - (np.asarray(c) - shift)).T) <= 1.6e-3]
        pts = sy.tm.mesh.p[:2, nodes].T
        F = np.zeros((sy.A.shape[0], 1))
        F[[ub.nodal_dofs[k, n] for n in nodes], 0] = 1.0 / len(nodes)
        V = -np.linalg.solve(Cmat, static.direct_charges(sy, F, driven)[:, 0][order])
        f = np.zeros((len(nodes), 3))
        f[:, k] = 1.0 / len(nodes)
        return gain * rt.loads(pts + shift, f).ravel(), m.voltage(pts, f).sum(axis=0)[mo], V

    rows = []
    print("| point | load | skin vs FEM | map vs FEM | skin vs map | load's peak | of the pressed taxel's peak |")
    print("|---|---|---|---|---|---|---|")
    for where, c in {"diagonal": (0.25 * p, 0.25 * p), "gap": (0.5 * p, 0.0),
                     "edge": (-(sk.taxel_width / 2 + 1.5e-3), 0.0)}.items():
        near = np.round(np.clip(np.array(c) / p, 0, [sk.cols - 1, sk.rows - 1])) * p
        ref = np.abs(three(near, 2)[2]).max()
        for k in range(3):
            v, vm, V = three(c, k)
            pk = np.abs(V).max()
            row = {"point": where, "load": "xyz"[k], "skin_fem": float(np.abs(v - V).max() / pk),
                   "map_fem": float(np.abs(vm - V).max() / pk), "skin_map": float(np.abs(v - vm).max() / pk),
                   "peak_V": float(pk), "skin_fem_of_pressed_peak": float(np.abs(v - V).max() / ref),
                   "signs_agree": bool(np.all(np.sign(v[np.abs(V) > 0.01 * ref]) == np.sign(V[np.abs(V) > 0.01 * ref])))}
            rows.append(row)
            print(f"| {where} | {'xyz'[k]} | {100 * row['skin_fem']:.2f} % | {100 * row['map_fem']:.2f} % | "
                  f"{100 * row['skin_map']:.2f} % | {pk:.3g} V | {100 * row['skin_fem_of_pressed_peak']:.2f} % |")
    out = Path(__file__).parent / "results" / "skin_3d_accuracy.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps({"rows": rows, "influence_error": sk.influence_error, "map_info": m.info}, indent=1,
                              default=str))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
